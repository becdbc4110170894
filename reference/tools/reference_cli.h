// pnb-reference's command line: its settings and the option table that parses them and prints
// --help (pnb_cli/options.h).
#pragma once

#include <optional>
#include <string>

#include "pnb_reference/frame_tracer.h"
#include "pnb_reference/indirect_tracer.h"
#include "pnb_reference/sky_tracer.h"

namespace pnb::reference_tool {

struct Settings {
    std::string scene, frameDir, outDir, prefix;
    bool quiet = false;
    bool indirect = false;
    pnb::reference::IndirectSettings indirectSettings;
    bool sky = false;
    pnb::reference::SkySettings skySettings;
    // --whole-frame: the path-traced HDR image of the whole frame (reference_whole_frame.h).
    bool wholeFrame = false;
    pnb::reference::FrameTraceSettings frameSettings;
    // Given on the command line (they override what frame.json records).
    std::optional<double> skyRotationDegrees, skyIntensity;
    // --anim-clip C (an index, a name or none), --anim-time T (seconds): the instant traced,
    // instead of frame.json's "anim" (reference_pose.h).
    std::optional<std::string> animClip;
    std::optional<double> animTime;
    std::string usageError; // an option's value that could not be used (exit 1)
};

// Parses argv into `settings`. Returns the exit code when the run ends here (--help: 0, a usage
// error: 1, reported), nothing when it goes on.
std::optional<int> parseCommandLine(int argc, char** argv, Settings& settings);

} // namespace pnb::reference_tool
