#include "pnb_converter/mtl_to_pbr.h"

#include <algorithm>
#include <cmath>

namespace pnb::converter {

namespace {

std::optional<float> finite(std::optional<float> v) {
    return v && std::isfinite(*v) ? v : std::nullopt;
}

float clamp01(float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; }

} // namespace

void applyMtlToPbr(const MtlParameters& mtl, Material& m) {
    float alpha = 1.0f;
    if (auto d = finite(mtl.d)) alpha = *d;
    else if (auto tr = finite(mtl.tr)) alpha = 1.0f - *tr;
    alpha = clamp01(alpha);
    m.baseColorFactor = {clamp01(mtl.kd.x), clamp01(mtl.kd.y), clamp01(mtl.kd.z), alpha};

    if (auto pr = finite(mtl.pr)) {
        m.roughnessFactor = clamp01(*pr);
    } else if (auto ns = finite(mtl.ns); ns && *ns > 0) {
        m.roughnessFactor = clamp01(std::pow(2.0f / (*ns + 2.0f), 0.25f));
    } else {
        m.roughnessFactor = 1.0f; // Ns absent or 0: no highlight at all
    }
    auto pm = finite(mtl.pm);
    m.metallicFactor = pm ? clamp01(*pm) : 0.0f;

    auto nonNegative = [](float v) { return std::isfinite(v) ? std::max(v, 0.0f) : 0.0f; };
    m.emissiveFactor = {nonNegative(mtl.ke.x), nonNegative(mtl.ke.y), nonNegative(mtl.ke.z)};
    m.alphaMode = alpha < 1.0f ? AlphaMode::Blend : AlphaMode::Opaque;
}

} // namespace pnb::converter
