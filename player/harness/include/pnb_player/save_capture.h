// pnb_player/save_capture.h — a captured buffer (Renderer::capture) written to an image file.
//
// In pnb_play_harness, not the renderer: the renderer hands images back in memory and writes no
// file; pnb-play, pnb-edit and the tests write them with this.
#pragma once

#include <string>

#include "pnb_player/play_error.h"
#include "pnb_player/renderer.h"

namespace pnb::player {

// Writes a captured buffer: PNG for 8-bit, EXR for float; rows flipped to top-down.
PlayResult<Done> saveCapture(const std::string& path, const CapturedImage& image);

} // namespace pnb::player
