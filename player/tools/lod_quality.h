// lod_quality.h — pnb-play's --lod-metrics: what level-of-detail selection costs in image
// quality. Each measured frame, as drawn with the levels the selection chose, is compared with
// the same view drawn at full detail (lod.force=0): PSNR of the sRGB output and the share of
// pixels off by more than 8/255, with the triangles of both renders.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "pnb_player/renderer.h"

namespace pnb::player {

// After renderer.render(): lod_psnr_db (RGB, 8-bit; 100 = identical), lod_pixels_over8_pct,
// lod_triangles, full_triangles (main view) and lod_triangle_ratio. Renders the last camera once
// more at full detail and restores the settings; the level state is not touched (lod.force
// bypasses it). Returns nothing for follow-up frames (no temporal metric).
// With `last`, a measured frame also leaves there the per-pixel array the metric counted: the
// largest |selected - full| over R, G, B in 8-bit units (lod_pixels_over8_pct: values > 8),
// rows bottom-up as captured.
struct LodFrame {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> worst;
};
PlayResult<std::vector<std::pair<std::string, double>>> measureLodQuality(Renderer& renderer, bool followUp,
                                                                          LodFrame* last = nullptr);

} // namespace pnb::player
