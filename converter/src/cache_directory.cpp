// The user's cache directory (cache_directory.h).

#include "pnb_converter/cache_directory.h"

#include <pwd.h>
#include <unistd.h>

#include <cstdlib>

namespace pnb::converter {

std::string userCacheDirectory() {
    if (const char* dir = std::getenv("PNB_CACHE_DIR"); dir && *dir) return dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && xdg[0] == '/')
        return std::string(xdg) + "/penumbra";
    const char* home = std::getenv("HOME");
    if (!home || !*home) {
        const passwd* pw = getpwuid(getuid());
        home = pw ? pw->pw_dir : nullptr;
    }
    if (!home || !*home) return {};
    return std::string(home) + "/.cache/penumbra";
}

} // namespace pnb::converter
