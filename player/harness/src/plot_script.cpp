// Running the benchmark's plot script (plot_script.h).
#include "plot_script.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "player_tools.h"

namespace pnb::player {

namespace {

// Debian's python3-matplotlib belongs to /usr/bin/python3, which a user's PATH may shadow
// (pyenv, venvs); PNB_PYTHON overrides.
std::string python() {
    if (const char* env = std::getenv("PNB_PYTHON")) return env;
    return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

} // namespace

bool runPlotScript(const std::string& outDir, const std::string& args) {
    std::string script;
    bool temporary = false;
    if (const char* env = std::getenv("PNB_PLOT_SCRIPT")) {
        script = env;
    } else {
        script = outDir + "/.plot_frames.py";
        for (const EmbeddedFile& f : kPlayerTools) {
            if (f.name != "plot_frames.py") continue;
            std::ofstream out(script, std::ios::binary | std::ios::trunc);
            out.write(f.text.data(), std::streamsize(f.text.size()));
            if (!out) return false;
            temporary = true;
        }
        if (!temporary) return false;
    }
    std::string cmd = python() + " '" + script + "' " + args;
    bool ok = std::system(cmd.c_str()) == 0;
    if (temporary) {
        std::error_code ec;
        std::filesystem::remove(script, ec);
    }
    return ok;
}

} // namespace pnb::player
