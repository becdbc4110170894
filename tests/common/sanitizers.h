// sanitizers.h — which sanitizer this build runs under, the same way for GCC (__SANITIZE_*__) and
// clang (__has_feature): PNB_ASAN, PNB_TSAN. Tests whose bounds or signals a sanitizer changes
// branch on these.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define PNB_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PNB_ASAN 1
#endif
#endif

#if defined(__SANITIZE_THREAD__)
#define PNB_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define PNB_TSAN 1
#endif
#endif
