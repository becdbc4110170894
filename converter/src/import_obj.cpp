// import_obj.cpp — Wavefront OBJ/MTL into the scene IR through tinyobjloader (Debian's
// libtinyobjloader-dev). Replaces assimp for .obj: parsing the 1M-triangle benchmark OBJ took
// assimp 1.37 s CPU and tinyobjloader 0.87 s (docs/CONVERTER.md, "Speed").
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
//   equivalent, and fewer vertices make it faster). Polygons are triangulated by tinyobjloader
//   (quads along the shorter diagonal, larger polygons by ear clipping).
// - V flip: IR UVs follow glTF (v = 0 is the top row), OBJ's v = 0 is the bottom row: (u, 1 - v).
// - Streams: a primitive gets normals (uvs) only when every corner has a valid vn (vt) index;
//   otherwise they are dropped with a warning naming the mesh and the mesh stage generates
//   normals. A normal/UV/colour stream holding NaN/Inf is dropped with a warning naming the mesh;
//   non-finite positions pass through (the mesh stage drops their triangles with a warning).
//   Vertex colours ("v x y z r g b") are kept when every vertex of the file has one.
// - Errors (exit code 2), naming the file and the line: a face or point/line index that is 0 or
//   not a number (tinyobjloader's parse error), a position index outside the file's vertices
//   (found again by scanning the text, since tinyobjloader keeps no line numbers).
// - Points and lines: dropped with a warning naming the mesh (the IR is triangles only).
//   tinyobjloader discards a "g" group that has only points or lines before we see it, so those
//   go unreported; a file with no triangles at all is an error.
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
// - Early texture report: each texture file an MTL's materials would use (base colour, normal,
//   emissive) is passed to the caller's `found` callback when the MTL is read, during the parse,
//   so convertScene can decode it meanwhile (image_prefetch.h).
// - The OBJ file is read with one read() into pre-faulted memory (ObjText): it is the largest
//   input the converter reads.
//
// Does NOT do: processing of any kind, image decoding, smoothing groups (the mesh stage's
// normals are smooth), tinyobjloader's extensions (vw skin weights, t subdivision tags).
#include "pnb_converter/importers.h"

#include <fcntl.h>
#include <sys/mman.h>
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
#include <functional>
#include <istream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <streambuf>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "import_paths.h"
#include "pnb_converter/mtl_to_pbr.h"

namespace pnb::converter {

namespace {

namespace fs = std::filesystem;
using namespace import_detail;

static_assert(sizeof(tinyobj::real_t) == sizeof(float),
              "Debian's libtinyobjloader.so is built with float; the streams are copied as such");

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

// The OBJ file's bytes, read with one read() into memory that mmap(MAP_POPULATE) gave whole:
// reading the 94 MB benchmark OBJ with readFile cost ~10 % of its conversion, in a copy through
// stdio's buffer and one page fault per 4 KiB page of the growing string. The file itself is
// not mapped: another program truncating it during the parse would kill us with SIGBUS.
class ObjText {
public:
    bool open(const fs::path& path) {
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return false;
        struct stat st {};
        bool ok = false;
        if (::fstat(fd, &st) == 0 && st.st_size > 0) {
            void* p = ::mmap(nullptr, size_t(st.st_size), PROT_READ | PROT_WRITE,
                             MAP_PRIVATE | MAP_ANONYMOUS | MAP_POPULATE, -1, 0);
            if (p != MAP_FAILED) {
                mMapped = static_cast<char*>(p);
                mCapacity = size_t(st.st_size);
                ok = true;
                while (mSize < mCapacity) { // a file that shrank meanwhile is read as it is
                    const ssize_t n = ::read(fd, mMapped + mSize, mCapacity - mSize);
                    if (n < 0 && errno == EINTR) continue;
                    if (n < 0) ok = false;
                    if (n <= 0) break;
                    mSize += size_t(n);
                }
            }
        }
        ::close(fd);
        if (mMapped) return ok;
        std::optional<std::string> bytes = readFile(path); // empty, or not mappable
        if (!bytes) return false;
        mCopy = std::move(*bytes);
        return true;
    }
    ObjText() = default;
    ObjText(const ObjText&) = delete;
    ObjText& operator=(const ObjText&) = delete;
    ~ObjText() {
        if (mMapped) ::munmap(mMapped, mCapacity);
    }

    std::string_view view() const {
        return mMapped ? std::string_view(mMapped, mSize) : std::string_view(mCopy);
    }
    char* data() { return mMapped ? mMapped : mCopy.data(); }

private:
    char* mMapped = nullptr;
    size_t mSize = 0, mCapacity = 0;
    std::string mCopy; // when not mapped
};

// An istream over bytes we already hold, without copying them into a stringbuf (read only).
class MemoryBuffer : public std::streambuf {
public:
    explicit MemoryBuffer(std::string_view bytes) {
        char* begin = const_cast<char*>(bytes.data()); // streambuf's get area is not const
        setg(begin, begin, begin + bytes.size());
    }
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
              std::map<std::string, MtlKeys>& keys,
              const std::function<void(const std::string&)>& found)
        : mSourceDir(std::move(sourceDir)), mObjPath(std::move(objPath)), mOut(out), mKeys(keys),
          mFound(found) {}

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
        // The texture files these materials would use (convertMaterial's slots), resolved as
        // imageForReference will resolve them, for the caller to start decoding.
        if (mFound) {
            for (size_t i = first; i < materials->size(); ++i) {
                const tinyobj::material_t& m = (*materials)[i];
                const std::string& normal =
                    m.normal_texname.empty() ? m.bump_texname : m.normal_texname;
                for (const std::string* ref : {&m.diffuse_texname, &normal, &m.emissive_texname}) {
                    if (ref->empty()) continue;
                    if (auto r = resolveReference(mSourceDir, *ref)) mFound(r->path.string());
                }
            }
        }
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
    const std::function<void(const std::string&)>& mFound;
};

// Blanks every "vw" line (tinyobjloader's skin-weight extension, which the importer ignores)
// in place, keeping the line count: tinyobjloader converts a vw joint id to int without a range
// check, which is undefined for a huge number (found by the obj_import fuzzer: "vw 6e21 ...").
void blankSkinWeightLines(ObjText& obj) {
    const std::string_view text = obj.view();
    char* bytes = obj.data();
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find_first_of("\r\n", pos); // tinyobjloader ends a line at either
        if (end == std::string_view::npos) end = text.size();
        size_t at = pos;
        while (at < end && (text[at] == ' ' || text[at] == '\t')) ++at;
        if (end - at > 2 && text[at] == 'v' && text[at + 1] == 'w' && (text[at + 2] == ' ' || text[at + 2] == '\t'))
            std::fill(bytes + pos, bytes + end, ' ');
        pos = end + 1;
    }
}

// The first line of `text` with a face index outside `vertexCount` positions (tinyobjloader's
// rules: k > 0 is k - 1, k < 0 counts back from the vertices read so far), or 0. Only called
// once something is known to be wrong. (Point and line indices are not checked: those elements
// are dropped.)
size_t lineOfBadIndex(std::string_view text, size_t vertexCount) {
    size_t line = 0, seen = 0, pos = 0;
    while (pos < text.size()) {
        size_t end = text.find_first_of("\r\n", pos); // tinyobjloader ends a line at either
        if (end == std::string_view::npos) end = text.size();
        std::string_view l = text.substr(pos, end - pos);
        pos = end + 1;
        ++line;
        while (!l.empty() && (l.front() == ' ' || l.front() == '\t')) l.remove_prefix(1);
        if (l.size() < 2 || (l[1] != ' ' && l[1] != '\t')) continue;
        if (l[0] == 'v') {
            ++seen;
            continue;
        }
        if (l[0] != 'f') continue;
        const std::string s(l.substr(2));
        const char* p = s.c_str();
        while (*p != '\0') {
            p += std::strspn(p, " \t\r");
            if (*p == '\0') break;
            const long k = std::strtol(p, nullptr, 10);
            const long index = k > 0 ? k - 1 : long(seen) + k;
            if (index < 0 || size_t(index) >= vertexCount) return line;
            p += std::strcspn(p, " \t\r");
        }
    }
    return 0;
}

// Line `number` (1-based) of `text`, shortened for a message.
std::string lineText(std::string_view text, size_t number) {
    size_t pos = 0;
    for (size_t line = 1; line < number && pos < text.size(); ++line) {
        const size_t end = text.find('\n', pos);
        pos = end == std::string_view::npos ? text.size() : end + 1;
    }
    std::string_view l = text.substr(std::min(pos, text.size()));
    l = l.substr(0, std::min(l.find_first_of("\r\n"), size_t(80)));
    std::string out;
    for (char c : l) out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
    return out;
}

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

// [SECTION] meshes

// Distinct (v, vt, vn) index triples of one primitive → its vertex numbers, in order of first
// use. Most triples are the only one with their position index, so a flat table indexed by
// position catches them; only further triples on a position go to the hash map.
class VertexNumbering {
public:
    explicit VertexNumbering(size_t positionCount) : mByPosition(positionCount) {}

    // Starts a new primitive: every earlier entry becomes stale at once.
    void reset() {
        ++mGeneration;
        mOthers.clear();
    }

    // The vertex number of `idx`, and whether it is new (== the count before the call).
    uint32_t find(const tinyobj::index_t& idx, uint32_t next, bool& isNew) {
        Slot& s = mByPosition[size_t(idx.vertex_index)];
        if (s.generation != mGeneration) {
            s = {mGeneration, next, idx.texcoord_index, idx.normal_index};
            isNew = true;
            return next;
        }
        if (s.vt == idx.texcoord_index && s.vn == idx.normal_index) {
            isNew = false;
            return s.vertex;
        }
        const Key key{idx.vertex_index, idx.texcoord_index, idx.normal_index};
        auto [it, inserted] = mOthers.emplace(key, next);
        isNew = inserted;
        return it->second;
    }

private:
    struct Slot {
        uint32_t generation = 0, vertex = 0;
        int vt = 0, vn = 0;
    };
    struct Key {
        int v, vt, vn;
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
    std::vector<Slot> mByPosition;
    std::unordered_map<Key, uint32_t, KeyHash> mOthers;
    uint32_t mGeneration = 0;
};

bool allFinite(const std::vector<float>& v) {
    bool ok = true;
    for (float x : v) ok &= std::isfinite(x);
    return ok;
}

// Faces [begin, end) of `shape` (triangles, one material) as a primitive.
IrPrimitive buildPrimitive(const tinyobj::attrib_t& attrib, const tinyobj::mesh_t& mesh,
                           size_t begin, size_t end, VertexNumbering& numbering,
                           bool& normalsValid, bool& uvsValid) {
    const size_t normalCount = attrib.normals.size() / 3;
    const size_t uvCount = attrib.texcoords.size() / 2;
    const bool hasColors = !attrib.colors.empty();
    IrPrimitive prim;
    prim.indices.resize((end - begin) * 3);
    numbering.reset();
    normalsValid = uvsValid = true;
    uint32_t count = 0;
    // Positions first; the other streams follow only if valid for every corner.
    std::vector<const tinyobj::index_t*> corners;
    corners.reserve((end - begin) * 3);
    for (size_t c = begin * 3; c < end * 3; ++c) {
        const tinyobj::index_t& idx = mesh.indices[c];
        bool isNew = false;
        const uint32_t v = numbering.find(idx, count, isNew);
        prim.indices[c - begin * 3] = v;
        if (!isNew) continue;
        ++count;
        corners.push_back(&idx);
        normalsValid &= idx.normal_index >= 0 && size_t(idx.normal_index) < normalCount;
        uvsValid &= idx.texcoord_index >= 0 && size_t(idx.texcoord_index) < uvCount;
    }
    prim.positions.resize(size_t(count) * 3);
    float* pos = prim.positions.data();
    for (const tinyobj::index_t* idx : corners) {
        std::memcpy(pos, &attrib.vertices[size_t(idx->vertex_index) * 3], 3 * sizeof(float));
        pos += 3;
    }
    if (normalsValid && normalCount > 0) {
        prim.normals.resize(size_t(count) * 3);
        float* n = prim.normals.data();
        for (const tinyobj::index_t* idx : corners) {
            std::memcpy(n, &attrib.normals[size_t(idx->normal_index) * 3], 3 * sizeof(float));
            n += 3;
        }
    }
    if (uvsValid && uvCount > 0) {
        prim.uv0.resize(size_t(count) * 2);
        float* uv = prim.uv0.data();
        for (const tinyobj::index_t* idx : corners) {
            const float* t = &attrib.texcoords[size_t(idx->texcoord_index) * 2];
            uv[0] = t[0];
            uv[1] = 1.0f - t[1]; // OBJ v-up → glTF v-down (header block)
            uv += 2;
        }
    }
    if (hasColors) {
        prim.colors.resize(size_t(count) * 4);
        float* col = prim.colors.data();
        for (const tinyobj::index_t* idx : corners) {
            std::memcpy(col, &attrib.colors[size_t(idx->vertex_index) * 3], 3 * sizeof(float));
            col[3] = 1.0f;
            col += 4;
        }
    }
    return prim;
}

} // namespace

Result<IrScene, ConvertError> importObj(const std::string& path,
                                        const std::function<void(const std::string&)>& found) {
    auto inputError = [&](std::string message) {
        return ConvertError{ConvertErrorKind::Input, path + ": " + message};
    };
    if (!isRegularFile(path)) return inputError("no such file (or not a regular file)");
    // tinyobjloader reports bad data through its error string, but std::bad_alloc must not
    // cross our module boundary either.
    try {
        ObjText obj;
        if (!obj.open(path)) return inputError("could not be read");
        blankSkinWeightLines(obj);
        const std::string_view text = obj.view();
        const fs::path sourceParent = fs::path(path).parent_path();
        Context ctx;
        ctx.path = path;
        ctx.sourceDir = sourceParent.empty() ? fs::path(".") : sourceParent;
        IrScene out;
        out.sourcePath = path;
        ctx.out = &out;

        tinyobj::attrib_t attrib;
        std::vector<tinyobj::shape_t> shapes;
        std::vector<tinyobj::material_t> materials;
        std::string warn, err;
        MtlReader mtlReader(ctx.sourceDir, fs::path(path), out, ctx.keys, found);
        bool parsed;
        {
            MemoryBuffer buffer(text);
            std::istream stream(&buffer);
            parsed = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream,
                                      &mtlReader, /*triangulate=*/true,
                                      /*default_vcols_fallback=*/false);
        }
        if (!parsed) {
            // tinyobjloader: "Failed parse `f' line(e.g. zero value for face index. line 5.)"
            while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
            const size_t at = err.rfind("line ");
            const size_t line =
                at == std::string::npos ? 0 : std::strtoul(&err[at + 5], nullptr, 10);
            if (line > 0 && err.rfind("Failed parse `", 0) == 0 && err.size() > 15) {
                return inputError(format("line %zu: malformed '%c' element (an index is 0 or not "
                                         "a number): \"%s\"", line, err[14],
                                         lineText(text, line).c_str()));
            }
            return inputError(err.empty() ? std::string("not a valid OBJ file") : err);
        }
        const size_t vertexCount = attrib.vertices.size() / 3;
        auto badIndex = [&]() {
            const size_t line = lineOfBadIndex(text, vertexCount);
            return inputError(line > 0 ? format("line %zu: vertex index out of range 1..%zu",
                                                line, vertexCount)
                                       : format("vertex index out of range 1..%zu", vertexCount));
        };
        // tinyobjloader only warns about out-of-range indices (and skips such a polygon).
        {
            std::istringstream lines(warn);
            std::string line;
            bool degenerateNoted = false;
            while (std::getline(lines, line)) {
                if (line.empty() || line == ".") continue;
                if (line.find("Vertex indices out of bounds") != std::string::npos ||
                    line.find("invalid vertex index") != std::string::npos) {
                    return badIndex();
                }
                // Normal/texcoord index problems are reported per mesh below.
                if (line.find("indices out of bounds") != std::string::npos) continue;
                if (line.find("Degenerated face") != std::string::npos) {
                    if (!degenerateNoted) {
                        out.warnings.push_back("faces with fewer than 3 vertices dropped");
                        degenerateNoted = true;
                    }
                    continue;
                }
                // "material [ 'name' ] not found in .mtl"
                if (line.rfind("material [ '", 0) == 0) {
                    const size_t close = line.rfind("' ]");
                    const std::string name =
                        close != std::string::npos && close > 12 ? line.substr(12, close - 12)
                                                                  : line;
                    out.warnings.push_back(format("usemtl '%s': no MTL file read defines it; "
                                                  "its faces use the default material",
                                                  name.c_str()));
                    continue;
                }
                if (line.find("Failed to load material file") != std::string::npos) continue;
                out.warnings.push_back(line);
            }
        }

        std::vector<int> materialOf(materials.size(), -2); // -2 = not converted yet
        auto materialFor = [&](int id) {
            if (id < 0 || size_t(id) >= materials.size()) return -1;
            int& cached = materialOf[size_t(id)];
            if (cached == -2) {
                out.materials.push_back(convertMaterial(ctx, materials[size_t(id)]));
                cached = int(out.materials.size() - 1);
            }
            return cached;
        };

        IrNode root;
        root.name = fs::path(path).filename().string();
        out.nodes.push_back(root);
        VertexNumbering numbering(vertexCount);
        for (const tinyobj::shape_t& shape : shapes) {
            const tinyobj::mesh_t& mesh = shape.mesh;
            const std::string name = shape.name.empty() ? kDefaultObjectName : shape.name;
            const std::string label = format("mesh '%s'", name.c_str());
            const size_t lineCount = shape.lines.num_line_vertices.size();
            const size_t pointCount = shape.points.indices.size();
            if (lineCount + pointCount > 0) {
                std::string what;
                if (pointCount > 0) what = format("%zu point(s)", pointCount);
                if (lineCount > 0) {
                    what += format("%s%zu line(s)", what.empty() ? "" : ", ", lineCount);
                }
                ctx.warn(format("%s: dropped %s; only triangles are imported", label.c_str(),
                                what.c_str()));
            }
            const size_t faces = mesh.num_face_vertices.size();
            if (faces == 0) continue;
            if (mesh.indices.size() != faces * 3 || mesh.material_ids.size() != faces) {
                return inputError(format("object '%s': inconsistent triangulation",
                                         name.c_str()));
            }
            for (const tinyobj::index_t& idx : mesh.indices) {
                if (idx.vertex_index < 0 || size_t(idx.vertex_index) >= vertexCount) {
                    return badIndex();
                }
            }
            IrMesh irMesh;
            irMesh.name = name;
            bool warnedNormals = false, warnedUvs = false;
            for (size_t begin = 0; begin < faces;) {
                size_t end = begin + 1;
                while (end < faces && mesh.material_ids[end] == mesh.material_ids[begin]) ++end;
                bool normalsValid = true, uvsValid = true;
                IrPrimitive prim = buildPrimitive(attrib, mesh, begin, end, numbering,
                                                  normalsValid, uvsValid);
                if (!normalsValid && !attrib.normals.empty() && !warnedNormals) {
                    ctx.warn(label + ": normal indices missing or out of range on some faces; "
                                     "normals dropped (they will be generated)");
                    warnedNormals = true;
                }
                if (!uvsValid && !attrib.texcoords.empty() && !warnedUvs) {
                    ctx.warn(label + ": texture coordinate indices missing or out of range on "
                                     "some faces; UVs dropped");
                    warnedUvs = true;
                }
                if (!allFinite(prim.normals)) {
                    prim.normals.clear();
                    ctx.warn(label + ": non-finite normals; dropped (they will be generated)");
                }
                if (!allFinite(prim.uv0)) {
                    prim.uv0.clear();
                    ctx.warn(label + ": non-finite UV set 0; dropped");
                }
                if (!allFinite(prim.colors)) {
                    prim.colors.clear();
                    ctx.warn(label + ": non-finite vertex colours; dropped");
                }
                prim.material = materialFor(mesh.material_ids[begin]);
                irMesh.primitives.push_back(std::move(prim));
                begin = end;
            }
            IrNode node;
            node.name = name;
            node.parent = 0;
            node.mesh = int(out.meshes.size());
            out.meshes.push_back(std::move(irMesh));
            out.nodes.push_back(std::move(node));
        }
        if (out.meshes.empty()) {
            return inputError(format("no triangle meshes (%zu object(s) in the file, none with "
                                     "triangles)", shapes.size()));
        }
        return out;
    } catch (const std::exception& e) {
        return inputError(format("import failed: %s", e.what()));
    } catch (...) {
        return inputError("import failed (unknown exception)");
    }
}

} // namespace pnb::converter
