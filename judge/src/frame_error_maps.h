// frame_error_maps.h — pnb-judge's --error-maps for --frame-metrics: error_frame.png (the
// LDR-FLIP of each pixel, magma as FLIP's papers draw it) and compare_frame.png (the player's
// displayed frame | the truth's, through the same tone map | the FLIP map), drawn with the
// player's map helpers (player/tools/error_maps.h).
#pragma once

#include "error_maps.h"
#include "frame_quality.h"

namespace pnb::player {

// Empty maps (width 0) when the frame is empty.
ErrorMap frameErrorMap(const FrameQuality::Frame& frame);
ErrorMap frameSideBySide(const FrameQuality::Frame& frame);

} // namespace pnb::player
