// pnb_converter/spec_gloss.h — KHR_materials_pbrSpecularGlossiness turned into glTF's
// metallic-roughness, the model the container, the player and the reference shade.
//
// The conversion is the one Khronos published beside the (archived) extension
// ("convert-between-workflows", KhronosGroup/glTF, extensions/2.0/Archived/
// KHR_materials_pbrSpecularGlossiness/examples): metallic solves the quadratic that makes a
// metal-rough material reflect the given specular colour above a 4 % dielectric; base colour is
// the diffuse colour rescaled for the energy the specular takes, blended toward the specular
// colour as metallic rises (weight metallic²); roughness = 1 − glossiness. Metals, whose diffuse
// is black and whose colour is in the specular (the gold bottle of SpecGlossVsMetalRough), come out
// with their colour as base colour and metallic near 1 instead of black.
//
// Every colour here is linear light. Applied per texel when a material has textures
// (texture_processing.cpp), or once to the factors when it has none.
#pragma once

#include "pnb/chunks.h"

namespace pnb::converter {

struct SpecGlossFactors {
    Vec4 diffuse{1, 1, 1, 1};  // diffuseFactor, linear RGBA
    Vec3 specular{1, 1, 1};    // specularFactor, linear RGB
    float glossiness = 1;      // glossinessFactor
};

struct MetalRough {
    Vec4 baseColor{1, 1, 1, 1}; // linear RGBA, alpha = the diffuse alpha
    float metallic = 0, roughness = 1;
};

// One texel or one set of factors: `diffuse` and `specular` are the products of each texture's
// texel (white without one) and its factor.
MetalRough specGlossToMetalRough(Vec4 diffuse, Vec3 specular, float glossiness);

} // namespace pnb::converter
