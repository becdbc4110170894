// pnb_converter/mtl_to_pbr.h — the documented mapping of Wavefront MTL parameters onto the glTF
// metallic-roughness model (issue 3 builds the OBJ importer on it).
//
// Mapping (docs note: MTL is a Phong model, so this is an approximation):
//   baseColor.rgb = Kd;  baseColor.a = d, else 1 - Tr, else 1
//   roughness     = Pr if given, else (2 / (Ns + 2))^(1/4): the Blinn-Phong exponent's equivalent
//                   GGX alpha = sqrt(2 / (Ns + 2)), and perceptual roughness = sqrt(alpha)
//   metallic      = Pm if given, else 0 (MTL's Ks has no metallic-roughness equivalent)
//   emissive      = Ke
//   alphaMode     = Blend when alpha < 1, else Opaque
// Non-finite inputs are treated as absent; outputs are clamped to their valid ranges.
#pragma once

#include <optional>

#include "pnb/chunks.h"

namespace pnb::converter {

struct MtlParameters {
    Vec3 kd{0.8f, 0.8f, 0.8f}; // diffuse colour (MTL default 0.8)
    std::optional<float> ns;   // specular exponent, 0..1000
    std::optional<float> d;    // dissolve (opacity)
    std::optional<float> tr;   // transparency = 1 - d (some exporters)
    Vec3 ke{0, 0, 0};          // emissive colour
    std::optional<float> pr;   // PBR extension: roughness
    std::optional<float> pm;   // PBR extension: metallic
};

// Fills the PBR factors and alpha mode of `material` from MTL parameters; other fields are kept.
void applyMtlToPbr(const MtlParameters& mtl, Material& material);

} // namespace pnb::converter
