// material_block.h — the per-material uniform block (binding PNB_BINDING_MATERIAL_BLOCK,
// bindings.h): the MATL chunk's factors as scene_load.cpp packs them (materialBlock()), for GLSL
// (interface.glsl, read by material.glsl) and C++ (pnb::player::MaterialBlock). gpu_layout.h
// says how one list serves both.
#ifndef PNB_SHARED_MATERIAL_BLOCK_H
#define PNB_SHARED_MATERIAL_BLOCK_H

#include "bindings.h"
#include "gpu_layout.h"

// Texture slots with a transform: base colour, metallic-roughness, normal, occlusion, emissive
// (interface.glsl's PNB_TEX_* units, pnb::Material::textures).
#define PNB_MATERIAL_TEXTURE_SLOTS 5

#define PNB_MATERIAL_BLOCK_MEMBERS(FIELD, ARRAY)                                                   \
    FIELD(vec4, baseColorFactor, uBaseColorFactor)                                                 \
    FIELD(vec4, emissive, uEmissive) /* rgb * strength, a unused */                                \
    FIELD(vec4, params, uMaterialParams) /* metallic, roughness, normalScale, occlusionStrength */ \
    FIELD(vec4, alphaParams, uAlphaParams) /* alphaCutoff, 1 if BLEND (else alpha is forced to 1), \
                                              1 if the surface receives shadows (deferred: a      \
                                              G-buffer bit), 1 if unlit (KHR_materials_unlit;     \
                                              deferred: a G-buffer bit) */                        \
    ARRAY(vec4, texTransform, uTexTransform, PNB_MATERIAL_TEXTURE_SLOTS * 2) /* per slot:          \
                                   (offset.xy, scale.xy), (rotation, texCoord, 0, 0) */

PNB_NAMESPACE_BEGIN
PNB_UNIFORM_BLOCK(MaterialBlock, MaterialBlock, PNB_BINDING_MATERIAL_BLOCK) {
    PNB_MATERIAL_BLOCK_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std140, MaterialBlock, PNB_MATERIAL_BLOCK_MEMBERS)
PNB_NAMESPACE_END

#endif
