// pnb-reference's judgement of the player's colour shadow visibility (light through glass, issue
// 43; docs/REFERENCE.md "Light through glass"): with frame<N>_shadow_color.exr (RGBA float, rgb
// = the judged light's colour visibility, -1 where unclassified) beside the frame, the colour
// truth is written as shadow_color_reference.exr, its error map as shadow_color_diff.png and its
// metrics as metrics.json's "shadow_color".
#pragma once

#include <span>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "pnb_reference/local_light.h"
#include "pnb_reference/shadow_color_metrics.h"
#include "reference_io.h"

namespace pnb::reference_tool {

// Compares the player's dump (its R, G, B) with `truth` (ShadowTracer::colorVisibility*, one per
// pixel): for a local light (`reach` non-null) over the pixels it reaches, weighted by its
// irradiance; for the sun weighted by `sunWeights`. Writes outDir/shadow_color_reference.exr
// (RGB float, NaN without geometry) and outDir/shadow_color_diff.png. Errors: Output.
Expected<pnb::reference::ShadowColorMetrics> judgeShadowColor(const std::string& outDir, const Frame& frame,
                                                              const FloatImage& player,
                                                              std::span<const glm::vec3> truth,
                                                              const pnb::reference::LocalLightWeights* reach,
                                                              std::span<const float> sunWeights);

// metrics.json's "shadow_color" object.
nlohmann::ordered_json shadowColorJson(const pnb::reference::ShadowColorMetrics& m);

// The summary line of the colour comparison.
void printShadowColorSummary(const pnb::reference::ShadowColorMetrics& m);

} // namespace pnb::reference_tool
