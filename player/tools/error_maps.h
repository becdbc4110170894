// error_maps.h — --error-maps: heat-maps of what the quality metrics counted in their last
// measured frame (error_lod.png here; error_shadow.png, error_gi.png, error_sky.png from pnb-judge's
// truth metrics, judge/src/truth_error_maps.h) and error_maps.json, which says for each map its
// frame and what every colour means.
//
// The maps are drawn from the arrays the metrics compared, with the metrics' own per-pixel rules
// (the > 8/255 count; reference::classifyShadow and reference::comparedPixel for the truth maps),
// so counting a map's pixels gives the frame's figure in quality.csv. Rows are written top-down
// like --screenshot's PNG, so a frame's screenshot and its map overlay.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "lod_quality.h"
#include "pnb_player/play_error.h"

namespace pnb::player {

struct Rgb8 {
    uint8_t r = 0, g = 0, b = 0;
};

// The heat ramp of the GI, sky and LOD maps: matplotlib's "magma" sampled at 9 stops, linear in
// between; t is clamped to [0, 1] (NaN: 0). Black-purple (0) to pale yellow (1); never grey.
Rgb8 rampColour(double t);

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

// The drawing helpers every map uses: a black map of `metric` (file error_<metric>.png) to fill;
// captured pixel i (rows bottom-up) into the map (rows top-down); a colour as error_maps.json
// names it; a value to a byte (rounded, clamped); the ramp's name in the legends.
ErrorMap blankErrorMap(const std::string& metric, uint32_t width, uint32_t height);
void putCapturedPixel(ErrorMap& m, size_t i, Rgb8 c);
std::string colourName(Rgb8 c);
uint8_t toByte(double v);
extern const std::string kRampName;

// The pixels the metric left out (no geometry, ...), on every map.
inline constexpr Rgb8 kMapOutside{40, 40, 40};

// The level-of-detail map (--lod-metrics); empty map (width 0) when the frame is empty.
ErrorMap lodErrorMap(const LodFrame& frame);

// Writes every map's PNG into `outDir` and error_maps.json beside them (`frame`: the measured
// frame the maps show, as quality.csv numbers it). Returns the paths written.
PlayResult<std::vector<std::string>> writeErrorMaps(const std::string& outDir, uint32_t frame,
                                                    const std::vector<ErrorMap>& maps);

} // namespace pnb::player
