// pnb-reference --whole-frame: the whole frame's path-traced truth (pnb_reference/frame_tracer.h)
// for a dumped frame's camera, written as whole_frame.exr (linear HDR RGB), whole_frame_stderr.exr,
// whole_frame.png (tone mapped with pnb_lighting/tonemap.h at frame.json's exposure) and a
// "whole_frame" object in metrics.json (added to the file's other objects when it exists).
#pragma once

#include "reference_cli.h"

namespace pnb::reference_tool {

// Returns the process exit code (reference_io.h).
int runWholeFrame(const Settings& settings);

} // namespace pnb::reference_tool
