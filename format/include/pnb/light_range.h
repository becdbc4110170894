// pnb/light_range.h — how far a point or spot light reaches: its own range, or, where it has none,
// the distance at which its illuminance falls to a cut-off.
//
// A property of the container, not of a renderer: the converter writes the computed range into
// LGHT (and warns), the player bounds its light clusters and shadow maps with the same number, and
// the reference judges the light over the same reach. KHR_lights_punctual's "no range" means
// inverse-square to infinity, which no culling can bound; the cut-off makes the dropped light
// a stated, measurable amount (FORMAT.md, LGHT).
#pragma once

#include "pnb/chunks.h"

namespace pnb {

// The default cut-off: 0.01 lux (lm/m², glTF's unit; candela / metre²). Lit at that, a white
// Lambertian surface reflects 0.01/π ≈ 0.0032 of radiance: below one 8-bit step (1/255) of the
// player's output at lighting.exposure 1.
inline constexpr float kDefaultLightCutoffLux = 0.01f;

// sqrt(intensity * max(colour) / cutoffLux): where the brightest channel's inverse-square
// illuminance reaches the cut-off. 0 for directional lights and for lights that give no light
// (intensity or colour 0, or NaN): such a light reaches nothing; at most FLT_MAX. cutoffLux <= 0
// or not finite is taken as the default.
float lightCutoffRange(const Light& light, float cutoffLux = kDefaultLightCutoffLux);

// The range the player and the reference use: the light's own when it has one (> 0 and finite),
// else lightCutoffRange. 0 for directional lights (unbounded) and for point and spot lights that
// give no light, whatever range they carry (they reach nothing: a renderer skips them).
// Containers pnb-convert writes carry the range already (computed with its --light-cutoff, which
// may differ from `cutoffLux`); this matters for other writers' range 0 (FORMAT.md "LGHT").
float effectiveLightRange(const Light& light, float cutoffLux = kDefaultLightCutoffLux);

} // namespace pnb
