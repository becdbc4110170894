// pnb_converter/light_processing.h — the lights as the container gets them (docs/CONVERTER.md
// "Lights"): every point and spot light that gives light has a range, local lights cast shadows,
// every value is in the domain the reader enforces (docs/FORMAT.md "LGHT"), and there are at most
// pnb::kMaxLights of them.
//
// Does NOT do: importing (importers fill IrLight with the source's values, an invalid range
// included), placing lights (nodes do), choosing which lights a player shadows (the player does,
// within its budget).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "pnb/light_range.h"
#include "pnb_converter/scene_ir.h"

namespace pnb::converter {

struct LightSettings {
    // Illuminance (lux) at which a point or spot light without a range is taken to stop
    // (pnb::lightCutoffRange). > 0 and finite. Default: pnb::kDefaultLightCutoffLux (0.01).
    // pnb-convert --light-cutoff.
    float cutoffLux = kDefaultLightCutoffLux;
};

// Up to this many lights of one kind of finding (no range, an invalid range, no light) are
// warned about one line each; more get one summary line: the count, the smallest and largest
// range with their lights, and the first few names. 8 lines stay readable beside the rest of the
// summary; a scene of 1024 lamps gets one line instead of 1024.
inline constexpr size_t kLightWarningsOneByOne = 8;

// Rewrites `scene.lights` into what the container holds, in place:
// - Directional: range 0 (the range means nothing for them), castsShadows.
// - Point and spot lights that give light (pnb::lightCutoffRange > 0): their own range when it is
//   > 0 and finite; none (0): lightCutoffRange(light, cutoffLux), warned; negative, NaN or
//   infinite: the same, warned as invalid. castsShadows = true: they are lamps, and
//   KHR_lights_punctual has no flag to say otherwise; the player decides how many it shadows.
// - Point and spot lights that give no light (intensity 0 or a black colour): range 0 and no
//   shadows; renderers skip them (warned).
// - Values a reader would refuse (a negative or non-finite intensity or colour channel, spot
//   cones outside 0 <= inner <= outer <= pi/2): clamped, warned. Importers clamp these already;
//   this makes the container valid whatever an importer let through.
// - More than pnb::kMaxLights lights: the kMaxLights that light the most are kept, in their
//   order: every directional light first, then by effective range x intensity x brightest
//   colour channel, the illuminance a light gives integrated over the ball it reaches
//   (4 pi I R for I / d^2 out to R), ties by source order. One warning names the count and the
//   first dropped lights. A dropped light's nodes stay, without a light.
// `generated` (one flag per light) and every node's `light` follow the kept lights. Warnings,
// each naming the light (by name, else by index and node), are appended to `warnings`.
// Deterministic. Cost: O(n log n) in the number of lights (100 000 lights: milliseconds).
void processLights(IrScene& scene, std::vector<bool>& generated, const LightSettings& settings,
                   std::vector<std::string>& warnings);

} // namespace pnb::converter
