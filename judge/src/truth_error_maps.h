// truth_error_maps.h — pnb-judge's --error-maps for the truth metrics: error_shadow.png (each pixel
// classified as --shadow-metrics counts it), error_gi.png / error_sky.png (|player - truth| over the
// mean truth) and compare_gi.png / compare_sky.png (player | truth | difference), drawn with the
// player's map helpers (player/tools/error_maps.h) and the reference's per-pixel rules.
#pragma once

#include <string>

#include "error_maps.h"
#include "irradiance_quality.h"
#include "shadow_quality.h"

namespace pnb::player {

// Shadow map colours (all greys are exactly grey; misclassified pixels never are).
inline constexpr Rgb8 kShadowAgreeLit{210, 210, 210}; // lit in both
inline constexpr Rgb8 kShadowAgreeDark{150, 150, 150}; // shadowed in both
inline constexpr Rgb8 kShadowAgreeGlass{190, 170, 120}; // through glass in both (issue 43)
// False lit (player lit, truth shadowed): (v, 0, 0); false shadow (player shadowed, truth lit):
// (0, v * 0.35, v); v = 64 + 191 * min(|clamp(player, 0, 1) - truth|, 1) (160..255 for a binary truth).
Rgb8 falseLitColour(double absError);
Rgb8 falseShadowColour(double absError);

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

} // namespace pnb::player
