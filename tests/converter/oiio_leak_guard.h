// oiio_leak_guard.h — PNB_IGNORE_OIIO_LEAKS for tests that decode corrupt images on purpose.
// OIIO 2.4's PNG reader longjmps out of libpng's error callback past a std::string of its own,
// leaking it (31 bytes per corrupt PNG). Such a test ignores the allocations of that one call, on
// that thread; leak checking stays on everywhere else.
#pragma once

#include "../common/sanitizers.h"

#if defined(PNB_ASAN)
#include <sanitizer/lsan_interface.h>
#define PNB_IGNORE_OIIO_LEAKS __lsan::ScopedDisabler lsanDisabler
#else
#define PNB_IGNORE_OIIO_LEAKS
#endif
