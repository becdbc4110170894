// How far a light reaches (pnb/light_range.h).
#include "pnb/light_range.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pnb {

float lightCutoffRange(const Light& light, float cutoffLux) {
    if (light.type == LightType::Directional) return 0.0f;
    if (!(cutoffLux > 0.0f) || !std::isfinite(cutoffLux)) cutoffLux = kDefaultLightCutoffLux;
    const double c[3] = {double(light.color.x), double(light.color.y), double(light.color.z)};
    // A NaN in any channel is "no light" as the header says (std::max would keep or drop a NaN
    // depending on which channel holds it).
    if (std::isnan(c[0]) || std::isnan(c[1]) || std::isnan(c[2])) return 0.0f;
    const double brightest = std::max({c[0], c[1], c[2]});
    const double power = double(light.intensity) * brightest;
    if (!(power > 0.0)) return 0.0f; // no light (or NaN intensity): nothing to reach
    return float(std::min(std::sqrt(power / double(cutoffLux)), double(std::numeric_limits<float>::max())));
}

float effectiveLightRange(const Light& light, float cutoffLux) {
    const float cutoffRange = lightCutoffRange(light, cutoffLux);
    // Checked before the own range, as the header says: a dark light reaches nothing whatever
    // range a writer gave it, so renderers can skip it by this number alone.
    if (cutoffRange == 0.0f) return 0.0f;
    if (light.range > 0.0f && std::isfinite(light.range)) return light.range;
    return cutoffRange;
}

} // namespace pnb
