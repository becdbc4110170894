// pnb/chunks.h — typed payloads of the v1 chunk kinds (docs/FORMAT.md §4) and their codecs.
//
// Does NOT do: file I/O (reader.h/writer.h), cross-chunk checks (scene.h validateScene).
//
// Each chunk struct lists its fields once, in `fields(v)`, in the exact order they are stored;
// one generic encoder and one generic decoder walk that list, so the byte layout of FORMAT.md §4
// is the field order below. Encoding rules (FORMAT.md §4.2): little-endian; bool = u8 0|1;
// enums = u8 checked against their Count; float = IEEE binary32; StringRef = u32 index into the
// string table (kNone = none); arrays = u32 count + elements; fixed arrays = elements only;
// Blob = u64 size, zero padding to a 16-byte boundary of the payload, bytes; string = u32 size +
// UTF-8 bytes (string table only).
//
// Decoded Blobs and string_views point into the payload: it must outlive the decoded struct
// (use pnb::Scene, which owns them). When encoding, they point at the caller's data.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "pnb/container.h"
#include "pnb/error.h"
#include "pnb/tags.h"

namespace pnb {

class Writer;

inline constexpr uint32_t kNone = 0xFFFFFFFFu; // "no reference" for every index field
using StringRef = uint32_t;                     // index into the string table, or kNone
using Blob = std::span<const std::byte>;

// A marker in a fields() list (FORMAT.md 3.5 rule 3): the fields after it were appended in
// chunk version `version`. The encoder writes nothing for it; the decoder of an older chunk
// stops there and leaves the later fields at their defaults.
struct SinceVersion {
    uint16_t version;
};

struct Vec2 { float x = 0, y = 0; template <class V> void fields(V& v) { v(x); v(y); } };
struct Vec3 { float x = 0, y = 0, z = 0; template <class V> void fields(V& v) { v(x); v(y); v(z); } };
struct Vec4 {
    float x = 0, y = 0, z = 0, w = 0;
    template <class V> void fields(V& v) { v(x); v(y); v(z); v(w); }
};
// Axis-aligned box; an empty box has min > max (the default).
struct Aabb {
    Vec3 min{1, 1, 1}, max{-1, -1, -1};
    template <class V> void fields(V& v) { v(min); v(max); }

    bool empty() const { return min.x > max.x; }
    // Extends the box to contain p (an empty box becomes the point).
    void grow(Vec3 p) {
        if (empty()) {
            min = max = p;
            return;
        }
        min = {p.x < min.x ? p.x : min.x, p.y < min.y ? p.y : min.y, p.z < min.z ? p.z : min.z};
        max = {p.x > max.x ? p.x : max.x, p.y > max.y ? p.y : max.y, p.z > max.z ? p.z : max.z};
    }
};
struct Sphere {
    Vec3 center;
    float radius = 0;
    template <class V> void fields(V& v) { v(center); v(radius); }
};

// [SECTION] STRS — string table. Must be the first chunk; every StringRef indexes it.
struct StringTable {
    std::vector<std::string_view> strings;
    template <class V> void fields(V& v) { v(strings); }
};

// [SECTION] INFO — scene info
struct SceneInfo {
    StringRef name = kNone;
    StringRef generator = kNone; // tool and version that wrote the file
    StringRef source = kNone;    // source file name, without directories
    float metersPerUnit = 1.0f;  // scene units; +Y is up, right-handed, glTF conventions
    Aabb bounds;                 // world-space bounds of all mesh instances
    template <class V> void fields(V& v) { v(name); v(generator); v(source); v(metersPerUnit); v(bounds); }
};

// [SECTION] RSET — render settings: "section.key" = "value" pairs, the same names as the
// player's --set option (e.g. shadows.cascades = 4). The player's command line wins.
struct Setting {
    StringRef key = kNone, value = kNone;
    template <class V> void fields(V& v) { v(key); v(value); }
};
struct RenderSettings {
    std::vector<Setting> entries;
    template <class V> void fields(V& v) { v(entries); }
};

// [SECTION] SHDR — one shader stage's GLSL source, #includes already resolved
enum class ShaderStage : uint8_t { Vertex, Fragment, Geometry, Compute, TessControl, TessEvaluation, Count };
struct ShaderSource {
    StringRef name = kNone;
    ShaderStage stage = ShaderStage::Vertex;
    Blob source; // UTF-8 GLSL without the #version line's defines (see Program)
    template <class V> void fields(V& v) { v(name); v(stage); v(source); }
};

// [SECTION] PROG — a program: shader stages + the permutation defines it was validated with
struct Program {
    StringRef name = kNone;
    std::vector<uint32_t> shaders; // indices of SHDR chunks (in file order), one per stage
    std::vector<StringRef> defines; // "NAME" or "NAME=VALUE", inserted after #version
    template <class V> void fields(V& v) { v(name); v(shaders); v(defines); }
};

// [SECTION] TEXR — texture descriptor; its pixels follow later in TMIP chunks
enum class TextureDimension : uint8_t { Tex2D, Cube, Count };
enum class TextureFormat : uint8_t {
    R8, RG8, RGB8, RGBA8, R16F, RG16F, RGBA16F, R32F, RG32F, RGBA32F, BC1, BC3, BC4, BC5, BC7, Count
};
enum class ColorSpace : uint8_t { Linear, Srgb, Count };
enum class Swizzle : uint8_t { R, G, B, A, Zero, One, Count };
enum class MinFilter : uint8_t { Nearest, Linear, NearestMipNearest, LinearMipNearest, NearestMipLinear, LinearMipLinear, Count };
enum class MagFilter : uint8_t { Nearest, Linear, Count };
enum class Wrap : uint8_t { Repeat, MirroredRepeat, ClampToEdge, Count };
struct TextureDesc {
    StringRef name = kNone;
    TextureDimension dimension = TextureDimension::Tex2D;
    TextureFormat format = TextureFormat::RGBA8;
    ColorSpace colorSpace = ColorSpace::Linear;
    std::array<Swizzle, 4> swizzle{Swizzle::R, Swizzle::G, Swizzle::B, Swizzle::A}; // sampled rgba
    uint32_t width = 0, height = 0; // level 0, texels
    uint32_t layers = 1;            // 1 for Tex2D, 6 for Cube (faces +X -X +Y -Y +Z -Z)
    uint32_t mipCount = 1;
    MinFilter minFilter = MinFilter::LinearMipLinear;
    MagFilter magFilter = MagFilter::Linear;
    Wrap wrapU = Wrap::Repeat, wrapV = Wrap::Repeat;
    template <class V> void fields(V& v) {
        v(name); v(dimension); v(format); v(colorSpace); v(swizzle); v(width); v(height);
        v(layers); v(mipCount); v(minFilter); v(magFilter); v(wrapU); v(wrapV);
    }
};

// Bytes of one mip level of all layers: block formats round up to 4x4 blocks.
uint64_t textureLevelSizeBytes(TextureFormat format, uint32_t width, uint32_t height,
                               uint32_t layers);

// [SECTION] TMIP — one mip level of one texture (all layers), stored smallest level first
struct TextureMip {
    uint32_t texture = 0; // index of the TEXR chunk
    uint32_t level = 0;   // 0 = full resolution
    uint32_t width = 0, height = 0;
    Blob data; // textureLevelSizeBytes(format, width, height, layers) bytes, rows bottom-up as GL
    template <class V> void fields(V& v) { v(texture); v(level); v(width); v(height); v(data); }
};

// [SECTION] MATL — one material: glTF PBR metallic-roughness plus its place in the pipeline
enum class AlphaMode : uint8_t { Opaque, Mask, Blend, Count };
enum class ShadingPath : uint8_t { Deferred, Forward, Count };
enum class TextureSlotKind : uint8_t { BaseColor, MetallicRoughness, Normal, Occlusion, Emissive, Count };
struct TextureSlot {
    uint32_t texture = kNone; // index of a TEXR chunk, or kNone
    uint8_t texCoord = 0;     // which TexCoord stream
    Vec2 offset{0, 0}, scale{1, 1}; // KHR_texture_transform
    float rotationRadians = 0;
    template <class V> void fields(V& v) { v(texture); v(texCoord); v(offset); v(scale); v(rotationRadians); }
};
struct Material {
    StringRef name = kNone;
    uint32_t program = kNone; // index of a PROG chunk
    Vec4 baseColorFactor{1, 1, 1, 1}; // linear RGBA
    Vec3 emissiveFactor{0, 0, 0};
    float emissiveStrength = 1;
    float metallicFactor = 1, roughnessFactor = 1;
    float normalScale = 1, occlusionStrength = 1;
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;
    ShadingPath shadingPath = ShadingPath::Deferred;
    uint16_t layerPriority = 0; // deferred layers draw in ascending priority
    bool doubleSided = false, castsShadows = true, receivesShadows = true;
    std::array<TextureSlot, size_t(TextureSlotKind::Count)> textures{};
    // Version 2. KHR_materials_unlit: the surface shows its base colour (plus emissive) as it
    // is, with no light, shadow or environment. Writers set the chunk's critical bit when true:
    // a version-1 reader would shade it lit.
    bool unlit = false;
    template <class V> void fields(V& v) {
        v(name); v(program); v(baseColorFactor); v(emissiveFactor); v(emissiveStrength);
        v(metallicFactor); v(roughnessFactor); v(normalScale); v(occlusionStrength);
        v(alphaMode); v(alphaCutoff); v(shadingPath); v(layerPriority); v(doubleSided);
        v(castsShadows); v(receivesShadows); v(textures);
        v(SinceVersion{2}); v(unlit);
    }
};

// [SECTION] MESH — one mesh: separate (non-interleaved) vertex streams, indices, sub-meshes
enum class Primitive : uint8_t { Triangles, Lines, Points, Count };
enum class IndexType : uint8_t { U16, U32, Count };
enum class VertexSemantic : uint8_t { Position, Normal, Tangent, TexCoord0, TexCoord1, Color0, Joints0, Weights0, Count };
enum class ComponentType : uint8_t { F32, F16, I8, U8, I16, U16, I32, U32, Count };
enum class VertexEncoding : uint8_t {
    Plain,      // components as stored (after normalisation, if normalized)
    Octahedral, // 2 components: an octahedron-mapped unit vector (normals, tangents' xyz)
    Count
};
struct VertexStream {
    VertexSemantic semantic = VertexSemantic::Position;
    ComponentType componentType = ComponentType::F32;
    uint8_t componentCount = 3; // 1..4
    bool normalized = false;    // integer types map to [0,1] (unsigned) or [-1,1] (signed)
    VertexEncoding encoding = VertexEncoding::Plain;
    // Quantised data: value = stored * dequantScale + dequantOffset (per component x,y,z).
    Vec3 dequantScale{1, 1, 1}, dequantOffset{0, 0, 0};
    Blob data; // vertexCount elements, tightly packed
    template <class V> void fields(V& v) {
        v(semantic); v(componentType); v(componentCount); v(normalized); v(encoding);
        v(dequantScale); v(dequantOffset); v(data);
    }
};
struct Submesh {
    uint32_t material = kNone; // index of a MATL chunk
    uint32_t firstIndex = 0, indexCount = 0;
    uint8_t lod = 0;            // level of detail, 0 = full
    float lodError = 0;         // simplification error of this level, in mesh units
    Aabb bounds;
    template <class V> void fields(V& v) { v(material); v(firstIndex); v(indexCount); v(lod); v(lodError); v(bounds); }
};
struct Mesh {
    StringRef name = kNone;
    Primitive primitive = Primitive::Triangles;
    IndexType indexType = IndexType::U32;
    uint32_t vertexCount = 0;
    std::vector<VertexStream> streams; // only the attributes the materials use
    Blob indices;                      // all sub-meshes and LODs
    std::vector<Submesh> submeshes;
    Aabb bounds;
    Sphere boundingSphere;
    template <class V> void fields(V& v) {
        v(name); v(primitive); v(indexType); v(vertexCount); v(streams); v(indices);
        v(submeshes); v(bounds); v(boundingSphere);
    }
};
// MDET: the full-detail mesh that replaces mesh `mesh`, whose MESH chunk is then a coarse proxy
// (docs/FORMAT.md "MDET"): with the same level-0 submeshes by material, so every draw item of
// the proxy is one of the detail.
struct MeshDetail {
    uint32_t mesh = 0;
    Mesh detail;
    template <class V> void fields(V& v) { v(mesh); v(detail); }
};
// [SECTION] MRPH — one mesh's morph targets (docs/FORMAT.md "MRPH")
// The mesh's shape at weights w is base + sum_k w_k * delta_k, for each attribute a target moves.
// Only the attributes the mesh's materials read are kept: Position always, Normal and Tangent
// where the mesh has those streams. Every delta stream is F32 x 3, Plain, vertexCount long.
inline constexpr uint32_t kMaxMorphTargets = 256;
struct MorphTarget {
    StringRef name = kNone;
    std::vector<VertexStream> deltas; // semantics Position, Normal, Tangent, each at most once
    template <class V> void fields(V& v) { v(name); v(deltas); }
};
struct MorphTargets {
    uint32_t mesh = 0;            // the MESH these targets move (no MDET may replace it)
    std::vector<float> weights;   // the default weights, one per target, finite
    std::vector<MorphTarget> targets;
    template <class V> void fields(V& v) { v(mesh); v(weights); v(targets); }
};

uint32_t componentSizeBytes(ComponentType t);
// The mesh's index count, and index k (U16 or U32, little-endian; precondition k < the count).
size_t meshIndexCount(const Mesh& mesh);
uint32_t meshIndex(const Mesh& mesh, size_t k);

// [SECTION] LGHT — all lights (placed by nodes; a light shines down its node's -Z)
enum class LightType : uint8_t { Directional, Point, Spot, Count };
// The most lights a LGHT chunk may hold (validateScene refuses more; docs/FORMAT.md "LGHT"). The
// player keeps one bit per light in each screen tile's light mask, so this bounds that memory:
// 65536 bits = 8 KiB per tile, whatever a file declares.
inline constexpr uint32_t kMaxLights = 65536;
// The widest spot cone: pi/2 rounded to float (1.5707964f, a hair above pi/2, so a cone of
// exactly pi/2 as glTF writes it passes). A spot's cone angles satisfy
// 0 <= innerConeRadians <= outerConeRadians <= kMaxSpotConeRadians.
inline constexpr float kMaxSpotConeRadians = 1.5707964f;
// The most light one light may give: intensity x its brightest colour channel (lux for a sun,
// candela otherwise). 1e10 is 10^5 times the noon sun and 10^3 times a stadium floodlight, and
// keeps a renderer's sums finite in float: x 10^4 at the 1 cm closest distance, x the BRDF's peak,
// x kMaxLights stays far below FLT_MAX (3.4e38), where FLT_MAX x FLT_MAX gave infinities and NaN.
inline constexpr float kMaxLightOutput = 1e10f;
// The largest texture edge every OpenGL 4.5 GPU takes (the minimum GL_MAX_TEXTURE_SIZE the
// standard guarantees): pnb-convert writes no larger texture unless --max-texture-size asks for
// one; a player meets a larger one by starting at a smaller mip level.
inline constexpr uint32_t kMaxPortableTextureSize = 16384;
struct Light {
    StringRef name = kNone;
    LightType type = LightType::Directional;
    Vec3 color{1, 1, 1}; // linear RGB, each channel finite and >= 0
    float intensity = 1; // lux (directional) or candela (point, spot), as KHR_lights_punctual;
                         // finite, >= 0
    float range = 0;     // metres, finite, >= 0; 0 = unlimited (readers then bound it with
                         // effectiveLightRange, pnb/light_range.h); pnb-convert writes > 0 for
                         // every point and spot light that gives light
    float innerConeRadians = 0, outerConeRadians = 0.7853982f;
    bool castsShadows = true;
    bool generated = false; // added by the converter (e.g. the default sun), not in the source
    template <class V> void fields(V& v) {
        v(name); v(type); v(color); v(intensity); v(range); v(innerConeRadians);
        v(outerConeRadians); v(castsShadows); v(generated);
    }
};
struct LightList {
    std::vector<Light> lights;
    template <class V> void fields(V& v) { v(lights); }
};

// [SECTION] CAMR — all cameras (placed by nodes; a camera looks down its node's -Z)
enum class Projection : uint8_t { Perspective, Orthographic, Count };
struct Camera {
    StringRef name = kNone;
    Projection projection = Projection::Perspective;
    float yfovRadians = 0.8f;
    float aspectRatio = 0; // 0 = the viewport's
    float znear = 0.1f;
    float zfar = 0; // 0 = infinite (reversed-Z)
    float xmag = 1, ymag = 1; // orthographic half extents
    template <class V> void fields(V& v) { v(name); v(projection); v(yfovRadians); v(aspectRatio); v(znear); v(zfar); v(xmag); v(ymag); }
};
struct CameraList {
    std::vector<Camera> cameras;
    template <class V> void fields(V& v) { v(cameras); }
};

// [SECTION] NODE — the node graph; parents precede children
struct Node {
    StringRef name = kNone;
    uint32_t parent = kNone; // index of an earlier node, or kNone for a root
    Vec3 translation{0, 0, 0};
    Vec4 rotation{0, 0, 0, 1}; // unit quaternion xyzw
    Vec3 scale{1, 1, 1};
    uint32_t mesh = kNone, light = kNone, camera = kNone; // MESH chunk / LGHT / CAMR index
    Aabb worldBounds;   // of this node's mesh instance, world space; empty if none
    Sphere worldSphere; // the same instance's bounding sphere, world space; radius 0 if none
    template <class V> void fields(V& v) {
        v(name); v(parent); v(translation); v(rotation); v(scale); v(mesh); v(light); v(camera);
        v(worldBounds); v(worldSphere);
    }
};
// NODE version 2: the copies of one node's mesh (EXT_mesh_gpu_instancing). Copy k is placed at
// world(node) * T_k * R_k * S_k; the node itself then draws no copy of its own. The node's
// worldBounds and worldSphere cover every copy.
struct InstanceTransform {
    Vec3 translation{0, 0, 0};
    Vec4 rotation{0, 0, 0, 1}; // unit quaternion xyzw
    Vec3 scale{1, 1, 1};
    template <class V> void fields(V& v) { v(translation); v(rotation); v(scale); }
};
struct NodeInstances {
    uint32_t node = 0; // a node with a mesh; each node at most once, in increasing node order
    std::vector<InstanceTransform> transforms; // at least one
    template <class V> void fields(V& v) { v(node); v(transforms); }
};
struct NodeGraph {
    std::vector<Node> nodes;
    // Version 2 (default: none). Writers set the critical bit when it is not empty: a version-1
    // reader would draw one copy where the file has many.
    std::vector<NodeInstances> instances;
    template <class V> void fields(V& v) { v(nodes); v(SinceVersion{2}); v(instances); }
};

// [SECTION] SKIN — one skin: the joints that deform the meshes of some nodes (FORMAT.md "SKIN")
// A skinned vertex is at sum_i w_i * J[j_i] * v in its node's space, with the joint matrix
// J[k] = inverse(world(node)) * world(joints[k]) * inverseBindMatrices[k]; j_i and w_i are its
// Joints0 and Weights0 streams.
inline constexpr uint32_t kMaxJoints = 1024;
struct Skin {
    StringRef name = kNone;
    std::vector<uint32_t> joints;                          // node indices, at least one
    std::vector<std::array<float, 16>> inverseBindMatrices; // one per joint, column-major
    std::vector<uint32_t> nodes; // the nodes whose mesh this skin deforms (each in one skin)
    template <class V> void fields(V& v) { v(name); v(joints); v(inverseBindMatrices); v(nodes); }
};

// [SECTION] ANIM — one animation clip: keyframed node properties (FORMAT.md "ANIM")
enum class AnimatedProperty : uint8_t { Translation, Rotation, Scale, Weights, Count };
enum class KeyInterpolation : uint8_t { Step, Linear, CubicSpline, Count };
struct AnimationChannel {
    uint32_t node = 0;
    AnimatedProperty property = AnimatedProperty::Translation;
    KeyInterpolation interpolation = KeyInterpolation::Linear;
    std::vector<float> times;  // seconds, finite, strictly increasing, at least one key
    // Per key: width floats (3 translation/scale, 4 rotation xyzw, the target count for
    // weights); CubicSpline stores in-tangent, value, out-tangent per key (3 x width).
    std::vector<float> values;
    template <class V> void fields(V& v) { v(node); v(property); v(interpolation); v(times); v(values); }
};
struct Animation {
    StringRef name = kNone;
    std::vector<AnimationChannel> channels; // each (node, property) at most once
    template <class V> void fields(V& v) { v(name); v(channels); }
};

// [SECTION] PATH — one camera path (fly-through)
enum class Interpolation : uint8_t { Linear, CatmullRom, Count };
struct CameraKey {
    float timeSeconds = 0; // strictly increasing
    Vec3 position;         // world space
    Vec4 rotation{0, 0, 0, 1};
    float yfovRadians = 0.8f;
    template <class V> void fields(V& v) { v(timeSeconds); v(position); v(rotation); v(yfovRadians); }
};
struct CameraPath {
    StringRef name = kNone;
    Interpolation interpolation = Interpolation::CatmullRom;
    bool loop = false;
    std::vector<CameraKey> keys;
    template <class V> void fields(V& v) { v(name); v(interpolation); v(loop); v(keys); }
};

// [SECTION] ENVM — the environment: light from the sky (image-based lighting) and the background
// (docs/FORMAT.md "ENVM"). Everything the player needs is precomputed: it samples, never filters.
enum class EnvironmentSource : uint8_t { Image, AnalyticSky, Count };
struct Environment {
    StringRef name = kNone;  // the image's file name, or the sky model ("preetham")
    EnvironmentSource source = EnvironmentSource::Image;
    uint32_t radiance = kNone; // TEXR: 2D equirectangular radiance in nits (linear), with mips
    uint32_t specular = kNone; // TEXR: cube of GGX-prefiltered radiance, level m at roughness
                               // m / (mipCount - 1); kNone = no specular term
    uint32_t brdfLut = kNone;  // TEXR: 2D split-sum scale and bias (A, B) at (NdotV, roughness)
    // Irradiance E(n) = sum_i irradiance[i] * Y_i(n) (lux), the 9 real SH basis functions of
    // FORMAT.md, already convolved with the clamped cosine and windowed (never negative).
    std::array<Vec3, 9> irradianceSh{};
    // AnalyticSky only (else zero): what the sky was computed from, so that a reader can redo it.
    Vec3 sunDirection{0, 0, 0}; // unit, towards the sun
    float turbidity = 0;
    Vec3 groundAlbedo{0, 0, 0};
    float sunIlluminance = 0;   // lux, the scene's sun light
    // Version 2 (appended; a version-1 chunk reads as false): the converter made this
    // environment up (its neutral default, for a source with no lights and no environment),
    // it is not the source's. Like Light::generated.
    bool generated = false;
    template <class V> void fields(V& v) {
        v(name); v(source); v(radiance); v(specular); v(brdfLut); v(irradianceSh);
        v(sunDirection); v(turbidity); v(groundAlbedo); v(sunIlluminance);
        v(SinceVersion{2}); v(generated);
    }
};

// [SECTION] chunk traits and codecs

// Tag, current payload version and default compression of each chunk struct.
template <class T> struct ChunkTraits;
#define PNB_CHUNK_TRAITS_V(Type, TagValue, Compress, Version)                                      \
    template <> struct ChunkTraits<Type> {                                                         \
        static constexpr Tag tag = TagValue;                                                       \
        static constexpr uint16_t version = Version;                                               \
        static constexpr Compression compression = Compress;                                       \
    }
#define PNB_CHUNK_TRAITS(Type, TagValue, Compress) PNB_CHUNK_TRAITS_V(Type, TagValue, Compress, 1)
// Bulk data (mesh streams, texels) defaults to uncompressed so it can be used in place from the
// mapping; small structured chunks compress well and are read once.
PNB_CHUNK_TRAITS(StringTable, tags::kStrings, Compression::Zstd);
PNB_CHUNK_TRAITS(SceneInfo, tags::kSceneInfo, Compression::None);
PNB_CHUNK_TRAITS(RenderSettings, tags::kRenderSettings, Compression::None);
PNB_CHUNK_TRAITS(ShaderSource, tags::kShader, Compression::Zstd);
PNB_CHUNK_TRAITS(Program, tags::kProgram, Compression::None);
PNB_CHUNK_TRAITS(TextureDesc, tags::kTexture, Compression::None);
PNB_CHUNK_TRAITS_V(Material, tags::kMaterial, Compression::None, 2); // 2: `unlit`
PNB_CHUNK_TRAITS(Mesh, tags::kMesh, Compression::None);
PNB_CHUNK_TRAITS(MorphTargets, tags::kMorphTargets, Compression::None);
PNB_CHUNK_TRAITS(LightList, tags::kLights, Compression::None);
PNB_CHUNK_TRAITS(CameraList, tags::kCameras, Compression::None);
PNB_CHUNK_TRAITS_V(NodeGraph, tags::kNodes, Compression::Zstd, 2); // 2: `instances`
PNB_CHUNK_TRAITS(Skin, tags::kSkin, Compression::Zstd);
PNB_CHUNK_TRAITS(Animation, tags::kAnimation, Compression::Zstd);
PNB_CHUNK_TRAITS(CameraPath, tags::kCameraPath, Compression::None);
PNB_CHUNK_TRAITS(TextureMip, tags::kTextureMip, Compression::None);
PNB_CHUNK_TRAITS(MeshDetail, tags::kMeshDetail, Compression::None);
PNB_CHUNK_TRAITS_V(Environment, tags::kEnvironment, Compression::None, 2); // 2: `generated`
#undef PNB_CHUNK_TRAITS
#undef PNB_CHUNK_TRAITS_V

// Encodes a chunk payload (deterministic: equal structs give equal bytes; blob padding is zero).
template <class T> std::vector<std::byte> encodeChunk(const T& value);
// Decodes a payload written as chunk `header` (its version and flags). A newer version than this
// reader's is read by the fields this reader knows; the bytes after them are the newer version's
// appended fields and are ignored (FORMAT.md 3.5) — unless the chunk is critical. Errors:
// UnsupportedChunkVersion (version 0, or newer and critical), BadPayload (truncated field, enum
// out of range, bool not 0/1, padding not zero, bytes left over in a version this reader knows).
// `offset` is the payload's position in the file, for messages.
template <class T>
Result<T> decodeChunk(std::span<const std::byte> payload, const ChunkHeader& header,
                      uint64_t offset = 0);
// Encodes and appends a chunk with its traits' tag and version.
template <class T>
Status writeChunk(Writer& writer, const T& value, Compression compression = ChunkTraits<T>::compression);

} // namespace pnb
