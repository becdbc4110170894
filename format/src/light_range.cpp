// How far a light reaches (pnb/light_range.h).
#include "pnb/light_range.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pnb {

float lightCutoffRange(const Light& light, float cutoffLux) {
    if (light.type == LightType::Directional) return 0.0f;
    if (!(cutoffLux > 0.0f) || !std::isfinite(cutoffLux)) cutoffLux = kDefaultLightCutoffLux;
    const double brightest = std::max({double(light.color.x), double(light.color.y), double(light.color.z)});
    const double power = double(light.intensity) * brightest;
    if (!(power > 0.0)) return 0.0f; // no light (or NaN): nothing to reach
    return float(std::min(std::sqrt(power / double(cutoffLux)), double(std::numeric_limits<float>::max())));
}

float effectiveLightRange(const Light& light, float cutoffLux) {
    if (light.type == LightType::Directional) return 0.0f;
    if (light.range > 0.0f && std::isfinite(light.range)) return light.range;
    return lightCutoffRange(light, cutoffLux);
}

} // namespace pnb
