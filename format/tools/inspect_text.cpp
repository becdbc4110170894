// inspect_text.cpp — pnb-inspect's text view: the file header, the chunk table and the scene's
// typed summaries as aligned tables. One view a file (the JSON view is inspect_json.cpp).
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

namespace {

// [SECTION] text tables

// Columns sized to their widest cell, two spaces apart; numeric columns right-aligned.
class TextTable {
public:
    // `align` has one character per column: 'l' or 'r'.
    TextTable(std::vector<std::string> header, std::string align) : mAlign(std::move(align)) {
        mRows.push_back(std::move(header));
    }
    void add(std::vector<std::string> row) { mRows.push_back(std::move(row)); }

    void print(std::string& out) const {
        std::vector<size_t> width(mAlign.size(), 0);
        for (const auto& row : mRows)
            for (size_t c = 0; c < row.size() && c < width.size(); ++c)
                width[c] = std::max(width[c], displayWidth(row[c]));
        for (const auto& row : mRows) {
            std::string line = "  ";
            for (size_t c = 0; c < row.size() && c < width.size(); ++c) {
                size_t pad = width[c] - displayWidth(row[c]);
                if (mAlign[c] == 'r') line.append(pad, ' ');
                line += row[c];
                if (mAlign[c] != 'r') line.append(pad, ' ');
                line += "  ";
            }
            while (!line.empty() && line.back() == ' ')
                line.pop_back();
            out += line + "\n";
        }
    }

private:
    std::string mAlign;
    std::vector<std::vector<std::string>> mRows;

    // Code points, not bytes: escaped names are valid UTF-8, so continuation bytes don't count.
    static size_t displayWidth(std::string_view s) {
        size_t n = 0;
        for (char ch : s)
            n += (uint8_t(ch) & 0xC0) != 0x80;
        return n;
    }
};

// [SECTION] text report

const char* yesNo(bool v) {
    return v ? "yes" : "no";
}

} // namespace

void textHeader(std::string& o, const InspectOptions& opt, const Container& c,
                const ChunkTable& t) {
    o += "file: " + textEscape(opt.path) + "\n";
    o += "format: version " + std::to_string(c.header().versionMajor) + "." +
         std::to_string(c.header().versionMinor) + ", " + u64(c.bytes().size()) + " bytes, " +
         u64(c.chunks().size()) + " chunks + table of contents\n";
    const size_t unchecked = chunksWithoutChecksum(c);
    o += std::string("read: chunks located by ") +
         (opt.useToc ? "table of contents" : "scanning chunk headers") + ", payload checksums " +
         (opt.verifyChecksums ? "verified" : "not verified");
    if (unchecked > 0)
        o += " (" + u64(unchecked) + " of " + u64(c.chunks().size()) +
             " chunks carry no checksum: their payload bytes cannot be checked)";
    o += "\n";
    o += "\nchunks:\n";
    TextTable table(
        {"#", "tag", "ver", "offset", "stored", "raw", "compression", "ratio", "checksum", "note"},
        "rlrrrrlrll");
    for (const ChunkRow& r : t.rows) {
        // An uncompressed chunk's ratio is 1 by definition; a dash makes compressed ones stand out.
        bool compressed = r.header.compression() != Compression::None;
        const char* note = r.kind == ChunkKind::Unknown ? "unknown (skipped)"
                           : r.kind == ChunkKind::Toc   ? "table of contents"
                                                        : "";
        table.add({u64(r.header.sequence), r.header.tag.str(), u64(r.header.version), u64(r.offset),
                   u64(r.header.storedSize), u64(r.header.rawSize),
                   nameOf(r.header.compression(), kCompressionNames),
                   compressed ? ratioText(r.header.rawSize, r.header.storedSize) : "-",
                   yesNo(r.header.hasChecksum()), note});
    }
    table.print(o);

    o += "\ntotals:\n";
    TextTable totals({"tag", "chunks", "stored", "raw", "ratio"}, "lrrrr");
    for (const TagTotal& tt : t.totals)
        totals.add({tt.tag.str(), u64(tt.count), u64(tt.storedSize), u64(tt.rawSize),
                    ratioText(tt.rawSize, tt.storedSize)});
    totals.add({"all", u64(t.rows.size()), u64(t.storedSize), u64(t.rawSize),
                ratioText(t.rawSize, t.storedSize)});
    totals.print(o);
    o += "  frame overhead (file header, chunk headers, padding, footer): " + u64(t.overheadBytes) +
         " bytes\n";
}

namespace {

// The scene's own facts: its INFO, and the counts of strings and skipped chunks.
void textSceneInfo(std::string& o, const Scene& s) {
    o += "\nscene:\n";
    o += "  name: " + nameText(s, s.info.name) + "\n";
    o += "  generator: " + nameText(s, s.info.generator) + "\n";
    o += "  source: " + nameText(s, s.info.source) + "\n";
    o += "  meters per unit: " + num(s.info.metersPerUnit) + "\n";
    o += "  bounds: " + boundsText(s.info.bounds) + "\n";
    o += "  strings: " + u64(s.strings.strings.size()) + "\n";
    o += "  unknown chunks (skipped): " + u64(s.unknownChunks) + "\n";
    if (s.newerChunks > 0)
        o += "  newer chunk versions (read by the fields this reader knows, the rest ignored): " +
             u64(s.newerChunks) + "\n";
}

void textRenderSettings(std::string& o, const Scene& s) {
    o += "\nrender settings (" + u64(s.settings.entries.size()) + "):\n";
    for (const Setting& e : s.settings.entries)
        o += "  " + textEscape(s.str(e.key)) + "=" + textEscape(s.str(e.value)) + "\n";
}

void textShaders(std::string& o, const Scene& s) {
    o += "\nshaders (" + u64(s.shaders.size()) + "):\n";
    if (!s.shaders.empty()) {
        TextTable t({"#", "name", "stage", "source bytes"}, "rllr");
        for (size_t i = 0; i < s.shaders.size(); ++i)
            t.add({u64(i), nameText(s, s.shaders[i].name), nameOf(s.shaders[i].stage, kStageNames),
                   u64(s.shaders[i].source.size())});
        t.print(o);
    }
}

void textPrograms(std::string& o, const Scene& s) {
    o += "\nprograms (" + u64(s.programs.size()) + "):\n";
    if (!s.programs.empty()) {
        TextTable t({"#", "name", "stages", "defines"}, "rlll");
        for (size_t i = 0; i < s.programs.size(); ++i) {
            const Program& p = s.programs[i];
            std::string stages, defines;
            for (const char* st : programStages(s, p))
                stages += (stages.empty() ? "" : "+") + std::string(st);
            for (StringRef d : p.defines)
                defines += (defines.empty() ? "" : " ") + textEscape(s.str(d));
            t.add({u64(i), nameText(s, p.name), stages, defines.empty() ? "-" : defines});
        }
        t.print(o);
    }
}

void textMaterials(std::string& o, const Scene& s) {
    o += "\nmaterials (" + u64(s.materials.size()) + "):\n";
    if (!s.materials.empty()) {
        TextTable t({"#", "name", "path", "layer", "alpha", "cutoff", "sided", "shadows",
                     "base colour", "metallic", "roughness", "program", "textures"},
                    "rllrlrllllrll");
        for (size_t i = 0; i < s.materials.size(); ++i) {
            const Material& m = s.materials[i];
            std::string textures;
            for (size_t k = 0; k < m.textures.size(); ++k) {
                uint32_t tex = m.textures[k].texture;
                if (tex == kNone) continue;
                std::string texName =
                    tex < s.textures.size() ? nameText(s, s.textures[tex].name) : "#" + u64(tex);
                textures +=
                    (textures.empty() ? "" : " ") + std::string(kSlotNames[k]) + ":" + texName;
            }
            std::string program = m.program == kNone || m.program >= s.programs.size()
                                      ? "-"
                                      : nameText(s, s.programs[m.program].name);
            t.add({u64(i), nameText(s, m.name), nameOf(m.shadingPath, kShadingPathNames),
                   u64(m.layerPriority), nameOf(m.alphaMode, kAlphaModeNames), num(m.alphaCutoff),
                   m.doubleSided ? "double" : "single",
                   shadowLabel(m.castsShadows, m.receivesShadows), vecText(m.baseColorFactor),
                   num(m.metallicFactor), num(m.roughnessFactor), program,
                   textures.empty() ? "-" : textures});
        }
        t.print(o);
    }
}

void textMeshes(std::string& o, const Scene& s) {
    o += "\nmeshes (" + u64(s.meshes.size()) + "):\n";
    if (!s.meshes.empty()) {
        TextTable t({"#", "name", "primitive", "vertices", "triangles", "index", "streams",
                     "submeshes", "bounds"},
                    "rllrrllrl");
        for (size_t i = 0; i < s.meshes.size(); ++i) {
            const Mesh& m = s.meshes[i];
            std::string streams;
            for (const VertexStream& v : m.streams)
                streams += (streams.empty() ? "" : " ") + streamLabel(v);
            t.add({u64(i), nameText(s, m.name), nameOf(m.primitive, kPrimitiveNames),
                   u64(m.vertexCount), u64(triangleCount(m)), nameOf(m.indexType, kIndexTypeNames),
                   streams.empty() ? "-" : streams, u64(m.submeshes.size()), boundsText(m.bounds)});
        }
        t.print(o);
    }
}

void textTextures(std::string& o, const Scene& s) {
    o += "\ntextures (" + u64(s.textures.size()) + "):\n";
    if (!s.textures.empty()) {
        TextTable t({"#", "name", "dim", "format", "size", "layers", "mips", "stored mips",
                     "colour space", "swizzle", "filter", "wrap"},
                    "rlllrrrrllll");
        for (size_t i = 0; i < s.textures.size(); ++i) {
            const TextureDesc& x = s.textures[i];
            t.add({u64(i), nameText(s, x.name), nameOf(x.dimension, kDimensionNames),
                   nameOf(x.format, kFormatNames), u64(x.width) + "x" + u64(x.height),
                   u64(x.layers), u64(x.mipCount), u64(storedMipCount(s, uint32_t(i))),
                   nameOf(x.colorSpace, kColorSpaceNames), swizzleLabel(x.swizzle),
                   std::string(nameOf(x.minFilter, kMinFilterNames)) + "/" +
                       nameOf(x.magFilter, kMagFilterNames),
                   std::string(nameOf(x.wrapU, kWrapNames)) + "/" + nameOf(x.wrapV, kWrapNames)});
        }
        t.print(o);
    }
    o += "  texture mips: " + u64(s.textureMips.size()) + " chunks, " + u64(mipBytes(s)) +
         " texel bytes\n";
}

void textLights(std::string& o, const Scene& s) {
    o += "\nlights (" + u64(s.lights.lights.size()) + "):\n";
    if (!s.lights.lights.empty()) {
        TextTable t({"#", "name", "type", "colour", "intensity", "range", "cone (rad)", "shadows",
                     "generated"},
                    "rlllrrlll");
        for (size_t i = 0; i < s.lights.lights.size(); ++i) {
            const Light& l = s.lights.lights[i];
            std::string cone = l.type == LightType::Spot
                                   ? num(l.innerConeRadians) + ".." + num(l.outerConeRadians)
                                   : "-";
            t.add({u64(i), nameText(s, l.name), nameOf(l.type, kLightTypeNames),
                   vecText({l.color.x, l.color.y, l.color.z}), num(l.intensity),
                   l.range == 0 ? "unlimited" : num(l.range), cone, yesNo(l.castsShadows),
                   yesNo(l.generated)});
        }
        t.print(o);
    }
}

void textCameras(std::string& o, const Scene& s) {
    o += "\ncameras (" + u64(s.cameras.cameras.size()) + "):\n";
    if (!s.cameras.cameras.empty()) {
        TextTable t({"#", "name", "projection", "yfov (rad)", "aspect", "znear", "zfar"},
                    "rllrrrr");
        for (size_t i = 0; i < s.cameras.cameras.size(); ++i) {
            const Camera& c = s.cameras.cameras[i];
            bool ortho = c.projection == Projection::Orthographic;
            t.add({u64(i), nameText(s, c.name), nameOf(c.projection, kProjectionNames),
                   ortho ? "-" : num(c.yfovRadians),
                   c.aspectRatio == 0 ? "viewport" : num(c.aspectRatio), num(c.znear),
                   c.zfar == 0 ? "infinite" : num(c.zfar)});
        }
        t.print(o);
    }
}

// Node counts (not each node: a scene may hold millions), then the camera paths.
void textNodesAndCameraPaths(std::string& o, const Scene& s) {
    NodeCounts n = countNodes(s.nodes);
    o += "\nnodes: " + u64(s.nodes.nodes.size()) + " (roots " + u64(n.roots) + ", with mesh " +
         u64(n.withMesh) + ", with light " + u64(n.withLight) + ", with camera " +
         u64(n.withCamera) + ")\n";

    o += "\ncamera paths (" + u64(s.cameraPaths.size()) + "):\n";
    if (!s.cameraPaths.empty()) {
        TextTable t({"#", "name", "keys", "duration (s)", "interpolation", "loop"}, "rlrrll");
        for (size_t i = 0; i < s.cameraPaths.size(); ++i) {
            const CameraPath& p = s.cameraPaths[i];
            t.add({u64(i), nameText(s, p.name), u64(p.keys.size()), num(pathDuration(p)),
                   nameOf(p.interpolation, kInterpolationNames), yesNo(p.loop)});
        }
        t.print(o);
    }
}

// Morph targets, skins and clips (MRPH, SKIN, ANIM), only when the file has some: a static
// scene's report is what it was before they existed.
void textAnimation(std::string& o, const Scene& s) {
    if (!s.morphTargets.empty()) {
        o += "\nmorph targets (" + u64(s.morphTargets.size()) + " meshes):\n";
        TextTable t({"#", "mesh", "targets", "deltas"}, "rrrl");
        for (size_t i = 0; i < s.morphTargets.size(); ++i) {
            const MorphTargets& m = s.morphTargets[i];
            t.add({u64(i), u64(m.mesh), u64(m.targets.size()),
                   m.targets.empty() ? std::string("-") : morphDeltaLabel(m.targets[0])});
        }
        t.print(o);
    }
    if (!s.skins.empty()) {
        o += "\nskins (" + u64(s.skins.size()) + "):\n";
        TextTable t({"#", "name", "joints", "nodes"}, "rlrr");
        for (size_t i = 0; i < s.skins.size(); ++i)
            t.add({u64(i), nameText(s, s.skins[i].name), u64(s.skins[i].joints.size()),
                   u64(s.skins[i].nodes.size())});
        t.print(o);
    }
    if (!s.animations.empty()) {
        o += "\nanimations (" + u64(s.animations.size()) + " clips):\n";
        TextTable t({"#", "name", "channels", "keys", "duration (s)"}, "rlrrr");
        for (size_t i = 0; i < s.animations.size(); ++i) {
            const ClipCounts c = countClip(s.animations[i]);
            t.add({u64(i), nameText(s, s.animations[i].name), u64(s.animations[i].channels.size()),
                   u64(c.keys), num(float(c.durationSeconds))});
        }
        t.print(o);
    }
}

// The environment (ENVM), when the file has one.
void textEnvironment(std::string& o, const Scene& s) {
    if (const auto& e = s.environment) {
        auto texture = [&](uint32_t t) {
            return t == kNone ? std::string("none") : "texture " + u64(t);
        };
        o += "\nenvironment: " + nameText(s, e->name) + " (" +
             nameOf(e->source, kEnvironmentSourceNames) + (e->generated ? ", generated" : "") +
             "), radiance " + texture(e->radiance) + ", specular " + texture(e->specular) +
             ", BRDF table " + texture(e->brdfLut) + "\n";
        o += "  irradiance SH band 0 (lux): " + vecText(e->irradianceSh[0]) + "\n";
        if (e->source == EnvironmentSource::AnalyticSky)
            o += "  sky: sun " + vecText(e->sunDirection) + ", turbidity " + num(e->turbidity) +
                 ", ground " + vecText(e->groundAlbedo) + ", sun " + num(e->sunIlluminance) +
                 " lux\n";
    }
}

} // namespace

// The decoded scene, one section per kind of content, in a fixed order.
void textScene(std::string& o, const Scene& s) {
    textSceneInfo(o, s);
    textRenderSettings(o, s);
    textShaders(o, s);
    textPrograms(o, s);
    textMaterials(o, s);
    textMeshes(o, s);
    textTextures(o, s);
    textLights(o, s);
    textCameras(o, s);
    textNodesAndCameraPaths(o, s);
    textAnimation(o, s);
    textEnvironment(o, s);
}

} // namespace pnb::inspect_detail
