// pnb/scene.h — a whole container decoded into typed chunks, written back in streamable order,
// and checked for cross-references (docs/FORMAT.md §4.1 and §4.3).
//
// Does NOT do: GPU upload (player), importing (converter). Progressive loading feeds chunks from
// streamChunks() to a SceneAssembler and handles the texels (TMIP) itself, one at a time.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/reader.h"

namespace pnb {

class Writer;

// Every chunk of a container, decoded. Blobs and strings point into `payloads` (or, for a
// Scene built by hand for writing, into the caller's memory).
struct Scene {
    StringTable strings;
    SceneInfo info;
    RenderSettings settings;
    std::vector<ShaderSource> shaders;
    std::vector<Program> programs;
    std::vector<TextureDesc> textures;
    std::vector<Material> materials;
    std::vector<Mesh> meshes;
    std::vector<MorphTargets> morphTargets; // MRPH: at most one per mesh
    LightList lights;
    CameraList cameras;
    NodeGraph nodes;
    std::vector<Skin> skins;           // SKIN
    std::vector<Animation> animations; // ANIM: the clips
    std::vector<CameraPath> cameraPaths;
    std::optional<Environment> environment; // ENVM: sky light and background, if the scene has one
    std::vector<TextureMip> textureMips;
    std::vector<MeshDetail> meshDetails; // MDET: full detail for meshes whose MESH is a proxy

    std::vector<Payload> payloads; // storage of decoded chunks (owned or views of the mapping)
    uint32_t unknownChunks = 0;    // chunks with tags this reader does not know (skipped)
    uint32_t newerChunks = 0;      // chunks of a newer version, read by the fields known here

    // The string a StringRef names; "" for kNone. Precondition: validateScene passed.
    std::string_view str(StringRef ref) const {
        return ref == kNone ? std::string_view{} : strings.strings[ref];
    }
};

// Builds a Scene from chunks handed over one at a time in file order (from a mapping or from
// streamChunks): the order rules of FORMAT.md §4.1 (every reference points backwards; single
// kinds at most once; STRS first), then the chunk's decoding. readScene is this over a whole
// container; a streaming reader uses it for everything before the texels and checks each TMIP
// with checkOrder + validateTextureMip instead of keeping it.
class SceneAssembler {
public:
    // Whether `info` may come next; records it as seen. Unknown tags are counted (or refused if
    // critical). Errors name the chunk's sequence number, tag and header offset.
    Status checkOrder(const ChunkInfo& info);
    // Decodes `payload` (the raw payload of `info`, which passed checkOrder) into the scene,
    // which keeps the payload (its blobs and strings point into it). Unknown tags are skipped.
    Status decode(const ChunkInfo& info, Payload payload);
    Status add(const ChunkInfo& info, Payload payload) { // checkOrder, then decode
        Status st = checkOrder(info);
        return isOk(st) ? decode(info, std::move(payload)) : st;
    }
    // The progressive section's own order rule (FORMAT.md §4.1): no MDET after a texel level
    // other than its texture's smallest (so a streaming reader that has seen such a level knows
    // every mesh detail has come). `mip`: the decoded TMIP, null for an MDET. decode() applies it;
    // a streaming reader that decodes those chunks itself calls it.
    Status checkProgressive(const ChunkInfo& info, const TextureMip* mip);
    bool largerTexelsSeen() const { return mLargerTexels; }
    // The string table was seen. (validateScene is the caller's: it may run on a prefix.)
    Status finish() const;
    Scene scene;

private:
    int mLastRank = -1;
    bool mSeen[24] = {};
    bool mLargerTexels = false;
};

// Decodes every chunk. Checks the chunk order of FORMAT.md §4.1 (which makes every reference
// point backwards), that single-instance chunks appear at most once, then validateScene().
// Unknown tags are skipped and counted.
Result<Scene> readScene(const Container& container);

// The mesh to draw at full detail: mesh `index`'s MDET detail if the scene has one, else the
// MESH itself. (A streaming reader draws the MESH, the proxy, until the MDET arrives.)
const Mesh& fullDetailMesh(const Scene& scene, uint32_t index);

// Checks one MDET chunk: its mesh index, the detail mesh as a mesh (§4.4), and that its level-0
// submeshes are the proxy's by material (the same count of each material, in the same order);
// `index` names it in the error. validateScene checks every one and that no mesh has two.
Status validateMeshDetail(const Scene& scene, const MeshDetail& detail, size_t index);

// Checks one texel chunk against its descriptor (texture index, level, size), as validateScene
// does for each of scene.textureMips; `index` names it in the error.
Status validateTextureMip(const Scene& scene, const TextureMip& mip, size_t index);

// Checks the ENVM chunk: its name, its textures (dimension, a linear float format, the cube and
// the BRDF table both or neither) and that every number is finite.
Status validateEnvironment(const Scene& scene, const Environment& environment);

// Checks one light's values against their domains (docs/FORMAT.md "LGHT"): a known type; colour
// finite and >= 0; intensity finite and >= 0; intensity x brightest colour channel at most
// kMaxLightOutput; range finite and >= 0; for a spot,
// 0 <= inner <= outer <= pi/2 (kMaxSpotConeRadians). Errors (BadPayload) name LGHT and `index`.
Status validateLight(const Light& light, size_t index);

// The animation chunks' rules (FORMAT.md "MRPH", "SKIN", "ANIM"; animation_rules.cpp), which
// validateScene applies: indices, stream formats the deforming pass reads, joint indices below the
// joint count, finite keys, strictly increasing times, value counts matching the property.
Status validateMorphTargets(const Scene& scene, const MorphTargets& targets, size_t index);
Status validateSkin(const Scene& scene, const Skin& skin, size_t index);
Status validateAnimation(const Scene& scene, const Animation& clip, size_t index);
// All of them, and that no mesh has two MRPH and no node two skins.
Status validateAnimationChunks(const Scene& scene);

// Checks every cross-reference of §4.3: string, shader, program, texture, material, mesh,
// light, camera and parent indices; mip levels and sizes; stream sizes; index values; the
// environment's textures (shape and format) and finite irradiance; at most kMaxLights lights
// (LimitExceeded), each as validateLight.
// `offset` in errors is 0 (the error names the chunk kind and index instead).
Status validateScene(const Scene& scene);

// Appends all chunks of `scene` to `writer` in the order of §4.1 (it does not commit).
// Textures' mips are written smallest level first, so something can be shown early. Small
// structured chunks use their ChunkTraits compression; bulk chunks (MESH, TMIP) use `bulk`
// (default None, so they load zero-copy from a mapping).
Status writeScene(Writer& writer, const Scene& scene, Compression bulk = Compression::None);

} // namespace pnb
