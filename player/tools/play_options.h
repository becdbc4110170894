// play_options.h — pnb-play's (and pnb-judge's) options: what the command line asks for, parsed
// and checked by one option table (pnb_cli/options.h), which also prints --help.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pnb::player {

// The command line, as given (modes resolve later: e.g. stream -1 follows --headless).
struct Args {
    std::string scene, pathName, outDir, screenshot, recordPath = "recorded_path.json", screenshotDir = ".",
        scriptInput, programCacheDir;
    bool programCache = true;
    double recordEvery = 0;
    std::vector<std::string> sets, dumps;
    bool headless = false, bench = false, ui = false, fixedDt = false, plot = true,
         checksums = true, glDebug = false, quiet = false;
    double dt = 0, seconds = 0;
    int camera = -1;
    uint32_t frames = 0, frame = 0, width = 0, height = 0, shadowMetrics = 0, giMetrics = 0, giSamples = 64,
             lodMetrics = 0, skyMetrics = 0, skySamples = 64,
             giBounces = 1; // --gi-bounces: 0 = converged
    bool giAllLights = false, skyFromSh = false, errorMaps = false;
    // --frame-metrics and its truth (pnb_reference::FrameTraceSettings' defaults)
    uint32_t frameMetrics = 0, frameBounces = 16, frameMaxSamples = 4096;
    double frameNoise = 0.003, frameTimeLimit = 120;
    std::string frameTruthCache, frameTruthScene;
    int stream = -1; // --stream 1, --no-stream 0, -1: by mode
    bool listSettings = false; // --list-settings: print the keys instead of running
};

// Parses and checks argv. Returns the exit code when the run ends here (--help and
// --list-settings: 0; a usage error: 1, reported as "PROGRAM: ..."), nothing when it goes on.
// `program` names the player in messages and usage.
std::optional<int> parsePlayOptions(int argc, char** argv, const char* program, Args& a);

} // namespace pnb::player
