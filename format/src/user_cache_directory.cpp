// The user's cache directory (pnb/user_cache_directory.h).

#include "pnb/user_cache_directory.h"

#include <cstdlib>

namespace pnb {

std::string userCacheDirectory(const char* overrideVariable, std::string_view subdirectory) {
    auto env = [](const char* name) -> std::string {
        const char* v = name ? std::getenv(name) : nullptr;
        return v && *v ? v : "";
    };
    if (std::string dir = env(overrideVariable); !dir.empty()) return dir;
    std::string base;
    if (std::string xdg = env("XDG_CACHE_HOME"); !xdg.empty() && xdg[0] == '/')
        base = xdg + "/penumbra";
    else if (std::string home = env("HOME"); !home.empty())
        base = home + "/.cache/penumbra";
    else
        return {};
    return subdirectory.empty() ? base : base + "/" + std::string(subdirectory);
}

} // namespace pnb
