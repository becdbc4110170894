// gl_debug.h — KHR_debug output routed to stderr; shared by both context kinds.
#pragma once

#include <cstdint>

namespace pnb::player {

// Installs the debug callback on the current context. Errors are always reported; with
// `verbose`, performance and portability messages too.
void installGlDebugOutput(bool verbose);

// GL errors the callback has seen so far in this process (tests: an operation added none).
uint64_t glErrorsReported();

} // namespace pnb::player
