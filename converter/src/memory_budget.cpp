// memory_budget.cpp — the machine's usable memory and the --max-memory argument
// (pnb_converter/memory_budget.h).
#include "pnb_converter/memory_budget.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

namespace pnb::converter {

namespace {

constexpr uint64_t kUnlimited = std::numeric_limits<uint64_t>::max();

// A cgroup limit file: a byte count, or "max" (v2) / a huge page-aligned number (v1) for none.
uint64_t readLimitFile(const std::string& path) {
    std::ifstream in(path);
    std::string text;
    if (!(in >> text) || text.empty() || text == "max") return kUnlimited;
    uint64_t v = 0;
    for (char c : text) {
        if (c < '0' || c > '9' || v > (kUnlimited - 9) / 10) return kUnlimited;
        v = v * 10 + uint64_t(c - '0');
    }
    return v > 0 ? v : kUnlimited;
}

// The memory limit of this process's cgroup, v2 or v1. Inside a container the path named in
// /proc/self/cgroup is often not mounted; the container's own root file is then the limit.
uint64_t cgroupLimit() {
    uint64_t limit = kUnlimited;
    std::ifstream in("/proc/self/cgroup");
    std::string line;
    while (std::getline(in, line)) {
        const size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos) continue;
        const std::string controllers = line.substr(a + 1, b - a - 1), path = line.substr(b + 1);
        const bool v2 = line.compare(0, a, "0") == 0 && controllers.empty();
        const bool v1 = (',' + controllers + ',').find(",memory,") != std::string::npos;
        if (v2) {
            limit = std::min({limit, readLimitFile("/sys/fs/cgroup" + path + "/memory.max"),
                              readLimitFile("/sys/fs/cgroup/memory.max")});
        } else if (v1) {
            const std::string root = "/sys/fs/cgroup/memory";
            limit = std::min({limit, readLimitFile(root + path + "/memory.limit_in_bytes"),
                              readLimitFile(root + "/memory.limit_in_bytes")});
        }
    }
    return limit;
}

} // namespace

uint64_t usableMemoryBytes() {
    uint64_t usable = kUnlimited;
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && pageSize > 0) usable = uint64_t(pages) * uint64_t(pageSize);
    rlimit as{};
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
        usable = std::min<uint64_t>(usable, as.rlim_cur);
    }
    usable = std::min(usable, cgroupLimit());
    // Nothing known (no sysconf, no limits): assume a small machine rather than none at all.
    return usable == kUnlimited ? uint64_t(4) << 30 : usable;
}

uint64_t defaultMemoryBudget() {
    return usableMemoryBytes() / 2;
}

std::optional<uint64_t> parseByteSize(std::string_view text) {
    // The number: digits with an optional fraction ("1.5G").
    size_t i = 0;
    double value = 0;
    bool digits = false;
    for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i, digits = true) {
        value = value * 10 + (text[i] - '0');
    }
    if (i < text.size() && text[i] == '.') {
        double scale = 0.1;
        for (++i; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i, digits = true) {
            value += (text[i] - '0') * scale;
            scale /= 10;
        }
    }
    if (!digits) return std::nullopt;
    std::string_view unit = text.substr(i);
    double multiplier = 1;
    static constexpr std::string_view kPrefixes = "KMGT";
    if (!unit.empty() && kPrefixes.find(char(std::toupper(unit[0]))) != std::string_view::npos) {
        multiplier = std::ldexp(1.0, 10 * int(kPrefixes.find(char(std::toupper(unit[0]))) + 1));
        unit.remove_prefix(1);
        if (unit == "i" || unit == "iB" || unit == "ib") unit = {};
    }
    if (unit == "B" || unit == "b") unit = {};
    if (!unit.empty()) return std::nullopt;
    const double bytes = std::floor(value * multiplier);
    if (!(bytes >= 1) || bytes >= 0x1p63) return std::nullopt;
    return uint64_t(bytes);
}

std::string formatBytes(uint64_t bytes) {
    static const char* const kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    int unit = 0;
    double v = double(bytes);
    while (v >= 1024 && unit < 6) {
        v /= 1024;
        ++unit;
    }
    char buf[32];
    if (unit == 0)
        std::snprintf(buf, sizeof(buf), "%llu B", (unsigned long long)bytes);
    else
        std::snprintf(buf, sizeof(buf), "%.2f %s", v, kUnits[unit]);
    return buf;
}

} // namespace pnb::converter
