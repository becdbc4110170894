// The benchmark's plot (internal to pnb_play_harness): player/tools/plot_frames.py, embedded in
// the harness at build time (player_tools.h) and run with python3.
#pragma once

#include <string>

namespace pnb::player {

// Runs plot_frames.py with ARGS (already shell-quoted); true on exit status 0. The embedded
// script is written next to the outputs in OUT_DIR for the run and removed afterwards, so an
// installed pnb-play plots from any directory; $PNB_PLOT_SCRIPT names a script file to run
// instead, $PNB_PYTHON the interpreter.
bool runPlotScript(const std::string& outDir, const std::string& args);

} // namespace pnb::player
