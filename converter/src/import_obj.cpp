// import_obj.cpp — Wavefront OBJ/MTL into the scene IR. The OBJ text is read by our parallel
// parser (obj_parse.h) when it stays in that parser's subset (v/vt/vn lines, polygons of any
// size, lines, points, usemtl, mtllib, o, g, s, comments: what exporters write), else by
// tinyobjloader (Debian's libtinyobjloader-dev, import_obj_tinyobj.cpp), which also gives every
// error message; both give the same IR (tests/converter/obj_parse_test.cpp). MTL files are read
// by tinyobjloader's LoadMtl. Parsing the 1M-triangle benchmark OBJ took assimp 1.37 s CPU,
// tinyobjloader 0.87 s, obj_parse ~0.17 s on one thread (docs/CONVERTER.md, "Speed", "Issue 30").
//
// A translation, not a processing step: welding, normals, tangents and optimisations are the
// mesh stage's (mesh_processing.h). The behaviour is the assimp importer's for OBJ
// (import_assimp.cpp), so both give the same IR up to vertex numbering:
// - Structure: a root node named after the file, one child node per object ("o" or "g" line;
//   faces before any are object "defaultobject"), each with its own IrMesh named like it. One
//   IrPrimitive per run of faces with one material, so an object with two materials is one
//   IrMesh with two primitives on one node.
// - Vertices: one per distinct (v, vt, vn) index triple of a primitive, in order of first use
//   (assimp gave every face corner its own vertex; the mesh stage's weld makes the two
//   equivalent, and fewer vertices make it faster). Polygons are triangulated as tinyobjloader
//   does (quads along the shorter diagonal, larger polygons by its ear clipping, both in its
//   float arithmetic, in either reader). Primitives are built in parallel (`jobs`); the
//   result does not depend on the job count.
// - Numbers: obj_parse rounds correctly (std::from_chars); tinyobjloader's conversion is
//   approximate, but equals it on every value of the assimp test models and of the benchmark
//   OBJ (the tests allow one ulp). A number beyond float's range is ±Inf, below it ±0. A
//   "v"/"vt"/"vn" line outside obj_parse's grammar ("v 1 2", "v x y z w", a word) is read by
//   tinyobjloader, that line alone: its defaults and leniency, the rest of the file in parallel.
// - V flip: IR UVs follow glTF (v = 0 is the top row), OBJ's v = 0 is the bottom row: (u, 1 - v).
// - Streams: a primitive gets normals (uvs) only when every corner has a valid vn (vt) index;
//   otherwise they are dropped with a warning naming the mesh and the mesh stage generates
//   normals. A normal/UV/colour stream holding NaN/Inf is dropped with a warning naming the mesh;
//   non-finite positions pass through (the mesh stage drops their triangles with a warning).
//   Vertex colours ("v x y z r g b") are kept when every vertex of the file has one.
// - Errors (exit code 2), naming the file and the line: a face or point/line index that is 0 or
//   not a number (tinyobjloader's parse error), a position index outside the file's vertices
//   (found again by scanning the text, since tinyobjloader keeps no line numbers). obj_parse
//   hands any such file to tinyobjloader, so the messages are its reader's.
// - Points and lines: dropped with a warning naming the mesh (the IR is triangles only), with
//   tinyobjloader's counts (which count a group's lines again at each material change within
//   it: readObjEvents). tinyobjloader discards a "g" group that has only points or lines, so
//   those go unreported; a file with no triangles at all is an error.
// - Materials: MTL parameters map onto PBR through applyMtlToPbr (mtl_to_pbr.h) with assimp's
//   defaults where the MTL is silent (Kd 0.6, Ns 0: tinyobjloader's defaults differ, so the MTL
//   text is scanned for which keys each material sets); map_Kd → base colour, map_d → the base
//   colour's alpha (Mask when d is 1) if it is the same file, else a warning; norm, else
//   bump/map_bump → normal map with -bm as its scale; map_Ke → emissive (factor 1 when Ke is
//   black); every other map is reported as having no PBR slot. -clamp on → clamp to edge; -o/-s
//   are reported as ignored. Faces without usemtl, or naming a material no MTL defines (a
//   warning), use the IR's default material. Materials are converted on first use, in order.
// - usemtl names with spaces: tinyobjloader's usemtl keeps only the first word, so a material
//   whose name has spaces is also registered under its first word (unless another material has
//   that name).
// - Files: mtllib and texture references resolve as import_paths.h describes (relative, '\' →
//   '/', case-insensitive, then the bare name next to the OBJ with a warning); an mtllib that is
//   still missing falls back to <obj name>.mtl next to the OBJ (as assimp does) with a warning.
//   Missing textures are dropped with a warning, the material kept. MTL files read are listed
//   in IrScene::dependencies (the --depfile); textures are listed by the texture stage.
// - The OBJ file is read with one read() into memory in transparent huge pages (ObjText): it is
//   the largest input the converter reads.
//
// Does NOT do: processing of any kind, image decoding, smoothing groups (the mesh stage's
// normals are smooth), tinyobjloader's extensions (vw skin weights, t subdivision tags).
#include "pnb_converter/importers.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <tiny_obj_loader.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <istream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "huge_pages.h"
#include "import_obj_internal.h"
#include "import_paths.h"
#include "obj_parse.h"
#include "parallel_for.h"
#include "pnb_converter/mtl_to_pbr.h"

namespace pnb::converter {

namespace {

namespace fs = std::filesystem;
using namespace import_detail;

// assimp's values for what an MTL leaves out (ObjFileData.h), kept so switching importers does
// not change materials.
constexpr float kDefaultKd = 0.6f;
constexpr const char* kDefaultObjectName = "defaultobject";

// [SECTION] files

std::optional<std::string> readFile(const fs::path& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) return std::nullopt;
    std::string data;
    char chunk[1 << 16];
    size_t n;
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (!ec) data.reserve(size_t(size));
    while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0) data.append(chunk, n);
    const bool failed = std::ferror(f) != 0;
    std::fclose(f);
    if (failed) return std::nullopt;
    return data;
}

// The OBJ file's bytes, read with one read() into memory allocateLarge gives in transparent huge
// pages (huge_pages.h): the 94 MB benchmark OBJ took 0.17 s to read into 4 KiB pages populated up
// front (mmap(MAP_POPULATE)) and as long again to scan once (TLB misses), 0.02 s and 0.04 s in
// huge pages (docs/CONVERTER.md, "Issue 30"). The file itself is not mapped: another program
// truncating it during the parse would kill us with SIGBUS (and the page cache's 4 KiB pages
// scan slowly too).
class ObjText {
public:
    bool open(const fs::path& path) {
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return false;
        struct stat st {};
        bool ok = true;
        if (::fstat(fd, &st) == 0 && st.st_size > 0) {
            mCapacity = size_t(st.st_size);
            mBytes = static_cast<char*>(allocateLarge(mCapacity));
            while (mSize < mCapacity) { // a file that shrank meanwhile is read as it is
                const ssize_t n = ::read(fd, mBytes + mSize, mCapacity - mSize);
                if (n < 0 && errno == EINTR) continue;
                if (n < 0) ok = false;
                if (n <= 0) break;
                mSize += size_t(n);
            }
        }
        ::close(fd);
        if (mBytes) return ok;
        std::optional<std::string> bytes = readFile(path); // empty, or no size (not a plain file)
        if (!bytes) return false;
        mCopy = std::move(*bytes);
        return true;
    }
    ObjText() = default;
    ObjText(const ObjText&) = delete;
    ObjText& operator=(const ObjText&) = delete;
    ~ObjText() {
        if (mBytes) freeLarge(mBytes, mCapacity);
    }

    std::string_view view() const {
        return mBytes ? std::string_view(mBytes, mSize) : std::string_view(mCopy);
    }
    char* data() { return mBytes ? mBytes : mCopy.data(); }

private:
    char* mBytes = nullptr;
    size_t mSize = 0, mCapacity = 0;
    std::string mCopy; // when the size is unknown
};

// Which MTL keys a material sets; tinyobjloader fills defaults that cannot be told apart.
struct MtlKeys {
    bool kd = false, ns = false, pr = false, pm = false;
};

// Scans MTL text for the keys each "newmtl" block sets, by material name as tinyobjloader
// reads it (the rest of the line, trailing blanks removed).
void scanMtlKeys(std::string_view text, std::map<std::string, MtlKeys>& out) {
    MtlKeys* current = nullptr;
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find_first_of("\r\n", pos); // tinyobjloader ends a line at either
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
        while (!line.empty() && blank(line.front())) line.remove_prefix(1);
        while (!line.empty() && blank(line.back())) line.remove_suffix(1);
        auto key = [&](std::string_view k) {
            return line.size() > k.size() && line.substr(0, k.size()) == k &&
                   (line[k.size()] == ' ' || line[k.size()] == '\t');
        };
        if (key("newmtl")) {
            current = &out[std::string(line.substr(7))];
            *current = MtlKeys{};
        } else if (current != nullptr) {
            if (key("Kd")) current->kd = true;
            else if (key("Ns")) current->ns = true;
            else if (key("Pr")) current->pr = true;
            else if (key("Pm")) current->pm = true;
        }
    }
}

// tinyobjloader calls this for each mtllib name: resolves it like a texture, reads it, records
// it as a dependency and scans it for the keys it sets.
class MtlReader : public tinyobj::MaterialReader {
public:
    MtlReader(fs::path sourceDir, fs::path objPath, IrScene& out,
              std::map<std::string, MtlKeys>& keys)
        : mSourceDir(std::move(sourceDir)), mObjPath(std::move(objPath)), mOut(out), mKeys(keys) {}

    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* byName, std::string* /*warn*/,
                    std::string* /*err*/) override {
        std::optional<ResolvedPath> resolved = resolveReference(mSourceDir, name);
        if (resolved && resolved->byNameOnly) {
            warnOnce(format("'%s' not found; using '%s' (same file name, next to the source file)",
                            name.c_str(), resolved->path.c_str()));
        }
        if (!resolved) {
            fs::path fallback = mObjPath;
            fallback.replace_extension(".mtl");
            if (auto p = resolveReference(mSourceDir, fallback.filename().string())) {
                warnOnce(format("could not open '%s' (referenced by the source file); using '%s'",
                                name.c_str(), p->path.c_str()));
                resolved = p;
            }
        }
        std::optional<std::string> text;
        if (resolved) text = readFile(resolved->path);
        if (!text) {
            warnOnce(format("could not open '%s' (referenced by the source file)", name.c_str()));
            return false;
        }
        const std::string path = resolved->path.string();
        if (std::find(mOut.dependencies.begin(), mOut.dependencies.end(), path) ==
            mOut.dependencies.end()) {
            mOut.dependencies.push_back(path);
        }
        scanMtlKeys(*text, mKeys);
        const size_t first = materials->size();
        MemoryBuffer buffer(*text);
        std::istream stream(&buffer);
        std::string warn, err;
        tinyobj::LoadMtl(byName, materials, &stream, &warn, &err);
        // usemtl keeps only its first word (header block): alias spaced names by it.
        for (size_t i = first; i < materials->size(); ++i) {
            const std::string& full = (*materials)[i].name;
            const size_t space = full.find_first_of(" \t");
            if (space != std::string::npos && space > 0) {
                byName->emplace(full.substr(0, space), int(i));
            }
        }
        return true;
    }

private:
    void warnOnce(std::string message) {
        if (std::find(mOut.warnings.begin(), mOut.warnings.end(), message) == mOut.warnings.end()) {
            mOut.warnings.push_back(std::move(message));
        }
    }

    fs::path mSourceDir, mObjPath;
    IrScene& mOut;
    std::map<std::string, MtlKeys>& mKeys;
};

// [SECTION] materials

struct Context {
    std::string path; // as given, for messages
    fs::path sourceDir;
    IrScene* out = nullptr;
    std::map<std::string, int> imageByPath;
    std::map<std::string, MtlKeys> keys;

    void warn(std::string message) { out->warnings.push_back(std::move(message)); }
};

int imageFor(Context& ctx, const std::string& ref, const std::string& what) {
    return imageForReference(ctx.sourceDir, ref, what, *ctx.out, ctx.imageByPath);
}

// Same file, or (both unresolved) the same reference once slashes and case are normalised.
bool sameTexture(const Context& ctx, const std::string& a, const std::string& b) {
    const auto ra = resolveReference(ctx.sourceDir, a), rb = resolveReference(ctx.sourceDir, b);
    if (ra || rb) return ra && rb && ra->path == rb->path;
    std::string x = a, y = b;
    std::replace(x.begin(), x.end(), '\\', '/');
    std::replace(y.begin(), y.end(), '\\', '/');
    return iequals(x, y);
}

IrTextureRef textureRef(Context& ctx, const std::string& ref, const tinyobj::texture_option_t& opt,
                        const std::string& what, const char* slotName) {
    IrTextureRef out;
    out.image = imageFor(ctx, ref, what);
    if (opt.clamp) out.wrapU = out.wrapV = Wrap::ClampToEdge;
    if (opt.origin_offset[0] != 0 || opt.origin_offset[1] != 0 || opt.scale[0] != 1 ||
        opt.scale[1] != 1) {
        ctx.warn(format("%s: %s texture UV transform ignored", what.c_str(), slotName));
    }
    return out;
}

IrMaterial convertMaterial(Context& ctx, const tinyobj::material_t& mat) {
    IrMaterial out;
    out.name = mat.name;
    const std::string what = format("material '%s'", out.name.c_str());
    MtlKeys keys;
    if (auto it = ctx.keys.find(mat.name); it != ctx.keys.end()) keys = it->second;

    MtlParameters mtl;
    mtl.kd = keys.kd ? Vec3{mat.diffuse[0], mat.diffuse[1], mat.diffuse[2]}
                     : Vec3{kDefaultKd, kDefaultKd, kDefaultKd};
    mtl.ns = keys.ns ? mat.shininess : 0.0f;
    mtl.d = mat.dissolve; // tinyobjloader folds Tr into it (d wins when both are given)
    mtl.ke = {mat.emission[0], mat.emission[1], mat.emission[2]};
    if (keys.pr) mtl.pr = mat.roughness;
    if (keys.pm) mtl.pm = mat.metallic;
    applyMtlToPbr(mtl, out.pbr);

    auto slot = [&](TextureSlotKind kind) -> IrTextureRef& { return out.textures[size_t(kind)]; };
    const bool hasBase = !mat.diffuse_texname.empty();
    if (hasBase) {
        slot(TextureSlotKind::BaseColor) =
            textureRef(ctx, mat.diffuse_texname, mat.diffuse_texopt, what, "diffuse");
    }
    if (!mat.alpha_texname.empty()) {
        if (hasBase && sameTexture(ctx, mat.alpha_texname, mat.diffuse_texname)) {
            // The base colour texture's alpha is the opacity: a cut-out unless d asked for
            // translucency. (A missing base colour file was reported above.)
            if (slot(TextureSlotKind::BaseColor).image >= 0 &&
                out.pbr.alphaMode == AlphaMode::Opaque) {
                out.pbr.alphaMode = AlphaMode::Mask;
            }
        } else {
            ctx.warn(format("%s: opacity map '%s' is not the base colour texture; separate "
                            "opacity maps are not supported yet (alpha mode from d only)",
                            what.c_str(), mat.alpha_texname.c_str()));
        }
    }

    // norm → normal map; bump/map_bump is the fallback (in OBJ exports nearly always a
    // tangent-space normal map too).
    const bool hasNormal = !mat.normal_texname.empty();
    const std::string& normalName = hasNormal ? mat.normal_texname : mat.bump_texname;
    const tinyobj::texture_option_t& normalOpt = hasNormal ? mat.normal_texopt : mat.bump_texopt;
    if (hasNormal && !mat.bump_texname.empty()) {
        ctx.warn(what + ": both a normal map and a bump map; the bump map is ignored");
    }
    if (!normalName.empty()) {
        slot(TextureSlotKind::Normal) = textureRef(ctx, normalName, normalOpt, what, "normal");
        // MTL's -bm multiplier scales the bump like glTF's normalTexture.scale.
        if (std::isfinite(normalOpt.bump_multiplier)) {
            out.pbr.normalScale = normalOpt.bump_multiplier;
        }
    }

    if (!mat.emissive_texname.empty()) {
        slot(TextureSlotKind::Emissive) =
            textureRef(ctx, mat.emissive_texname, mat.emissive_texopt, what, "emissive");
        // glTF multiplies the texture by the factor; a map_Ke with no (or black) Ke means the
        // texture itself is the emission.
        const Vec3& e = out.pbr.emissiveFactor;
        if (e.x == 0 && e.y == 0 && e.z == 0) out.pbr.emissiveFactor = {1, 1, 1};
    }

    // Maps with no slot (glTF packs roughness and metallic into one texture, which a separate
    // map_Pr / map_Pm is not).
    const std::pair<const std::string*, const char*> ignored[] = {
        {&mat.ambient_texname, "ambient (map_Ka)"},
        {&mat.specular_texname, "specular (map_Ks)"},
        {&mat.specular_highlight_texname, "shininess (map_Ns)"},
        {&mat.displacement_texname, "displacement (disp)"},
        {&mat.reflection_texname, "reflection (refl)"},
        {&mat.roughness_texname, "roughness (map_Pr)"},
        {&mat.metallic_texname, "metallic (map_Pm)"},
        {&mat.sheen_texname, "sheen (map_Ps)"},
    };
    for (const auto& [name, kind] : ignored) {
        if (name->empty()) continue;
        ctx.warn(format("%s: %s texture '%s' ignored (no PBR slot)", what.c_str(), kind,
                        name->c_str()));
    }
    return out;
}

// [SECTION] the fast reader's events

// tinyobjloader's split of an mtllib line: at spaces, '\' escaping the next character; empty
// names between spaces skipped, the last kept even when empty.
std::vector<std::string> splitMtllib(const std::string& s) {
    std::vector<std::string> names;
    std::string name;
    bool escaping = false;
    for (char c : s) {
        if (escaping) {
            escaping = false;
        } else if (c == '\\') {
            escaping = true;
            continue;
        } else if (c == ' ') {
            if (!name.empty()) names.push_back(name);
            name.clear();
            continue;
        }
        name += c;
    }
    names.push_back(name);
    return names;
}

// The events of obj_parse in order, as LoadObj acts on those lines: mtllib reads MTL files
// (the first of its names that loads, skipping those read before), usemtl switches the
// material of the following faces (a name no MTL read so far defines is -1, with a warning
// after the MTL reader's), "g"/"o" start a new shape. LoadObj gathers faces, lines and points
// in a group that it flushes into the shape (exportGroupsToShape) when the material changes and
// at "g", "o" and the end: a flush of an empty group does nothing; a material change clears only
// the group's faces, so its lines and points count again at the next flush. "g" keeps the shape
// only if it has triangles, "o" also if it has lines or points, the end if it has triangles or
// the last flush was not empty.
ObjRead readObjEvents(ObjParse&& parsed, tinyobj::MaterialReader& mtl, IrScene& out) {
    ObjRead read;
    read.geometry = std::move(parsed.geometry);
    std::map<std::string, int> materialByName;
    std::set<std::string> mtlFiles;
    std::vector<std::string> usemtlWarnings;
    int material = -1;
    ObjShape shape;
    uint64_t runStart = 0;                  // the group's faces: triangles [runStart, now)
    size_t groupLines = 0, groupPoints = 0; // and its lines and points
    auto flush = [&](uint64_t at) {
        if (at == runStart && groupLines == 0 && groupPoints == 0) return false;
        if (at > runStart) shape.runs.push_back(ObjRun{runStart, at, material});
        runStart = at;
        shape.lines += groupLines;
        shape.points += groupPoints;
        return true;
    };
    auto newShape = [&](uint64_t at, std::string nextName) {
        shape = ObjShape{};
        shape.name = std::move(nextName);
        runStart = at;
        groupLines = groupPoints = 0;
    };
    for (ObjEvent& e : parsed.events) {
        switch (e.kind) {
        case ObjEvent::Kind::MtlLib:
            for (const std::string& name : splitMtllib(e.text)) {
                if (mtlFiles.count(name)) continue;
                std::string warn, err;
                if (mtl(name, &read.materials, &materialByName, &warn, &err)) {
                    mtlFiles.insert(name);
                    break;
                }
            }
            break;
        case ObjEvent::Kind::UseMtl: {
            const auto it = materialByName.find(e.text);
            const int id = it == materialByName.end() ? -1 : it->second;
            if (it == materialByName.end()) {
                usemtlWarnings.push_back(format("usemtl '%s': no MTL file read defines it; its "
                                                "faces use the default material",
                                                e.text.c_str()));
            }
            if (id != material) {
                flush(e.triangle);
                runStart = e.triangle;
                material = id;
            }
            break;
        }
        case ObjEvent::Kind::Group:
            flush(e.triangle);
            if (!shape.runs.empty()) read.shapes.push_back(std::move(shape));
            newShape(e.triangle, std::move(e.text));
            break;
        case ObjEvent::Kind::Object:
            flush(e.triangle);
            if (!shape.runs.empty() || shape.lines + shape.points > 0)
                read.shapes.push_back(std::move(shape));
            newShape(e.triangle, std::move(e.text));
            break;
        case ObjEvent::Kind::Lines: groupLines += size_t(e.count); break;
        case ObjEvent::Kind::Points: groupPoints += size_t(e.count); break;
        }
    }
    if (flush(read.geometry.triangles.count()) || !shape.runs.empty())
        read.shapes.push_back(std::move(shape));
    for (std::string& w : usemtlWarnings) out.warnings.push_back(std::move(w));
    return read;
}

// [SECTION] meshes

// Distinct (v, vt, vn) index triples of one primitive → its vertex numbers, in order of first
// use. Most triples are the only one with their position index, so a flat table over the
// primitive's range of position indices catches them; only further triples on a position go
// to the hash map.
class VertexNumbering {
public:
    VertexNumbering(int32_t firstPosition, int32_t lastPosition)
        : mFirst(firstPosition), mByPosition(size_t(lastPosition - firstPosition) + 1) {}

    // The vertex number of `c`, and whether it is new (== `next`, the count before the call).
    uint32_t find(const ObjCorner& c, uint32_t next, bool& isNew) {
        Slot& s = mByPosition[size_t(c.v - mFirst)];
        if (s.vertex == kNone) {
            s = {next, c.vt, c.vn};
            isNew = true;
            return next;
        }
        if (s.vt == c.vt && s.vn == c.vn) {
            isNew = false;
            return s.vertex;
        }
        auto [it, inserted] = mOthers.emplace(Key{c.v, c.vt, c.vn}, next);
        isNew = inserted;
        return it->second;
    }

private:
    static constexpr uint32_t kNone = ~0u;
    struct Slot {
        uint32_t vertex = kNone;
        int32_t vt = 0, vn = 0;
    };
    struct Key {
        int32_t v, vt, vn;
        bool operator==(const Key& o) const { return v == o.v && vt == o.vt && vn == o.vn; }
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = uint64_t(uint32_t(k.v)) * 0x9E3779B97F4A7C15ull;
            h ^= (uint64_t(uint32_t(k.vt)) + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full;
            h ^= (uint64_t(uint32_t(k.vn)) + 0x165667B19E3779F9ull) * 0x27D4EB2F165667C5ull;
            return size_t(h ^ (h >> 29));
        }
    };
    int32_t mFirst;
    std::vector<Slot> mByPosition;
    std::unordered_map<Key, uint32_t, KeyHash> mOthers;
};

template <class Floats> bool allFinite(const Floats& v) {
    bool ok = true;
    for (float x : v) ok &= std::isfinite(x);
    return ok;
}

// One primitive under construction: run `run` of a shape, built on any thread; its warnings
// are issued afterwards, in order.
struct PrimitiveJob {
    ObjRun run;
    IrPrimitive prim;
    bool normalsValid = true, uvsValid = true;
    bool normalsFinite = true, uvsFinite = true, colorsFinite = true;
};

// Triangles of `job.run` as a primitive. Each stream is written after a reserve: these
// vectors are large, and value-initialising them first only costs page faults and a memset.
void buildPrimitive(const ObjGeometry& g, PrimitiveJob& job) {
    const ObjTriangles& tris = g.triangles;
    const size_t normalCount = g.normals.size() / 3;
    const size_t uvCount = g.texcoords.size() / 2;
    IrPrimitive& prim = job.prim;
    int32_t first = std::numeric_limits<int32_t>::max(), last = 0;
    tris.forEachCorner(job.run.begin, job.run.end, [&](const ObjCorner& c) {
        first = std::min(first, c.v);
        last = std::max(last, c.v);
    });
    VertexNumbering numbering(first, last);
    auto reserve = [](auto& v, size_t n) {
        v.reserve(n);
        adviseHugePages(v.data(), n * sizeof(v[0]));
    };
    reserve(prim.indices, size_t(job.run.end - job.run.begin) * 3);
    // Positions first; the other streams follow only if valid for every corner.
    std::vector<ObjCorner> corners; // the first corner of each vertex (at most one per corner)
    reserve(corners, size_t(job.run.end - job.run.begin) * 3);
    bool normalsValid = true, uvsValid = true;
    tris.forEachCorner(job.run.begin, job.run.end, [&](const ObjCorner& c) {
        bool isNew = false;
        const uint32_t v = numbering.find(c, uint32_t(corners.size()), isNew);
        prim.indices.push_back(v);
        if (!isNew) return;
        corners.push_back(c);
        normalsValid &= c.vn >= 0 && size_t(c.vn) < normalCount;
        uvsValid &= c.vt >= 0 && size_t(c.vt) < uvCount;
    });
    const size_t count = corners.size();
    reserve(prim.positions, count * 3);
    for (const ObjCorner& c : corners) {
        const float* p = &g.positions[size_t(c.v) * 3];
        for (int i = 0; i < 3; ++i) prim.positions.push_back(p[i]);
    }
    if (normalsValid && normalCount > 0) {
        reserve(prim.normals, count * 3);
        for (const ObjCorner& c : corners) {
            const float* n = &g.normals[size_t(c.vn) * 3];
            for (int i = 0; i < 3; ++i) prim.normals.push_back(n[i]);
        }
    }
    if (uvsValid && uvCount > 0) {
        reserve(prim.uv0, count * 2);
        for (const ObjCorner& c : corners) {
            const float* t = &g.texcoords[size_t(c.vt) * 2];
            prim.uv0.push_back(t[0]);
            prim.uv0.push_back(1.0f - t[1]); // OBJ v-up → glTF v-down (header block)
        }
    }
    if (!g.colors.empty()) {
        reserve(prim.colors, count * 4);
        for (const ObjCorner& c : corners) {
            const float* col = &g.colors[size_t(c.v) * 3];
            for (int i = 0; i < 3; ++i) prim.colors.push_back(col[i]);
            prim.colors.push_back(1.0f);
        }
    }
    job.normalsValid = normalsValid;
    job.uvsValid = uvsValid;
    job.normalsFinite = allFinite(prim.normals);
    job.uvsFinite = allFinite(prim.uv0);
    job.colorsFinite = allFinite(prim.colors);
    if (!job.normalsFinite) prim.normals.clear();
    if (!job.uvsFinite) prim.uv0.clear();
    if (!job.colorsFinite) prim.colors.clear();
}

// The shapes as nodes and meshes under a root named after the file: primitives built in
// parallel, then warnings and materials (converted on first use) in shape and run order.
Result<IrScene, ConvertError> buildScene(Context& ctx, const ObjRead& read, unsigned jobs) {
    IrScene& out = *ctx.out;
    std::vector<PrimitiveJob> prims;
    for (const ObjShape& shape : read.shapes) {
        for (const ObjRun& run : shape.runs) prims.push_back(PrimitiveJob{run, {}});
    }
    parallelFor(prims.size(), jobs, [&](size_t i) { buildPrimitive(read.geometry, prims[i]); });

    std::vector<int> materialOf(read.materials.size(), -2); // -2 = not converted yet
    auto materialFor = [&](int id) {
        if (id < 0 || size_t(id) >= read.materials.size()) return -1;
        int& cached = materialOf[size_t(id)];
        if (cached == -2) {
            out.materials.push_back(convertMaterial(ctx, read.materials[size_t(id)]));
            cached = int(out.materials.size() - 1);
        }
        return cached;
    };
    IrNode root;
    root.name = fs::path(ctx.path).filename().string();
    out.nodes.push_back(root);
    size_t next = 0; // prims[next] is the next shape's first run
    for (const ObjShape& shape : read.shapes) {
        const std::string name = shape.name.empty() ? kDefaultObjectName : shape.name;
        const std::string label = format("mesh '%s'", name.c_str());
        if (shape.lines + shape.points > 0) {
            std::string what;
            if (shape.points > 0) what = format("%zu point(s)", shape.points);
            if (shape.lines > 0) what += format("%s%zu line(s)", what.empty() ? "" : ", ", shape.lines);
            ctx.warn(format("%s: dropped %s; only triangles are imported", label.c_str(),
                            what.c_str()));
        }
        if (shape.runs.empty()) continue;
        IrMesh irMesh;
        irMesh.name = name;
        bool warnedNormals = false, warnedUvs = false;
        for (size_t r = 0; r < shape.runs.size(); ++r) {
            PrimitiveJob& job = prims[next++];
            if (!job.normalsValid && !read.geometry.normals.empty() && !warnedNormals) {
                ctx.warn(label + ": normal indices missing or out of range on some faces; "
                                 "normals dropped (they will be generated)");
                warnedNormals = true;
            }
            if (!job.uvsValid && !read.geometry.texcoords.empty() && !warnedUvs) {
                ctx.warn(label + ": texture coordinate indices missing or out of range on "
                                 "some faces; UVs dropped");
                warnedUvs = true;
            }
            if (!job.normalsFinite)
                ctx.warn(label + ": non-finite normals; dropped (they will be generated)");
            if (!job.uvsFinite) ctx.warn(label + ": non-finite UV set 0; dropped");
            if (!job.colorsFinite) ctx.warn(label + ": non-finite vertex colours; dropped");
            job.prim.material = materialFor(job.run.material);
            irMesh.primitives.push_back(std::move(job.prim));
        }
        IrNode node;
        node.name = name;
        node.parent = 0;
        node.mesh = int(out.meshes.size());
        out.meshes.push_back(std::move(irMesh));
        out.nodes.push_back(std::move(node));
    }
    if (out.meshes.empty()) {
        return ConvertError{ConvertErrorKind::Input,
                            ctx.path + ": " +
                                format("no triangle meshes (%zu object(s) in the file, none with "
                                       "triangles)",
                                       read.shapes.size())};
    }
    return std::move(out);
}

} // namespace

Result<IrScene, ConvertError> importObjWith(const std::string& path,
                                            const ObjImportOptions& options, ObjReader* used) {
    auto inputError = [&](std::string message) {
        return ConvertError{ConvertErrorKind::Input, path + ": " + message};
    };
    if (!isRegularFile(path)) return inputError("no such file (or not a regular file)");
    // std::bad_alloc must not cross our module boundary.
    try {
        ObjText obj;
        if (!obj.open(path)) return inputError("could not be read");
        const fs::path sourceParent = fs::path(path).parent_path();
        Context ctx;
        ctx.path = path;
        ctx.sourceDir = sourceParent.empty() ? fs::path(".") : sourceParent;
        IrScene out;
        out.sourcePath = path;
        ctx.out = &out;
        MtlReader mtlReader(ctx.sourceDir, fs::path(path), out, ctx.keys);

        std::optional<ObjParse> parsed;
        if (!options.tinyobjOnly) {
            parsed = parseObjText(obj.view(), ObjParseOptions{options.jobs, options.chunkBytes,
                                                              readNumberLinesWithTinyobj});
        }
        if (used) *used = parsed ? ObjReader::Fast : ObjReader::Tinyobj;
        ObjRead read;
        if (parsed) {
            read = readObjEvents(std::move(*parsed), mtlReader, out);
        } else {
            auto r = readObjWithTinyobj(path, obj.data(), obj.view().size(), mtlReader, out);
            if (!r) return r.error();
            read = std::move(*r);
        }
        return buildScene(ctx, read, options.jobs);
    } catch (const std::exception& e) {
        return inputError(format("import failed: %s", e.what()));
    } catch (...) {
        return inputError("import failed (unknown exception)");
    }
}

Result<IrScene, ConvertError> importObj(const std::string& path, unsigned jobs) {
    return importObjWith(path, ObjImportOptions{jobs});
}

} // namespace pnb::converter
