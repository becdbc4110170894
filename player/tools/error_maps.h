// error_maps.h — pnb-play's --error-maps: heat-maps of what the quality metrics counted in their
// last measured frame (error_shadow.png, error_gi.png, error_sky.png, error_lod.png) and
// error_maps.json, which says for each map its frame and what every colour means.
//
// The maps are drawn from the arrays the metrics compared (the modules' lastFrame()/LodFrame),
// with the metrics' own per-pixel rules (reference::classifyShadow, reference::comparedPixel, the
// > 8/255 count), so counting a map's pixels gives the frame's figure in quality.csv. Rows are
// written top-down like --screenshot's PNG, so a frame's screenshot and its map overlay.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "irradiance_quality.h"
#include "lod_quality.h"
#include "shadow_quality.h"
#include "pnb_player/play_error.h"

namespace pnb::player {

struct Rgb8 {
    uint8_t r = 0, g = 0, b = 0;
};

// The heat ramp of the GI, sky and LOD maps: matplotlib's "magma" sampled at 9 stops, linear in
// between; t is clamped to [0, 1] (NaN: 0). Black-purple (0) to pale yellow (1); never grey.
Rgb8 rampColour(double t);

// Shadow map colours (all greys are exactly grey; misclassified pixels never are).
inline constexpr Rgb8 kMapOutside{40, 40, 40};        // not in the metric's pixel set
inline constexpr Rgb8 kShadowAgreeLit{210, 210, 210}; // lit in both
inline constexpr Rgb8 kShadowAgreeDark{150, 150, 150}; // shadowed in both
// False lit (player lit, truth shadowed): (v, 0, 0); false shadow (player shadowed, truth lit):
// (0, v * 0.35, v); v = 64 + 191 * min(|clamp(player, 0, 1) - truth|, 1) (160..255 for a binary truth).
Rgb8 falseLitColour(double absError);
Rgb8 falseShadowColour(double absError);

// One heat-map, RGB8 rows top-down, with what error_maps.json says about it.
struct ErrorMap {
    std::string metric;   // "shadow", "gi", "sky", "lod"
    std::string file;     // "error_<metric>.png"
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgb;
    std::string encoding; // one sentence: what a pixel's colour measures
    std::vector<std::pair<std::string, std::string>> legend; // colour -> meaning
    double clamp = 0;     // the value drawn at the ramp's top (0: no ramp)
    std::string clampMeaning;
    std::vector<std::pair<std::string, double>> stats; // counts/figures of the map's own pixels
};

// The encoders: empty map (width 0) when the frame is empty.
ErrorMap shadowErrorMap(const ShadowQuality::Frame& frame);
// `metric`: "gi" or "sky" (the file name and the legend's wording).
ErrorMap irradianceErrorMap(const std::string& metric, const IrradianceQuality::Frame& frame);
// The same frame side by side, three panels of the frame's size (compare_<metric>.png): the
// player's and the truth's luminance on one ramp (0 .. 2 x the mean truth), then the signed
// difference (player - truth) / mean truth on a diverging ramp (blue too dark, white right, red
// too bright; clamped at +-1). What the scorecard's numbers summarise, as a picture.
ErrorMap irradianceSideBySide(const std::string& metric, const IrradianceQuality::Frame& frame);
// The diverging ramp of the side-by-side's third panel: t in [-1, 1] (clamped, NaN: 0).
Rgb8 divergingColour(double t);
ErrorMap lodErrorMap(const LodFrame& frame);

// Writes every map's PNG into `outDir` and error_maps.json beside them (`frame`: the measured
// frame the maps show, as quality.csv numbers it). Returns the paths written.
PlayResult<std::vector<std::string>> writeErrorMaps(const std::string& outDir, uint32_t frame,
                                                    const std::vector<ErrorMap>& maps);

} // namespace pnb::player
