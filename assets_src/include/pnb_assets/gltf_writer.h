// pnb_assets/gltf_writer.h — a small glTF 2.0 binary (.glb) writer for procedural source scenes.
//
// The procedural scenes (procedural_scenes.h) are *source* assets: they go through the same
// converter path as artists' files, so they are written as glTF rather than as .pnb. This writer
// turns a plain in-memory Document into a .glb: a JSON chunk (nlohmann::json, which sorts object
// keys, so the text is stable) and a BIN chunk holding every accessor and embedded image.
//
// Output guarantees (tests/assets check each one on every procedural scene):
//   - asset.version "2.0", asset.generator "penumbra assets_src";
//   - one bufferView per accessor or image, each starting on a 4-byte boundary; vertex views
//     carry target ARRAY_BUFFER, index views ELEMENT_ARRAY_BUFFER, image views no target;
//   - buffers[0].byteLength equals the BIN chunk's length, both chunks padded to 4 bytes (JSON
//     with spaces, BIN with zeros) as the GLB container requires;
//   - POSITION accessors carry exact min/max; indices are UNSIGNED_SHORT when a primitive has
//     at most 65535 vertices (65535 itself is never used: glTF reserves the maximum value for
//     primitive restart), UNSIGNED_INT otherwise;
//   - lights via KHR_lights_punctual (listed in extensionsUsed, never extensionsRequired);
//   - the scene's root nodes are the nodes no other node lists as a child, in index order.
//   - Deterministic: the same Document gives identical bytes (no timestamps; floats are written
//     as the exact decimal value of the float, which also makes min/max round-trip exactly).
//
// Conventions are glTF's: metres, +Y up, right-handed; cameras look along their node's local
// -Z with +Y up; directional and spot lights shine along their node's local -Z.
//
//   - skins, morph targets and animations (the moving scenes, crowd and moving-light): JOINTS_0
//     as UNSIGNED_BYTE VEC4 when every joint index is below 256, else UNSIGNED_SHORT; WEIGHTS_0
//     float VEC4; morph targets' POSITION deltas with exact min/max; animation inputs with
//     min/max; inverse bind matrices, animation inputs and outputs are written once per distinct
//     content (a thousand characters sharing one bind pose share one accessor), in views
//     without a target.
//
// Does NOT do: tangents, interleaving, sparse accessors, cubic-spline samplers, compression
// (Draco/meshopt), external .bin or image files, KHR_texture_transform.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "pnb/atomic_file.h"
#include "pnb/error.h"

namespace pnb::assets::gltf {

using Float2 = std::array<float, 2>;
using Float3 = std::array<float, 3>;
using Float4 = std::array<float, 4>; // quaternions are (x, y, z, w), as in glTF

constexpr int32_t kNone = -1;

enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

// An embedded image. `png` holds a complete PNG file (see png_writer.h); it is stored in the BIN
// chunk with mimeType "image/png".
struct Image {
    std::string name;
    std::vector<uint8_t> png;
};

// A metallic-roughness material. Defaults differ from glTF's where noted: our scenes are mostly
// dielectric, so metallicFactor defaults to 0 (glTF: 1).
struct Material {
    std::string name;
    Float4 baseColorFactor{1, 1, 1, 1}; // linear RGB + alpha
    float metallicFactor = 0.0f;        // [0, 1]. Default 0 (glTF's default is 1).
    float roughnessFactor = 1.0f;       // [0, 1]. Default 1.
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f; // written only for AlphaMode::Mask. Default 0.5.
    bool doubleSided = false;
    bool unlit = false;             // KHR_materials_unlit
    Float3 emissiveFactor{0, 0, 0}; // linear RGB, each in [0, 1]
    int32_t baseColorImage = kNone; // index into Document::images, or kNone. The texture
                                    // uses a repeat-wrap, trilinear sampler.
    int32_t normalImage = kNone;    // tangent-space normal map (glTF normalTexture, scale 1),
                                    // or kNone. No TANGENT is written: the converter derives
                                    // tangents from uv0, so primitives using it need uv0.
};

// A morph target of a primitive: per-vertex displacements (parallel to the primitive's
// positions); normal displacements are optional (empty: not written).
struct MorphTarget {
    std::vector<Float3> positionDeltas;
    std::vector<Float3> normalDeltas;
};

using Joints4 = std::array<uint16_t, 4>;

// One triangle list with one material. Vertex arrays are parallel: normals.size() ==
// positions.size(), and uv0 is either empty (no TEXCOORD_0) or the same size. Normals must be
// unit length. Triangles are counter-clockwise seen from the front, as glTF requires.
struct Primitive {
    std::vector<Float3> positions; // metres, in the mesh's (node-local) space
    std::vector<Float3> normals;
    std::vector<Float2> uv0;       // optional; glTF convention: v = 0 is the image's top row
    std::vector<uint32_t> indices; // multiple of 3, each < positions.size()
    uint32_t material = 0;         // index into Document::materials
    // Skinning (both empty, or both positions.size()): indices into the skin's joint list, and
    // weights >= 0 summing to 1 (within 1e-5); a slot of weight 0 should name joint 0.
    std::vector<Joints4> joints0;
    std::vector<Float4> weights0;
    // Morph targets: every primitive of a mesh has the same number (Mesh::weights.size()).
    std::vector<MorphTarget> targets;

    uint64_t triangleCount() const { return indices.size() / 3; }
};

struct Mesh {
    std::string name;
    std::vector<Primitive> primitives; // at least one
    std::vector<float> weights;        // default morph weights, one per morph target
};

// A skin: its joints (node indices) and one inverse bind matrix per joint (column-major 4x4, the
// inverse of the joint's world matrix in the bind pose). `skeleton`: the joints' common root
// node, or kNone.
struct Skin {
    std::string name;
    std::vector<uint32_t> joints; // at least one, distinct
    std::vector<std::array<float, 16>> inverseBindMatrices;
    int32_t skeleton = kNone;
};

enum class AnimationPath : uint8_t { Translation, Rotation, Scale, Weights };
enum class Interpolation : uint8_t { Linear, Step };

// Key times (seconds, strictly increasing, >= 0) and values: 3 floats a key for translation and
// scale, 4 (a unit quaternion, x y z w) for rotation, one per morph target for weights.
struct AnimationSampler {
    std::vector<float> input;
    std::vector<float> output;
    Interpolation interpolation = Interpolation::Linear;
};

// A channel animates one property of one node with one sampler; several channels may share a
// sampler. At most one channel per (node, path).
struct AnimationChannel {
    uint32_t sampler = 0; // index into Animation::samplers
    uint32_t node = 0;
    AnimationPath path = AnimationPath::Rotation;
};

struct Animation {
    std::string name;
    std::vector<AnimationSampler> samplers; // at least one
    std::vector<AnimationChannel> channels; // at least one
};

// A node with a TRS transform (written only where not the identity).
struct Node {
    std::string name;
    Float3 translation{0, 0, 0};
    Float4 rotation{0, 0, 0, 1}; // unit quaternion (x, y, z, w)
    Float3 scale{1, 1, 1};
    int32_t mesh = kNone;           // index into Document::meshes
    int32_t camera = kNone;         // index into Document::cameras
    int32_t light = kNone;          // index into Document::lights (KHR_lights_punctual)
    int32_t skin = kNone;           // index into Document::skins (the node's mesh is skinned)
    std::vector<uint32_t> children; // each node has at most one parent; no cycles
    // EXT_mesh_gpu_instancing: the mesh is drawn once per translation (empty: once, plainly).
    std::vector<Float3> instanceTranslations;
};

// A perspective camera, or with `orthographic` an orthographic one (xmag, ymag, znear >= 0 and
// zfar > znear, which glTF requires there; yfov and aspectRatio are then not written).
struct Camera {
    std::string name;
    float yfovRadians = 0.9f; // vertical field of view, (0, pi). Default 0.9 (~52 degrees).
    float aspectRatio = 0.0f; // width / height; 0 = not written (the viewport decides)
    float znear = 0.1f;       // metres, > 0. Default 0.1.
    float zfar = 0.0f;        // metres, > znear; 0 = not written (infinite projection)
    bool orthographic = false;
    float xmag = 1.0f, ymag = 1.0f; // orthographic half width and height, metres, > 0
};

enum class LightType : uint8_t { Directional, Point, Spot };

// A KHR_lights_punctual light. Units follow the extension: directional intensity in lux, point
// and spot intensity in candela. A light shines down its node's -Z (directional, spot).
struct Light {
    std::string name;
    LightType type = LightType::Directional;
    Float3 color{1, 1, 1}; // linear RGB
    float intensity = 1.0f;
    float range = 0.0f; // point and spot lights only; metres; 0 = not written (infinite)
    // Spot lights only: angles from the axis, 0 <= inner < outer <= pi/2 (the extension's rule).
    // Defaults: the extension's (0 and pi/4).
    float innerConeRadians = 0.0f;
    float outerConeRadians = 0.7853982f;
};

// Everything one .glb holds.
struct Document {
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Image> images;
    std::vector<Node> nodes;
    std::vector<Camera> cameras;
    std::vector<Light> lights;
    std::vector<Skin> skins;
    std::vector<Animation> animations;
    std::string sceneName; // glTF scenes[0].name; may be empty
};

// Counts of what encodeGlb() wrote.
struct GlbStats {
    uint64_t renderedTriangles = 0; // triangles drawn once per node that references a mesh
    uint64_t uniqueTriangles = 0;   // triangles stored in the file (each mesh counted once)
    uint64_t vertices = 0;          // vertices stored in the file
    uint64_t sizeBytes = 0;         // size of the .glb
};

// Checks the Document against the preconditions stated on the structs above (array sizes,
// indices in range, one parent per node, no cycles, finite numbers). Returns an empty string if
// the Document is valid, else a sentence naming the first problem. encodeGlb() asserts this.
std::string validateDocument(const Document& doc);

// Triangles drawn when the scene is rendered: each node with a mesh draws all of its primitives
// once (instancing counts every instance). Only nodes reachable from the roots count.
// Precondition: validateDocument(doc) is empty.
uint64_t countRenderedTriangles(const Document& doc);

// Encodes `doc` as a .glb. Precondition (asserted): validateDocument(doc) is empty.
// `stats`, if not null, receives the counts. Deterministic. Thread-safe for distinct documents.
std::vector<uint8_t> encodeGlb(const Document& doc, GlbStats* stats = nullptr);

// Files are written with pnb::writeFileAtomic (pnb/atomic_file.h).

// --- Small helpers for building Documents ------------------------------------------------------

// The rotation that turns a node's local -Z axis into `forward` and keeps local +Y as close to
// `up` as possible (a "look rotation" for cameras and lights). `forward` need not be normalised
// but must not be zero or parallel to `up`.
Float4 lookRotation(Float3 forward, Float3 up = {0, 1, 0});

// Rotates vector `v` by unit quaternion `q`.
Float3 rotate(Float4 q, Float3 v);

// Rotation of `radians` about the +Y axis.
Float4 rotationY(float radians);

// Rotation of `radians` about the unit axis `axis`.
Float4 rotationAxis(Float3 axis, float radians);

// Hamilton product a * b (apply b, then a).
Float4 multiply(Float4 a, Float4 b);

} // namespace pnb::assets::gltf
