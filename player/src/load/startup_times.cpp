// Time to first frame (pnb_player/startup_times.h): the process's age and the one-line summary.
#include "pnb_player/startup_times.h"

#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace pnb::player {

namespace {

double clockMs(clockid_t clock) {
    timespec ts{};
    clock_gettime(clock, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

} // namespace

double processAgeMs(std::string* source) {
    if (const char* launch = std::getenv("PNB_LAUNCH_TIME_NS"); launch && *launch) {
        char* end = nullptr;
        unsigned long long ns = std::strtoull(launch, &end, 10);
        double age = clockMs(CLOCK_MONOTONIC) - double(ns) * 1e-6;
        if (end && !*end && age >= 0 && age < 3.6e6) {
            if (source) *source = "PNB_LAUNCH_TIME_NS";
            return age;
        }
    }
    // Field 22 of /proc/self/stat, after the parenthesised command name (which may hold spaces).
    std::ifstream in("/proc/self/stat");
    std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    size_t paren = stat.rfind(')');
    long ticks = sysconf(_SC_CLK_TCK);
    if (paren == std::string::npos || ticks <= 0) return -1;
    std::istringstream fields(stat.substr(paren + 2));
    std::string field;
    for (int i = 3; i <= 22 && fields >> field; ++i)
        if (i == 22) {
            double startMs = double(std::strtoull(field.c_str(), nullptr, 10)) * 1e3 / double(ticks);
            if (source) *source = "/proc/self/stat";
            return clockMs(CLOCK_BOOTTIME) - startMs; // starttime counts from boot, as BOOTTIME does
        }
    return -1;
}

std::string startupSummary(const StartupTimes& t) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "time to first frame: %.1f ms = process start %.1f + context %.1f + load %.1f + "
                  "programs %.1f (%u from cache, %u compiled) + warm-up %.1f%s + first frame %.1f (render thread "
                  "%.1f CPU) + other %.1f",
                  t.totalMs, t.processStartMs, t.contextMs, t.loadMs, t.programsMs, t.programs.hits,
                  t.programs.compiled(), t.warmUpMs, t.warmUp ? "" : " (off)", t.firstFrameMs,
                  t.firstFrameThreadCpuMs, t.otherMs);
    return buf;
}

} // namespace pnb::player
