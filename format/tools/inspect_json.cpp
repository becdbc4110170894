// inspect_json.cpp — pnb-inspect's JSON view: the same facts as the text view, as one JSON
// object whose keys are the tool's output contract. One view a file (the text view is
// inspect_text.cpp).
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "inspect_internal.h"

namespace pnb::inspect_detail {

// [SECTION] JSON report

void jsonError(Json& j, const Error& e) {
    j.key("error").beginObject();
    j.key("code").str(toString(e.code));
    j.key("offset").uint(e.offset);
    j.key("message").str(e.message);
    j.endObject();
}

void jsonHeader(Json& j, const InspectOptions& opt, const Container& c, const ChunkTable& t) {
    j.key("size_bytes").uint(c.bytes().size());
    j.key("version").beginObject(true);
    j.key("major").uint(c.header().versionMajor);
    j.key("minor").uint(c.header().versionMinor);
    j.endObject();
    j.key("header_flags").uint(c.header().flags);
    j.key("index_mode").str(opt.useToc ? "toc" : "scan");
    j.key("checksums_verified").boolean(opt.verifyChecksums);
    j.key("chunks_without_checksum").uint(chunksWithoutChecksum(c));

    j.key("chunks").beginArray();
    for (const ChunkRow& r : t.rows) {
        j.beginObject(true);
        j.key("index").uint(r.header.sequence);
        j.key("tag").str(r.header.tag.str());
        j.key("kind").str(kindName(r.kind));
        j.key("version").uint(r.header.version);
        j.key("offset").uint(r.offset);
        j.key("payload_offset").uint(r.offset + kChunkHeaderSize);
        j.key("stored_size").uint(r.header.storedSize);
        j.key("raw_size").uint(r.header.rawSize);
        j.key("compression").str(nameOf(r.header.compression(), kCompressionNames));
        auto q = ratio(r.header.rawSize, r.header.storedSize);
        if (q)
            j.key("ratio").number(*q, 3);
        else
            j.key("ratio").null();
        j.key("checksum").boolean(r.header.hasChecksum());
        j.endObject();
    }
    j.endArray();

    j.key("totals").beginArray();
    for (const TagTotal& tt : t.totals) {
        j.beginObject(true);
        j.key("tag").str(tt.tag.str());
        j.key("chunks").uint(tt.count);
        j.key("stored_size").uint(tt.storedSize);
        j.key("raw_size").uint(tt.rawSize);
        j.endObject();
    }
    j.endArray();
    j.key("total_stored_size").uint(t.storedSize);
    j.key("total_raw_size").uint(t.rawSize);
    j.key("frame_overhead_bytes").uint(t.overheadBytes);
}

namespace {

// The scene's own facts: its INFO, and the counts of strings and skipped chunks.
void jsonSceneInfo(Json& j, const Scene& s) {
    j.key("info").beginObject();
    j.key("name").name(s, s.info.name);
    j.key("generator").name(s, s.info.generator);
    j.key("source").name(s, s.info.source);
    j.key("meters_per_unit").number(s.info.metersPerUnit);
    j.key("bounds").bounds(s.info.bounds);
    j.endObject();
    j.key("string_count").uint(s.strings.strings.size());
    j.key("unknown_chunks").uint(s.unknownChunks);
    j.key("newer_chunks").uint(s.newerChunks);
}

void jsonRenderSettings(Json& j, const Scene& s) {
    // An array, not an object: keys may repeat in a file and order is meaningful to readers.
    j.key("render_settings").beginArray();
    for (const Setting& e : s.settings.entries) {
        j.beginObject(true);
        j.key("key").name(s, e.key);
        j.key("value").name(s, e.value);
        j.endObject();
    }
    j.endArray();
}

// Shader sources, then the programs linking them.
void jsonShadersAndPrograms(Json& j, const Scene& s) {
    j.key("shaders").beginArray();
    for (const ShaderSource& sh : s.shaders) {
        j.beginObject(true);
        j.key("name").name(s, sh.name);
        j.key("stage").str(nameOf(sh.stage, kStageNames));
        j.key("source_bytes").uint(sh.source.size());
        j.endObject();
    }
    j.endArray();

    j.key("programs").beginArray();
    for (const Program& p : s.programs) {
        j.beginObject();
        j.key("name").name(s, p.name);
        j.key("shaders").beginArray(true);
        for (uint32_t sh : p.shaders)
            j.uint(sh);
        j.endArray();
        j.key("stages").beginArray(true);
        for (const char* st : programStages(s, p))
            j.str(st);
        j.endArray();
        j.key("defines").beginArray(true);
        for (StringRef d : p.defines)
            j.name(s, d);
        j.endArray();
        j.endObject();
    }
    j.endArray();
}

void jsonTextures(Json& j, const Scene& s) {
    j.key("textures").beginArray();
    for (size_t i = 0; i < s.textures.size(); ++i) {
        const TextureDesc& x = s.textures[i];
        j.beginObject();
        j.key("name").name(s, x.name);
        j.key("dimension").str(nameOf(x.dimension, kDimensionNames));
        j.key("format").str(nameOf(x.format, kFormatNames));
        j.key("width").uint(x.width);
        j.key("height").uint(x.height);
        j.key("layers").uint(x.layers);
        j.key("mip_count").uint(x.mipCount);
        j.key("stored_mips").uint(storedMipCount(s, uint32_t(i)));
        j.key("color_space").str(nameOf(x.colorSpace, kColorSpaceNames));
        j.key("swizzle").str(swizzleLabel(x.swizzle));
        j.key("min_filter").str(nameOf(x.minFilter, kMinFilterNames));
        j.key("mag_filter").str(nameOf(x.magFilter, kMagFilterNames));
        j.key("wrap_u").str(nameOf(x.wrapU, kWrapNames));
        j.key("wrap_v").str(nameOf(x.wrapV, kWrapNames));
        j.endObject();
    }
    j.endArray();
    j.key("texture_mips").beginObject(true);
    j.key("chunks").uint(s.textureMips.size());
    j.key("texel_bytes").uint(mipBytes(s));
    j.endObject();
}

void jsonMaterials(Json& j, const Scene& s) {
    j.key("materials").beginArray();
    for (const Material& m : s.materials) {
        j.beginObject();
        j.key("name").name(s, m.name);
        j.key("program").index(m.program);
        j.key("shading_path").str(nameOf(m.shadingPath, kShadingPathNames));
        j.key("layer_priority").uint(m.layerPriority);
        j.key("alpha_mode").str(nameOf(m.alphaMode, kAlphaModeNames));
        j.key("alpha_cutoff").number(m.alphaCutoff);
        j.key("double_sided").boolean(m.doubleSided);
        j.key("casts_shadows").boolean(m.castsShadows);
        j.key("receives_shadows").boolean(m.receivesShadows);
        j.key("base_color").vec(m.baseColorFactor);
        j.key("emissive").vec(m.emissiveFactor);
        j.key("emissive_strength").number(m.emissiveStrength);
        j.key("metallic").number(m.metallicFactor);
        j.key("roughness").number(m.roughnessFactor);
        j.key("normal_scale").number(m.normalScale);
        j.key("occlusion_strength").number(m.occlusionStrength);
        j.key("textures").beginArray();
        for (size_t k = 0; k < m.textures.size(); ++k) {
            const TextureSlot& slot = m.textures[k];
            if (slot.texture == kNone) continue;
            j.beginObject(true);
            j.key("slot").str(kSlotNames[k]);
            j.key("texture").uint(slot.texture);
            j.key("tex_coord").uint(slot.texCoord);
            j.endObject();
        }
        j.endArray();
        j.endObject();
    }
    j.endArray();
}

void jsonMeshes(Json& j, const Scene& s) {
    j.key("meshes").beginArray();
    for (const Mesh& m : s.meshes) {
        j.beginObject();
        j.key("name").name(s, m.name);
        j.key("primitive").str(nameOf(m.primitive, kPrimitiveNames));
        j.key("vertices").uint(m.vertexCount);
        j.key("index_type").str(nameOf(m.indexType, kIndexTypeNames));
        j.key("index_count").uint(indexCount(m));
        j.key("triangles").uint(triangleCount(m));
        j.key("streams").beginArray();
        for (const VertexStream& v : m.streams) {
            j.beginObject(true);
            j.key("semantic").str(nameOf(v.semantic, kSemanticNames));
            j.key("type").str(nameOf(v.componentType, kComponentNames));
            j.key("components").uint(v.componentCount);
            j.key("normalized").boolean(v.normalized);
            j.key("encoding").str(nameOf(v.encoding, kEncodingNames));
            j.key("bytes").uint(v.data.size());
            j.endObject();
        }
        j.endArray();
        j.key("submeshes").beginArray();
        for (const Submesh& sm : m.submeshes) {
            j.beginObject(true);
            j.key("material").index(sm.material);
            j.key("first_index").uint(sm.firstIndex);
            j.key("index_count").uint(sm.indexCount);
            j.key("lod").uint(sm.lod);
            j.endObject();
        }
        j.endArray();
        j.key("bounds").bounds(m.bounds);
        j.key("bounding_sphere").beginObject(true);
        j.key("center").vec(m.boundingSphere.center);
        j.key("radius").number(m.boundingSphere.radius);
        j.endObject();
        j.endObject();
    }
    j.endArray();
}

void jsonLightsAndCameras(Json& j, const Scene& s) {
    j.key("lights").beginArray();
    for (const Light& l : s.lights.lights) {
        j.beginObject(true);
        j.key("name").name(s, l.name);
        j.key("type").str(nameOf(l.type, kLightTypeNames));
        j.key("color").vec(l.color);
        j.key("intensity").number(l.intensity);
        j.key("range").number(l.range);
        j.key("inner_cone_radians").number(l.innerConeRadians);
        j.key("outer_cone_radians").number(l.outerConeRadians);
        j.key("casts_shadows").boolean(l.castsShadows);
        j.key("generated").boolean(l.generated);
        j.endObject();
    }
    j.endArray();

    j.key("cameras").beginArray();
    for (const Camera& c : s.cameras.cameras) {
        j.beginObject(true);
        j.key("name").name(s, c.name);
        j.key("projection").str(nameOf(c.projection, kProjectionNames));
        j.key("yfov_radians").number(c.yfovRadians);
        j.key("aspect_ratio").number(c.aspectRatio);
        j.key("znear").number(c.znear);
        j.key("zfar").number(c.zfar);
        j.key("xmag").number(c.xmag);
        j.key("ymag").number(c.ymag);
        j.endObject();
    }
    j.endArray();
}

// Node counts (not each node: a scene may hold millions), then the camera paths.
void jsonNodesAndCameraPaths(Json& j, const Scene& s) {
    NodeCounts n = countNodes(s.nodes);
    j.key("nodes").beginObject(true);
    j.key("count").uint(s.nodes.nodes.size());
    j.key("roots").uint(n.roots);
    j.key("with_mesh").uint(n.withMesh);
    j.key("with_light").uint(n.withLight);
    j.key("with_camera").uint(n.withCamera);
    j.endObject();

    j.key("camera_paths").beginArray();
    for (const CameraPath& p : s.cameraPaths) {
        j.beginObject(true);
        j.key("name").name(s, p.name);
        j.key("keys").uint(p.keys.size());
        j.key("duration_seconds").number(pathDuration(p));
        j.key("interpolation").str(nameOf(p.interpolation, kInterpolationNames));
        j.key("loop").boolean(p.loop);
        j.endObject();
    }
    j.endArray();
}

// "morph_targets", "skins", "animations": only when the file has some (a static scene's
// report is what it was before they existed).
void jsonAnimation(Json& j, const Scene& s) {
    if (!s.morphTargets.empty()) {
        j.key("morph_targets").beginArray();
        for (const MorphTargets& m : s.morphTargets) {
            j.beginObject(true);
            j.key("mesh").uint(m.mesh);
            j.key("targets").uint(m.targets.size());
            j.key("deltas").str(m.targets.empty() ? "none" : morphDeltaLabel(m.targets[0]));
            j.endObject();
        }
        j.endArray();
    }
    if (!s.skins.empty()) {
        j.key("skins").beginArray();
        for (const Skin& k : s.skins) {
            j.beginObject(true);
            j.key("name").name(s, k.name);
            j.key("joints").uint(k.joints.size());
            j.key("nodes").uint(k.nodes.size());
            j.endObject();
        }
        j.endArray();
    }
    if (!s.animations.empty()) {
        j.key("animations").beginArray();
        for (const Animation& a : s.animations) {
            const ClipCounts c = countClip(a);
            j.beginObject(true);
            j.key("name").name(s, a.name);
            j.key("channels").uint(a.channels.size());
            j.key("keys").uint(c.keys);
            j.key("duration_seconds").number(float(c.durationSeconds));
            j.endObject();
        }
        j.endArray();
    }
}

} // namespace

// The decoded scene as the object "scene": one member per kind of content, in a fixed order.
void jsonScene(Json& j, const Scene& s) {
    j.key("scene").beginObject();
    jsonSceneInfo(j, s);
    jsonRenderSettings(j, s);
    jsonShadersAndPrograms(j, s);
    jsonTextures(j, s);
    jsonMaterials(j, s);
    jsonMeshes(j, s);
    jsonLightsAndCameras(j, s);
    jsonNodesAndCameraPaths(j, s);
    jsonAnimation(j, s);
    j.endObject();
}

} // namespace pnb::inspect_detail
