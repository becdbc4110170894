// Whole-container decode, ordered write and cross-reference validation.

#include "pnb/scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "bytes.h"
#include "pnb/writer.h"

namespace pnb {

namespace {


bool isSingleton(Tag t) {
    return t == tags::kStrings || t == tags::kSceneInfo || t == tags::kRenderSettings ||
           t == tags::kLights || t == tags::kCameras || t == tags::kNodes || t == tags::kEnvironment;
}

template <class T> Status decodeInto(const ChunkInfo& info, Payload payload, Scene& s, T& out) {
    auto value = decodeChunk<T>(payload.bytes(), info.header, info.payloadOffset);
    if (!value) return value.error();
    if (info.header.version > ChunkTraits<T>::version) ++s.newerChunks;
    out = std::move(*value);
    s.payloads.push_back(std::move(payload));
    return {};
}

template <class T>
Status decodeAppend(const ChunkInfo& info, Payload payload, Scene& s, std::vector<T>& out) {
    out.emplace_back();
    return decodeInto(info, std::move(payload), s, out.back());
}

Error refError(const char* what, size_t index, const char* field, uint64_t value, size_t count) {
    return makeError(FormatError::BadReference, 0, "%s %zu: %s = %llu, but there are %zu", what,
                     index, field, (unsigned long long)value, count);
}

bool refOk(uint32_t ref, size_t count) { return ref == kNone || ref < count; }

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const Vec4& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w); }

} // namespace

Status SceneAssembler::checkOrder(const ChunkInfo& info) {
    const Tag tag = info.header.tag;
    const int rank = streamOrderRank(tag);
    if (rank < 0) {
        if (info.header.flags & kChunkCritical)
            return makeError(FormatError::UnsupportedChunkVersion, info.headerOffset,
                             "chunk %u '%s' is critical and unknown to this reader: update "
                             "Penumbra to read it",
                             info.header.sequence, tag.str().c_str());
        ++scene.unknownChunks;
        return {};
    }
    if (rank < mLastRank)
        return makeError(FormatError::BadReference, info.headerOffset,
                         "chunk %u '%s' is out of order (FORMAT.md 4.1)", info.header.sequence,
                         tag.str().c_str());
    if (mLastRank < 0 && !(tag == tags::kStrings))
        return makeError(FormatError::Missing, info.headerOffset,
                         "the first chunk must be the string table STRS");
    if (isSingleton(tag) && mSeen[rank])
        return makeError(FormatError::BadReference, info.headerOffset,
                         "second '%s' chunk; only one is allowed", tag.str().c_str());
    mSeen[rank] = true;
    mLastRank = rank;
    return {};
}

Status SceneAssembler::decode(const ChunkInfo& info, Payload payload) {
    const Tag tag = info.header.tag;
    Scene& s = scene;
    Payload p = std::move(payload);
    if (tag == tags::kStrings) return decodeInto(info, std::move(p), s, s.strings);
    if (tag == tags::kSceneInfo) return decodeInto(info, std::move(p), s, s.info);
    if (tag == tags::kRenderSettings) return decodeInto(info, std::move(p), s, s.settings);
    if (tag == tags::kShader) return decodeAppend(info, std::move(p), s, s.shaders);
    if (tag == tags::kProgram) return decodeAppend(info, std::move(p), s, s.programs);
    if (tag == tags::kTexture) return decodeAppend(info, std::move(p), s, s.textures);
    if (tag == tags::kMaterial) return decodeAppend(info, std::move(p), s, s.materials);
    if (tag == tags::kMesh) return decodeAppend(info, std::move(p), s, s.meshes);
    if (tag == tags::kMorphTargets) return decodeAppend(info, std::move(p), s, s.morphTargets);
    if (tag == tags::kSkin) return decodeAppend(info, std::move(p), s, s.skins);
    if (tag == tags::kAnimation) return decodeAppend(info, std::move(p), s, s.animations);
    if (tag == tags::kLights) return decodeInto(info, std::move(p), s, s.lights);
    if (tag == tags::kCameras) return decodeInto(info, std::move(p), s, s.cameras);
    if (tag == tags::kNodes) return decodeInto(info, std::move(p), s, s.nodes);
    if (tag == tags::kCameraPath) return decodeAppend(info, std::move(p), s, s.cameraPaths);
    if (tag == tags::kEnvironment) return decodeInto(info, std::move(p), s, s.environment.emplace());
    if (tag == tags::kTextureMip) {
        Status st = decodeAppend(info, std::move(p), s, s.textureMips);
        return isOk(st) ? checkProgressive(info, &s.textureMips.back()) : st;
    }
    if (tag == tags::kMeshDetail) {
        Status st = checkProgressive(info, nullptr);
        return isOk(st) ? decodeAppend(info, std::move(p), s, s.meshDetails) : st;
    }
    return {}; // unknown (counted by checkOrder)
}

Status SceneAssembler::checkProgressive(const ChunkInfo& info, const TextureMip* mip) {
    if (!mip) {
        if (mLargerTexels)
            return makeError(FormatError::BadReference, info.headerOffset,
                             "chunk %u 'MDET' comes after a texel level larger than its texture's "
                             "smallest (FORMAT.md 4.1)",
                             info.header.sequence);
        return {};
    }
    if (mip->texture < scene.textures.size() && mip->level + 1 < scene.textures[mip->texture].mipCount)
        mLargerTexels = true;
    return {};
}

Status SceneAssembler::finish() const {
    if (!mSeen[0]) return makeError(FormatError::Missing, 0, "no string table (STRS) chunk");
    return {};
}

Result<Scene> readScene(const Container& container) {
    SceneAssembler assembler;
    for (const ChunkInfo& info : container.chunks()) {
        if (Status st = assembler.checkOrder(info); !isOk(st)) return st;
        if (streamOrderRank(info.header.tag) < 0) continue; // unknown: not even loaded
        auto payload = container.load(info);
        if (!payload) return payload.error();
        // Decoding reads the mapping itself (an uncompressed payload is a view into it): a file
        // cut short meanwhile reads as zeros there, so its truncation is the error to report.
        if (Status st = assembler.decode(info, std::move(*payload)); !isOk(st)) {
            if (Status cut = container.intact(); !isOk(cut)) return cut;
            return st;
        }
    }
    if (Status st = assembler.finish(); !isOk(st)) return st;
    if (Status st = validateScene(assembler.scene); !isOk(st)) return st;
    return std::move(assembler.scene);
}

// One mesh record (a MESH chunk, or an MDET's detail): §4.4's mesh rules. `what` and `i` name it.
Status validateMesh(const Scene& s, const Mesh& m, const char* what, size_t i) {
    if (!refOk(m.name, s.strings.strings.size()))
        return refError(what, i, "name", m.name, s.strings.strings.size());
    for (const VertexStream& vs : m.streams) {
        uint64_t expect = uint64_t(m.vertexCount) * componentSizeBytes(vs.componentType) *
                          vs.componentCount;
        if (vs.componentCount < 1 || vs.componentCount > 4 || vs.data.size() != expect)
            return makeError(FormatError::BadReference, 0,
                             "%s %zu: stream %u holds %zu bytes, %u vertices of %u x %u "
                             "need %llu",
                             what, i, unsigned(vs.semantic), vs.data.size(), m.vertexCount,
                             vs.componentCount, componentSizeBytes(vs.componentType),
                             (unsigned long long)expect);
    }
    const size_t indexSize = m.indexType == IndexType::U16 ? 2 : 4;
    if (m.indices.size() % indexSize != 0)
        return makeError(FormatError::BadReference, 0,
                         "%s %zu: index data is not a whole number of indices", what, i);
    const size_t indexCount = meshIndexCount(m);
    for (size_t k = 0; k < indexCount; ++k) {
        uint32_t v = meshIndex(m, k);
        if (v >= m.vertexCount)
            return makeError(FormatError::BadReference, 0,
                             "%s %zu: index %zu = %u, but there are %u vertices", what, i, k, v,
                             m.vertexCount);
    }
    for (size_t k = 0; k < m.submeshes.size(); ++k) {
        const Submesh& sm = m.submeshes[k];
        if (!refOk(sm.material, s.materials.size()))
            return refError("submesh", k, "material", sm.material, s.materials.size());
        if (uint64_t(sm.firstIndex) + sm.indexCount > indexCount)
            return makeError(FormatError::BadReference, 0,
                             "%s %zu submesh %zu: indices %u..%u, the mesh has %zu", what, i, k,
                             sm.firstIndex, sm.firstIndex + sm.indexCount, indexCount);
    }
    return {};
}

Status validateLight(const Light& l, size_t i) {
    // Each rule keeps a value a renderer would turn into NaN or infinity, or a cone its falloff
    // (smoothstep between cos outer and cos inner) cannot describe, out of the lighting.
    if (l.type >= LightType::Count)
        return makeError(FormatError::BadPayload, 0, "LGHT light %zu: unknown type %u", i, unsigned(l.type));
    if (!finite(l.color) || !(l.color.x >= 0 && l.color.y >= 0 && l.color.z >= 0))
        return makeError(FormatError::BadPayload, 0,
                         "LGHT light %zu: colour (%g, %g, %g) is not finite and >= 0", i,
                         double(l.color.x), double(l.color.y), double(l.color.z));
    if (!std::isfinite(l.intensity) || !(l.intensity >= 0))
        return makeError(FormatError::BadPayload, 0, "LGHT light %zu: intensity %g is not finite and >= 0",
                         i, double(l.intensity));
    if (const double output = double(l.intensity) * std::max({double(l.color.x),
                                                               double(l.color.y), double(l.color.z)});
        !(output <= double(kMaxLightOutput)))
        return makeError(FormatError::BadPayload, 0,
                         "LGHT light %zu: intensity %g x brightest colour channel = %g exceeds "
                         "%g, the most a light may give (kMaxLightOutput)",
                         i, double(l.intensity), output, double(kMaxLightOutput));
    if (!std::isfinite(l.range) || !(l.range >= 0))
        return makeError(FormatError::BadPayload, 0,
                         "LGHT light %zu: range %g is not finite and >= 0 (0 means unlimited)", i,
                         double(l.range));
    if (l.type == LightType::Spot &&
        !(l.innerConeRadians >= 0 && l.innerConeRadians <= l.outerConeRadians &&
          l.outerConeRadians <= kMaxSpotConeRadians))
        return makeError(FormatError::BadPayload, 0,
                         "LGHT light %zu: spot cone angles inner %g, outer %g are not 0 <= inner <= "
                         "outer <= pi/2",
                         i, double(l.innerConeRadians), double(l.outerConeRadians));
    return {};
}

Status validateScene(const Scene& s) {
    const size_t nStr = s.strings.strings.size();
    auto str = [&](const char* what, size_t i, const char* field, StringRef r) -> Status {
        if (refOk(r, nStr)) return {};
        return refError(what, i, field, r, nStr);
    };
#define PNB_CHECK(expr)                                                                            \
    do {                                                                                           \
        if (Status st_ = (expr); !isOk(st_)) return st_;                                           \
    } while (0)

    PNB_CHECK(str("scene info", 0, "name", s.info.name));
    PNB_CHECK(str("scene info", 0, "generator", s.info.generator));
    PNB_CHECK(str("scene info", 0, "source", s.info.source));
    for (size_t i = 0; i < s.settings.entries.size(); ++i) {
        PNB_CHECK(str("setting", i, "key", s.settings.entries[i].key));
        PNB_CHECK(str("setting", i, "value", s.settings.entries[i].value));
        if (s.settings.entries[i].key == kNone)
            return makeError(FormatError::BadReference, 0, "setting %zu has no key", i);
    }
    for (size_t i = 0; i < s.shaders.size(); ++i) PNB_CHECK(str("shader", i, "name", s.shaders[i].name));
    for (size_t i = 0; i < s.programs.size(); ++i) {
        const Program& p = s.programs[i];
        PNB_CHECK(str("program", i, "name", p.name));
        if (p.shaders.empty())
            return makeError(FormatError::BadReference, 0, "program %zu has no shader stages", i);
        for (uint32_t sh : p.shaders)
            if (sh >= s.shaders.size()) return refError("program", i, "shader", sh, s.shaders.size());
        for (StringRef d : p.defines) PNB_CHECK(str("program", i, "define", d));
    }
    for (size_t i = 0; i < s.textures.size(); ++i) {
        const TextureDesc& t = s.textures[i];
        PNB_CHECK(str("texture", i, "name", t.name));
        uint32_t maxMips = 1;
        for (uint32_t d = std::max(t.width, t.height); d > 1; d >>= 1) ++maxMips;
        bool cube = t.dimension == TextureDimension::Cube;
        if (t.width == 0 || t.height == 0 || t.mipCount == 0 || t.mipCount > maxMips ||
            t.layers != (cube ? 6u : 1u) || (cube && t.width != t.height))
            return makeError(FormatError::BadReference, 0,
                             "texture %zu: impossible shape %ux%u, %u layers, %u mips", i, t.width,
                             t.height, t.layers, t.mipCount);
    }
    for (size_t i = 0; i < s.materials.size(); ++i) {
        const Material& m = s.materials[i];
        PNB_CHECK(str("material", i, "name", m.name));
        if (!refOk(m.program, s.programs.size()))
            return refError("material", i, "program", m.program, s.programs.size());
        for (const TextureSlot& slot : m.textures)
            if (!refOk(slot.texture, s.textures.size()))
                return refError("material", i, "texture", slot.texture, s.textures.size());
    }
    for (size_t i = 0; i < s.meshes.size(); ++i) PNB_CHECK(validateMesh(s, s.meshes[i], "mesh", i));
    // The cap first: a file declaring more lights than a player can mask is refused as a whole.
    if (s.lights.lights.size() > kMaxLights)
        return makeError(FormatError::LimitExceeded, 0, "LGHT: %zu lights, more than kMaxLights (%u)",
                         s.lights.lights.size(), kMaxLights);
    for (size_t i = 0; i < s.lights.lights.size(); ++i) {
        PNB_CHECK(str("light", i, "name", s.lights.lights[i].name));
        PNB_CHECK(validateLight(s.lights.lights[i], i));
    }
    for (size_t i = 0; i < s.cameras.cameras.size(); ++i)
        PNB_CHECK(str("camera", i, "name", s.cameras.cameras[i].name));
    for (size_t i = 0; i < s.nodes.nodes.size(); ++i) {
        const Node& n = s.nodes.nodes[i];
        PNB_CHECK(str("node", i, "name", n.name));
        if (n.parent != kNone && n.parent >= i)
            return makeError(FormatError::BadReference, 0,
                             "node %zu: parent %u does not come before it", i, n.parent);
        if (!refOk(n.mesh, s.meshes.size())) return refError("node", i, "mesh", n.mesh, s.meshes.size());
        if (!refOk(n.light, s.lights.lights.size()))
            return refError("node", i, "light", n.light, s.lights.lights.size());
        if (!refOk(n.camera, s.cameras.cameras.size()))
            return refError("node", i, "camera", n.camera, s.cameras.cameras.size());
        if (!finite(n.translation) || !finite(n.scale))
            return makeError(FormatError::BadReference, 0, "node %zu: non-finite transform", i);
    }
    for (size_t k = 0; k < s.nodes.instances.size(); ++k) {
        const NodeInstances& in = s.nodes.instances[k];
        if (in.node >= s.nodes.nodes.size() || s.nodes.nodes[in.node].mesh == kNone)
            return makeError(FormatError::BadReference, 0,
                             "node instances %zu: node %u is not a node with a mesh", k, in.node);
        if (k > 0 && in.node <= s.nodes.instances[k - 1].node)
            return makeError(FormatError::BadReference, 0,
                             "node instances %zu: node %u does not come after node %u", k, in.node,
                             s.nodes.instances[k - 1].node);
        if (in.transforms.empty())
            return makeError(FormatError::BadReference, 0, "node instances %zu: no transforms", k);
        for (size_t t = 0; t < in.transforms.size(); ++t)
            if (!finite(in.transforms[t].translation) || !finite(in.transforms[t].scale) ||
                !finite(in.transforms[t].rotation))
                return makeError(FormatError::BadReference, 0,
                                 "node instances %zu: transform %zu is not finite", k, t);
    }
    PNB_CHECK(validateAnimationChunks(s));
    for (size_t i = 0; i < s.cameraPaths.size(); ++i) {
        const CameraPath& p = s.cameraPaths[i];
        PNB_CHECK(str("camera path", i, "name", p.name));
        for (size_t k = 1; k < p.keys.size(); ++k)
            if (!(p.keys[k].timeSeconds > p.keys[k - 1].timeSeconds))
                return makeError(FormatError::BadReference, 0,
                                 "camera path %zu: key %zu time does not increase", i, k);
    }
    if (s.environment) PNB_CHECK(validateEnvironment(s, *s.environment));
    for (size_t i = 0; i < s.textureMips.size(); ++i) PNB_CHECK(validateTextureMip(s, s.textureMips[i], i));
    std::vector<bool> detailed(s.meshes.size());
    for (size_t i = 0; i < s.meshDetails.size(); ++i) {
        PNB_CHECK(validateMeshDetail(s, s.meshDetails[i], i));
        if (detailed[s.meshDetails[i].mesh])
            return makeError(FormatError::BadReference, 0, "mesh detail %zu: mesh %u has one already", i,
                             s.meshDetails[i].mesh);
        detailed[s.meshDetails[i].mesh] = true;
    }
#undef PNB_CHECK
    return {};
}

namespace {

// One of the environment's textures: absent, or of the dimension and a format the field needs.
Status checkEnvironmentTexture(const Scene& s, uint32_t ref, const char* field, TextureDimension dimension,
                               std::initializer_list<TextureFormat> formats) {
    if (ref == kNone) return {};
    if (ref >= s.textures.size()) return refError("environment", 0, field, ref, s.textures.size());
    const TextureDesc& t = s.textures[ref];
    bool formatOk = std::find(formats.begin(), formats.end(), t.format) != formats.end();
    if (t.dimension != dimension || !formatOk || t.colorSpace != ColorSpace::Linear)
        return makeError(FormatError::BadReference, 0,
                         "environment: %s is texture %u, which is not a linear %s texture of a "
                         "format FORMAT.md allows there",
                         field, ref, dimension == TextureDimension::Cube ? "cube" : "2D");
    return {};
}

} // namespace

Status validateEnvironment(const Scene& s, const Environment& e) {
    if (!refOk(e.name, s.strings.strings.size()))
        return refError("environment", 0, "name", e.name, s.strings.strings.size());
    const auto hdr = {TextureFormat::RGBA16F, TextureFormat::RGBA32F};
    if (Status st = checkEnvironmentTexture(s, e.radiance, "radiance", TextureDimension::Tex2D, hdr); !isOk(st))
        return st;
    if (Status st = checkEnvironmentTexture(s, e.specular, "specular", TextureDimension::Cube, hdr); !isOk(st))
        return st;
    if (Status st = checkEnvironmentTexture(s, e.brdfLut, "brdfLut", TextureDimension::Tex2D,
                                            {TextureFormat::RG16F, TextureFormat::RG32F});
        !isOk(st))
        return st;
    if ((e.specular == kNone) != (e.brdfLut == kNone))
        return makeError(FormatError::BadReference, 0,
                         "environment: a specular cube needs the BRDF table and the table a cube");
    for (const Vec3& c : e.irradianceSh)
        if (!finite(c))
            return makeError(FormatError::BadPayload, 0, "environment: non-finite irradiance coefficient");
    if (!finite(e.sunDirection) || !finite(e.groundAlbedo) || !std::isfinite(e.turbidity) ||
        !std::isfinite(e.sunIlluminance))
        return makeError(FormatError::BadPayload, 0, "environment: non-finite sky parameter");
    return {};
}

const Mesh& fullDetailMesh(const Scene& s, uint32_t index) {
    for (const MeshDetail& d : s.meshDetails)
        if (d.mesh == index) return d.detail;
    return s.meshes[index];
}

Status validateMeshDetail(const Scene& s, const MeshDetail& d, size_t i) {
    if (d.mesh >= s.meshes.size()) return refError("mesh detail", i, "mesh", d.mesh, s.meshes.size());
    if (Status st = validateMesh(s, d.detail, "mesh detail", i); !isOk(st)) return st;
    // Level-0 submeshes by material, in order: the draw items the proxy makes are the detail's.
    auto levelZero = [](const Mesh& m) {
        std::vector<uint32_t> materials;
        for (const Submesh& sm : m.submeshes)
            if (sm.lod == 0 && sm.material != kNone) materials.push_back(sm.material); // drawn ones
        return materials;
    };
    if (levelZero(d.detail) != levelZero(s.meshes[d.mesh]))
        return makeError(FormatError::BadReference, 0,
                         "mesh detail %zu: its level-0 submeshes (by material) are not those of mesh %u, "
                         "its proxy",
                         i, d.mesh);
    if (d.detail.primitive != s.meshes[d.mesh].primitive)
        return makeError(FormatError::BadReference, 0, "mesh detail %zu: another primitive than mesh %u", i, d.mesh);
    return {};
}

Status validateTextureMip(const Scene& s, const TextureMip& mip, size_t i) {
    if (mip.texture >= s.textures.size())
        return refError("texture mip", i, "texture", mip.texture, s.textures.size());
    const TextureDesc& t = s.textures[mip.texture];
    uint32_t w = std::max(1u, t.width >> std::min(mip.level, 31u));
    uint32_t h = std::max(1u, t.height >> std::min(mip.level, 31u));
    if (mip.level >= t.mipCount || mip.width != w || mip.height != h ||
        mip.data.size() != textureLevelSizeBytes(t.format, w, h, t.layers))
        return makeError(FormatError::BadReference, 0,
                         "texture mip %zu: level %u of texture %u (%ux%u, %zu bytes) does "
                         "not fit its descriptor",
                         i, mip.level, mip.texture, mip.width, mip.height, mip.data.size());
    return {};
}

Status writeScene(Writer& w, const Scene& s, Compression bulk) {
    Status st = writeChunk(w, s.strings);
    auto all = [&](const auto& list) {
        for (const auto& item : list)
            if (isOk(st)) st = writeChunk(w, item);
    };
    if (isOk(st)) st = writeChunk(w, s.info);
    if (isOk(st)) st = writeChunk(w, s.settings);
    all(s.shaders);
    all(s.programs);
    all(s.textures);
    all(s.materials);
    for (const Mesh& m : s.meshes)
        if (isOk(st)) st = writeChunk(w, m, bulk);
    for (const MorphTargets& m : s.morphTargets)
        if (isOk(st)) st = writeChunk(w, m, bulk);
    if (isOk(st)) st = writeChunk(w, s.lights);
    if (isOk(st)) st = writeChunk(w, s.cameras);
    if (isOk(st)) st = writeChunk(w, s.nodes);
    all(s.skins);
    all(s.animations);
    all(s.cameraPaths);
    if (isOk(st) && s.environment) st = writeChunk(w, *s.environment);
    // The progressive section (§4.1): smallest level first across all textures, so a streaming
    // reader can show every texture coarsely before any full-resolution level arrives; the mesh
    // details once every texture's smallest level is out (the first frame has what it needs),
    // before the larger levels. Stable for determinism.
    std::vector<const TextureMip*> mips;
    for (const TextureMip& m : s.textureMips) mips.push_back(&m);
    auto smallest = [&](const TextureMip* m) {
        return m->texture < s.textures.size() && m->level + 1 == s.textures[m->texture].mipCount;
    };
    std::stable_sort(mips.begin(), mips.end(), [&](const TextureMip* a, const TextureMip* b) {
        if (smallest(a) != smallest(b)) return smallest(a);
        return a->level > b->level;
    });
    bool detailsOut = false;
    auto details = [&] {
        for (const MeshDetail& d : s.meshDetails)
            if (isOk(st)) st = writeChunk(w, d, bulk);
        detailsOut = true;
    };
    for (const TextureMip* m : mips) {
        if (!detailsOut && !smallest(m)) details();
        if (isOk(st)) st = writeChunk(w, *m, bulk);
    }
    if (!detailsOut) details();
    return st;
}

} // namespace pnb
