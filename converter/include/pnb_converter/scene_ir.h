// pnb_converter/scene_ir.h — the format-neutral scene the importers produce and the processing
// stages consume (importer → IR → processing → container writer).
//
// Does NOT do: any processing (welding, mips, ...): the IR holds what the source said, in plain
// float arrays and decoded-or-not images, so every importer stays a translation and every
// processing step is written once.
//
// Conventions: right-handed, +Y up, metres, glTF's (the assimp importer converts). Triangles
// only: importers turn strips, fans and quads into triangle lists; lines and points are dropped
// with a warning. Indices are 32-bit and refer to the primitive's own vertex arrays.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb_converter/spec_gloss.h"

namespace pnb::converter {

// What went wrong, and the exit code it maps to (docs/STYLE.md §5.4).
enum class ConvertErrorKind : uint8_t {
    Input = 2,       // the source is malformed, missing, or inconsistent
    Unsupported = 3, // the source is valid but needs something we do not do (required extension)
    Output = 4,      // the container could not be written
};

// An error that stops the conversion. `message` names the file and the item at fault
// ("scene.gltf: accessor 7 (mesh 'Wheel' primitive 0 POSITION): index 812 out of range 0..799").
struct ConvertError {
    ConvertErrorKind kind = ConvertErrorKind::Input;
    std::string message;
};

// An image as the source refers to it. Exactly one of `path` and `encoded` is set: a file on disk
// (already resolved relative to the source file), or bytes embedded in the source (a data URI or
// a glb buffer view) still in their file format (PNG, JPEG, ...).
struct IrImage {
    std::string name;                 // for messages and the container's texture name
    std::string path;                 // absolute or relative to the working directory
    std::vector<uint8_t> encoded;     // embedded image file bytes
    std::string mimeType;             // "image/png", ... if known
};

// How a material uses a texture. `image` indexes IrScene::images, or -1 for "no texture".
struct IrTextureRef {
    int image = -1;
    uint8_t texCoord = 0;
    Vec2 offset{0, 0}, scale{1, 1}; // KHR_texture_transform
    float rotationRadians = 0;
    MinFilter minFilter = MinFilter::LinearMipLinear;
    MagFilter magFilter = MagFilter::Linear;
    Wrap wrapU = Wrap::Repeat, wrapV = Wrap::Repeat;
};

struct IrMaterial {
    std::string name;
    // PBR factors, alpha mode, double-sided, as the source gives them; `program`, the texture
    // indices inside `pbr.textures` and the pipeline placement are decided later (material
    // resolve), so importers leave them at their defaults.
    Material pbr;
    std::array<IrTextureRef, size_t(TextureSlotKind::Count)> textures{};
    // KHR_materials_pbrSpecularGlossiness without a metallic-roughness fallback: its factors, to
    // be converted by material resolve (pnb_converter/spec_gloss.h). The BaseColor and
    // MetallicRoughness texture slots then hold the diffuse and specular-glossiness textures,
    // and pbr's colour, metallic and roughness factors are ignored.
    std::optional<SpecGlossFactors> specGloss;
};

// One morph target of a primitive: per-vertex displacements (xyz), each stream empty when the
// target does not move that attribute (glTF 2.0 §3.7.2.2). Tangent deltas are xyz only.
struct IrMorphTarget {
    std::vector<float> positions, normals, tangents;
};

// One draw's worth of geometry: separate float streams, empty when the source has none.
struct IrPrimitive {
    std::vector<float> positions; // xyz per vertex (required)
    std::vector<float> normals;   // xyz
    std::vector<float> tangents;  // xyzw (w = bitangent sign)
    std::vector<float> uv0, uv1;  // uv, glTF orientation (v down the image)
    std::vector<float> colors;    // rgba, linear
    // Skinning (only in a mesh a skinned node draws): four joint indices into the node's skin
    // and four weights per vertex, as the source gave them (the weights are normalised by mesh
    // processing). Both empty, or both 4 x vertexCount.
    std::vector<uint32_t> joints;
    std::vector<float> weights;
    std::vector<IrMorphTarget> targets; // empty, or one per IrMesh::morphWeights entry
    std::vector<uint32_t> indices; // triangle list; importers generate 0..n-1 when unindexed
    int material = -1;             // IrScene::materials index, -1 = the default material

    size_t vertexCount() const { return positions.size() / 3; }
};

struct IrMesh {
    std::string name;
    std::vector<IrPrimitive> primitives;
    // Morph targets: their default weights and names (empty: the mesh has none). A primitive
    // with fewer targets than this (or none) does not move under the missing ones.
    std::vector<float> morphWeights;
    std::vector<std::string> targetNames; // empty or one per target
    bool skinned = false; // drawn by a skinned node: every primitive carries joints and weights

    bool deformed() const { return skinned || !morphWeights.empty(); }
};

struct IrNode {
    std::string name;
    int parent = -1; // an earlier node, or -1
    Vec3 translation{0, 0, 0};
    Vec4 rotation{0, 0, 0, 1}; // unit quaternion xyzw
    Vec3 scale{1, 1, 1};
    int mesh = -1, light = -1, camera = -1;
    int skin = -1; // IrScene::skins index deforming the node's mesh (which is then skinned)
    // EXT_mesh_gpu_instancing: the mesh's copies, each at the node's transform times its own;
    // empty = the node draws its mesh once (docs/FORMAT.md NODE version 2).
    std::vector<InstanceTransform> instances;
};

struct IrLight {
    std::string name;
    LightType type = LightType::Directional;
    Vec3 color{1, 1, 1};
    float intensity = 1; // lux or candela (KHR_lights_punctual)
    // As in the source: 0 = none given; negative, NaN or infinite = invalid in the source.
    // processLights (light_processing.h) turns both into a computed range, with a warning.
    float range = 0;
    float innerConeRadians = 0, outerConeRadians = 0.7853982f;
    bool castsShadows = true; // decided by processLights, not by importers
};

struct IrCamera {
    std::string name;
    Projection projection = Projection::Perspective;
    float yfovRadians = 0.8f, aspectRatio = 0, znear = 0.1f, zfar = 0, xmag = 1, ymag = 1;
};

// A skin: the nodes (IR indices) whose world transforms deform the vertices of the skinned nodes'
// meshes, with one inverse bind matrix (column-major) per joint. The nodes it deforms are those
// with IrNode::skin naming it.
struct IrSkin {
    std::string name;
    std::vector<int> joints;
    std::vector<std::array<float, 16>> inverseBindMatrices;
};

// A clip's channel: one property of one node (IR index), as pnb::AnimationChannel stores it
// (times in seconds, rotations xyzw, cubic-spline keys as in-tangent, value, out-tangent).
struct IrAnimationChannel {
    int node = -1;
    AnimatedProperty property = AnimatedProperty::Translation;
    KeyInterpolation interpolation = KeyInterpolation::Linear;
    std::vector<float> times, values;
};

struct IrAnimation {
    std::string name;
    std::vector<IrAnimationChannel> channels;
};

// A feature of the source the player does not draw, once per feature: how much of the scene
// uses it and what is drawn instead ({"KHR_materials_sheen", 3, "materials", "the base layer,
// without sheen"}). The summary lists them once, not as a warning per item.
struct IrNotRendered {
    std::string feature;
    size_t count = 0;     // 0: `unit` says it all ("2 materials, 1 texture")
    std::string unit;     // what `count` counts: "materials", "primitives", "clips", ... ("":
                          // the feature's own name says it: "skins (2)")
    std::string fallback; // what the player draws instead
};

// A whole imported scene. Nodes are ordered parents first (importers reorder if needed).
struct IrScene {
    std::string sourcePath;
    std::vector<IrImage> images;
    std::vector<IrMaterial> materials;
    std::vector<IrMesh> meshes;
    std::vector<IrNode> nodes;
    std::vector<IrLight> lights;
    std::vector<IrCamera> cameras;
    std::vector<IrSkin> skins;
    std::vector<IrAnimation> animations;
    // Non-fatal findings, each naming the item ("material 'Wood': alphaMode 'X' is invalid").
    std::vector<std::string> warnings;
    std::vector<IrNotRendered> notRendered; // noteNotRendered adds to it

    // Adds `count` uses of `feature` (merged with earlier uses of the same feature).
    void noteNotRendered(const std::string& feature, size_t count, const std::string& unit,
                         const std::string& fallback) {
        for (IrNotRendered& n : notRendered)
            if (n.feature == feature) {
                n.count += count;
                return;
            }
        notRendered.push_back({feature, count, unit, fallback});
    }
    // Files read besides the source itself (buffers, MTL libraries), for build-system
    // dependency files. External images are listed in `images`.
    std::vector<std::string> dependencies;
};

} // namespace pnb::converter
