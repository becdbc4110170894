// pnb-inspect's report and check modes (see inspect.h).
//
// Both output formats are printed from the same sources: a chunk table built from the container
// index (valid even when payloads are damaged) and the Scene from readScene(). Derived values
// (triangle counts, stage lists, durations) come from one helper each so text and JSON agree.
//
// Index: [SECTION] enum names, [SECTION] escaping and numbers, [SECTION] JSON emitter,
//        [SECTION] text tables, [SECTION] chunk table, [SECTION] derived values,
//        [SECTION] text report, [SECTION] JSON report, [SECTION] runInspect

#include "inspect.h"

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

#include "pnb/container.h"
#include "pnb/error.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/tags.h"

namespace pnb {

namespace {

// [SECTION] enum names
// These strings are part of the tool's output contract (scripts match on them): snake_case,
// never renamed. The static_asserts catch an enum growing without a name here.

constexpr const char* kStageNames[] = {"vertex",  "fragment",     "geometry",
                                       "compute", "tess_control", "tess_evaluation"};
constexpr const char* kDimensionNames[] = {"2d", "cube"};
constexpr const char* kFormatNames[] = {"r8",    "rg8",     "rgb8", "rgba8", "r16f",
                                        "rg16f", "rgba16f", "r32f", "rg32f", "rgba32f",
                                        "bc1",   "bc3",     "bc4",  "bc5",   "bc7"};
constexpr const char* kColorSpaceNames[] = {"linear", "srgb"};
constexpr const char* kSwizzleNames[] = {"r", "g", "b", "a", "0", "1"};
constexpr const char* kMinFilterNames[] = {
    "nearest",          "linear", "nearest_mip_nearest", "linear_mip_nearest", "nearest_mip_linear",
    "linear_mip_linear"};
constexpr const char* kMagFilterNames[] = {"nearest", "linear"};
constexpr const char* kWrapNames[] = {"repeat", "mirrored_repeat", "clamp_to_edge"};
constexpr const char* kAlphaModeNames[] = {"opaque", "mask", "blend"};
constexpr const char* kShadingPathNames[] = {"deferred", "forward"};
constexpr const char* kSlotNames[] = {"base_color", "metallic_roughness", "normal", "occlusion",
                                      "emissive"};
constexpr const char* kPrimitiveNames[] = {"triangles", "lines", "points"};
constexpr const char* kIndexTypeNames[] = {"u16", "u32"};
constexpr const char* kSemanticNames[] = {"position",  "normal", "tangent", "texcoord0",
                                          "texcoord1", "color0", "joints0", "weights0"};
constexpr const char* kComponentNames[] = {"f32", "f16", "i8", "u8", "i16", "u16", "i32", "u32"};
constexpr const char* kEncodingNames[] = {"plain", "octahedral"};
constexpr const char* kLightTypeNames[] = {"directional", "point", "spot"};
constexpr const char* kProjectionNames[] = {"perspective", "orthographic"};
constexpr const char* kInterpolationNames[] = {"linear", "catmull_rom"};
constexpr const char* kEnvironmentSourceNames[] = {"image", "analytic_sky"};
constexpr const char* kCompressionNames[] = {"none", "zstd"};

#define PNB_NAMES_MATCH(names, Enum)                                                               \
    static_assert(std::size(names) == size_t(Enum::Count), #Enum " needs a name for every value")
PNB_NAMES_MATCH(kStageNames, ShaderStage);
PNB_NAMES_MATCH(kDimensionNames, TextureDimension);
PNB_NAMES_MATCH(kFormatNames, TextureFormat);
PNB_NAMES_MATCH(kColorSpaceNames, ColorSpace);
PNB_NAMES_MATCH(kSwizzleNames, Swizzle);
PNB_NAMES_MATCH(kMinFilterNames, MinFilter);
PNB_NAMES_MATCH(kMagFilterNames, MagFilter);
PNB_NAMES_MATCH(kWrapNames, Wrap);
PNB_NAMES_MATCH(kAlphaModeNames, AlphaMode);
PNB_NAMES_MATCH(kShadingPathNames, ShadingPath);
PNB_NAMES_MATCH(kSlotNames, TextureSlotKind);
PNB_NAMES_MATCH(kPrimitiveNames, Primitive);
PNB_NAMES_MATCH(kIndexTypeNames, IndexType);
PNB_NAMES_MATCH(kSemanticNames, VertexSemantic);
PNB_NAMES_MATCH(kComponentNames, ComponentType);
PNB_NAMES_MATCH(kEncodingNames, VertexEncoding);
PNB_NAMES_MATCH(kLightTypeNames, LightType);
PNB_NAMES_MATCH(kProjectionNames, Projection);
PNB_NAMES_MATCH(kInterpolationNames, Interpolation);
PNB_NAMES_MATCH(kEnvironmentSourceNames, EnvironmentSource);
#undef PNB_NAMES_MATCH

// The decoders reject out-of-range enums, but Compression comes straight from header flags and
// the inspector must not index past a table whatever it is handed.
template <class E, size_t N> const char* nameOf(E value, const char* const (&names)[N]) {
    size_t i = size_t(value);
    return i < N ? names[i] : "unknown";
}

// [SECTION] escaping and numbers

// Length of the valid UTF-8 sequence at s[i] (1..4), or 0 if the bytes there are not one
// (overlong forms, surrogates and code points past U+10FFFF are invalid, as RFC 3629 says).
size_t utf8SequenceLength(std::string_view s, size_t i) {
    const auto byte = [&](size_t k) { return i + k < s.size() ? uint8_t(s[i + k]) : 0u; };
    const auto cont = [&](size_t k, unsigned lo = 0x80, unsigned hi = 0xBF) {
        unsigned b = byte(k);
        return i + k < s.size() && b >= lo && b <= hi;
    };
    unsigned b0 = byte(0);
    if (b0 < 0x80) return 1;
    if (b0 >= 0xC2 && b0 <= 0xDF) return cont(1) ? 2 : 0;
    if (b0 >= 0xE0 && b0 <= 0xEF) {
        unsigned lo = b0 == 0xE0 ? 0xA0 : 0x80, hi = b0 == 0xED ? 0x9F : 0xBF;
        return cont(1, lo, hi) && cont(2) ? 3 : 0;
    }
    if (b0 >= 0xF0 && b0 <= 0xF4) {
        unsigned lo = b0 == 0xF0 ? 0x90 : 0x80, hi = b0 == 0xF4 ? 0x8F : 0xBF;
        return cont(1, lo, hi) && cont(2) && cont(3) ? 4 : 0;
    }
    return 0;
}

// Strings from the file printed to a terminal: control bytes (C0, DEL, and C1 as U+0080..U+009F,
// which some terminals obey) and invalid UTF-8 become visible \xNN escapes, so a hostile name
// cannot move the cursor or hide text.
std::string textEscape(std::string_view s) {
    std::string out;
    char buf[8];
    for (size_t i = 0; i < s.size();) {
        size_t n = utf8SequenceLength(s, i);
        bool c1 = n == 2 && uint8_t(s[i]) == 0xC2 && uint8_t(s[i + 1]) < 0xA0;
        uint8_t b = uint8_t(s[i]);
        if (n == 0 || c1 || b < 0x20 || b == 0x7F) {
            size_t count = n == 0 ? 1 : n;
            for (size_t k = 0; k < count; ++k) {
                std::snprintf(buf, sizeof(buf), "\\x%02x", unsigned(uint8_t(s[i + k])));
                out += buf;
            }
            i += count;
        } else {
            out.append(s.substr(i, n));
            i += n;
        }
    }
    return out;
}

// A JSON string literal (RFC 8259). Invalid UTF-8 becomes U+FFFD so the document stays valid
// UTF-8 for strict parsers; DEL and C1 controls are escaped for the same terminal reason as text.
std::string jsonQuote(std::string_view s) {
    std::string out = "\"";
    char buf[8];
    for (size_t i = 0; i < s.size();) {
        size_t n = utf8SequenceLength(s, i);
        uint8_t b = uint8_t(s[i]);
        if (n == 0) {
            out += "\\ufffd";
            i += 1;
            continue;
        }
        if (n == 2 && b == 0xC2 && uint8_t(s[i + 1]) < 0xA0) {
            std::snprintf(buf, sizeof(buf), "\\u%04x", unsigned(uint8_t(s[i + 1])));
            out += buf;
        } else if (n > 1) {
            out.append(s.substr(i, n));
        } else if (b == '"') {
            out += "\\\"";
        } else if (b == '\\') {
            out += "\\\\";
        } else if (b == '\n') {
            out += "\\n";
        } else if (b == '\r') {
            out += "\\r";
        } else if (b == '\t') {
            out += "\\t";
        } else if (b < 0x20 || b == 0x7F) {
            std::snprintf(buf, sizeof(buf), "\\u%04x", unsigned(b));
            out += buf;
        } else {
            out += char(b);
        }
        i += n;
    }
    return out + "\"";
}

// Shortest text that reads back as the same float: stable across runs and platforms, and short
// for round values ("0.8", not "0.800000012"). Non-finite values are spelled as printf does.
std::string num(float v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v < 0 ? "-inf" : "inf";
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof(buf), v);
    return std::string(buf, r.ptr);
}

std::string fixed(double v, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
    return buf;
}

std::string u64(uint64_t v) {
    return std::to_string(v);
}

std::string vecText(std::initializer_list<float> values) {
    std::string s = "(";
    for (float v : values)
        s += (s.size() > 1 ? ", " : "") + num(v);
    return s + ")";
}
std::string vecText(const Vec3& v) {
    return vecText({v.x, v.y, v.z});
}
std::string vecText(const Vec4& v) {
    return vecText({v.x, v.y, v.z, v.w});
}

bool isEmpty(const Aabb& b) {
    return b.min.x > b.max.x || b.min.y > b.max.y || b.min.z > b.max.z;
}

std::string boundsText(const Aabb& b) {
    return isEmpty(b) ? "empty" : vecText(b.min) + ".." + vecText(b.max);
}

// A name for text output: "-" for none or empty, escaped otherwise.
std::string nameText(const Scene& s, StringRef ref) {
    std::string_view v = s.str(ref);
    return v.empty() ? "-" : textEscape(v);
}

// [SECTION] JSON emitter
// Pretty-printed with two-space indents; arrays of numbers (vectors) stay on one line.

class Json {
public:
    std::string out;

    void beginObject(bool inlined = false) { open('{', inlined); }
    void endObject() { close('}'); }
    void beginArray(bool inlined = false) { open('[', inlined); }
    void endArray() { close(']'); }

    Json& key(std::string_view k) {
        element();
        out += jsonQuote(k);
        out += ": ";
        mAfterKey = true;
        return *this;
    }
    void str(std::string_view v) { raw(jsonQuote(v)); }
    void uint(uint64_t v) { raw(std::to_string(v)); }
    void boolean(bool v) { raw(v ? "true" : "false"); }
    void null() { raw("null"); }
    // JSON has no NaN or infinity: those become null.
    void number(float v) { raw(std::isfinite(v) ? num(v) : "null"); }
    void number(double v, int decimals) { raw(std::isfinite(v) ? fixed(v, decimals) : "null"); }

    void vec(std::initializer_list<float> values) {
        beginArray(true);
        for (float v : values)
            number(v);
        endArray();
    }
    void vec(const Vec3& v) { vec({v.x, v.y, v.z}); }
    void vec(const Vec4& v) { vec({v.x, v.y, v.z, v.w}); }
    void bounds(const Aabb& b) {
        if (isEmpty(b)) return null();
        beginObject(true);
        key("min").vec(b.min);
        key("max").vec(b.max);
        endObject();
    }
    // A StringRef: null for none, so "no name" and "empty name" stay distinguishable.
    void name(const Scene& s, StringRef ref) {
        if (ref == kNone) return null();
        str(s.str(ref));
    }
    void index(uint32_t ref) {
        if (ref == kNone) return null();
        uint(ref);
    }

private:
    struct Frame {
        bool inlined;
        size_t count;
    };
    std::vector<Frame> mStack;
    bool mAfterKey = false;

    void element() {
        if (mAfterKey) {
            mAfterKey = false;
            return;
        }
        if (mStack.empty()) return;
        Frame& f = mStack.back();
        if (f.count++ > 0) out += f.inlined ? ", " : ",";
        if (!f.inlined) newline(mStack.size());
    }
    void raw(std::string_view text) {
        element();
        out += text;
    }
    void open(char c, bool inlined) {
        element();
        out += c;
        mStack.push_back({inlined || (!mStack.empty() && mStack.back().inlined), 0});
    }
    void close(char c) {
        Frame f = mStack.back();
        mStack.pop_back();
        if (!f.inlined && f.count > 0) newline(mStack.size());
        out += c;
        if (mStack.empty()) out += '\n';
    }
    void newline(size_t depth) {
        out += '\n';
        out.append(depth * 2, ' ');
    }
};

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

// [SECTION] chunk table

enum class ChunkKind { Known, Unknown, Toc };

bool isKnownTag(Tag t) { return streamOrderRank(t) >= 0; }

const char* kindName(ChunkKind k) {
    return k == ChunkKind::Known ? "known" : k == ChunkKind::Unknown ? "unknown" : "toc";
}

struct ChunkRow {
    ChunkHeader header;
    uint64_t offset = 0;
    ChunkKind kind = ChunkKind::Known;
};

struct TagTotal {
    Tag tag{};
    uint64_t count = 0, storedSize = 0, rawSize = 0;
};

struct ChunkTable {
    std::vector<ChunkRow> rows;   // file order, the table of contents last
    std::vector<TagTotal> totals; // by first appearance, so the order is deterministic
    uint64_t storedSize = 0, rawSize = 0;
    uint64_t overheadBytes = 0; // file header, chunk headers, padding and footer
};

ChunkTable buildChunkTable(const Container& c) {
    ChunkTable t;
    for (const ChunkInfo& info : c.chunks())
        t.rows.push_back({info.header, info.headerOffset,
                          isKnownTag(info.header.tag) ? ChunkKind::Known : ChunkKind::Unknown});
    // Container::chunks() leaves the TOC out; the footer says where it is. Opening already
    // validated both, so a decode failure here is unreachable and just omits the row.
    std::span<const std::byte> b = c.bytes();
    if (b.size() >= kFooterSize) {
        const uint64_t footerOff = b.size() - kFooterSize;
        auto footer = decodeFooter(b.subspan(footerOff, kFooterSize), footerOff);
        if (footer && footer->tocOffset <= footerOff &&
            footerOff - footer->tocOffset >= kChunkHeaderSize) {
            auto h = decodeChunkHeader(b.subspan(footer->tocOffset, kChunkHeaderSize),
                                       footer->tocOffset);
            if (h) t.rows.push_back({*h, footer->tocOffset, ChunkKind::Toc});
        }
    }
    for (const ChunkRow& r : t.rows) {
        TagTotal* total = nullptr;
        for (TagTotal& tt : t.totals)
            if (tt.tag == r.header.tag) total = &tt;
        if (!total) total = &t.totals.emplace_back(TagTotal{r.header.tag});
        ++total->count;
        total->storedSize += r.header.storedSize;
        total->rawSize += r.header.rawSize;
        t.storedSize += r.header.storedSize;
        t.rawSize += r.header.rawSize;
    }
    t.overheadBytes = b.size() >= t.storedSize ? b.size() - t.storedSize : 0;
    return t;
}

// raw / stored; nullopt for an empty payload, where a ratio means nothing.
std::optional<double> ratio(uint64_t raw, uint64_t stored) {
    if (stored == 0) return std::nullopt;
    return double(raw) / double(stored);
}

std::string ratioText(uint64_t raw, uint64_t stored) {
    auto q = ratio(raw, stored);
    return q ? fixed(*q, 2) + "x" : "-";
}

// [SECTION] derived values

uint64_t indexCount(const Mesh& m) {
    return m.indices.size() / (m.indexType == IndexType::U16 ? 2 : 4);
}

// Counts every LOD level: the index buffer holds them all (chunks.h, Mesh::indices).
uint64_t triangleCount(const Mesh& m) {
    return m.primitive == Primitive::Triangles ? indexCount(m) / 3 : 0;
}

std::string streamLabel(const VertexStream& v) {
    std::string s = std::string(nameOf(v.semantic, kSemanticNames)) + ":" +
                    nameOf(v.componentType, kComponentNames) + "x" +
                    std::to_string(v.componentCount);
    if (v.normalized) s += ",norm";
    if (v.encoding != VertexEncoding::Plain)
        s += std::string(",") + nameOf(v.encoding, kEncodingNames);
    return s;
}

std::vector<const char*> programStages(const Scene& s, const Program& p) {
    std::vector<const char*> stages;
    for (uint32_t sh : p.shaders)
        stages.push_back(sh < s.shaders.size() ? nameOf(s.shaders[sh].stage, kStageNames) : "?");
    return stages;
}

std::string swizzleLabel(const std::array<Swizzle, 4>& sw) {
    std::string s;
    for (Swizzle c : sw)
        s += nameOf(c, kSwizzleNames);
    return s;
}

// Seconds from the first key to the last (0 with fewer than two keys).
float pathDuration(const CameraPath& p) {
    return p.keys.size() < 2 ? 0.0f : p.keys.back().timeSeconds - p.keys.front().timeSeconds;
}

uint32_t storedMipCount(const Scene& s, uint32_t texture) {
    uint32_t n = 0;
    for (const TextureMip& m : s.textureMips)
        n += m.texture == texture;
    return n;
}

struct NodeCounts {
    uint64_t roots = 0, withMesh = 0, withLight = 0, withCamera = 0;
};

NodeCounts countNodes(const NodeGraph& g) {
    NodeCounts n;
    for (const Node& node : g.nodes) {
        n.roots += node.parent == kNone;
        n.withMesh += node.mesh != kNone;
        n.withLight += node.light != kNone;
        n.withCamera += node.camera != kNone;
    }
    return n;
}

uint64_t mipBytes(const Scene& s) {
    uint64_t n = 0;
    for (const TextureMip& m : s.textureMips)
        n += m.data.size();
    return n;
}

std::string shadowLabel(bool casts, bool receives) {
    if (casts && receives) return "cast+receive";
    return casts ? "cast" : receives ? "receive" : "none";
}

// Chunks written without a payload checksum (pnb-convert --no-checksums): their bytes decode,
// but nothing says they are the bytes that were written.
size_t chunksWithoutChecksum(const Container& c) {
    size_t n = 0;
    for (const ChunkInfo& info : c.chunks()) n += info.header.hasChecksum() ? 0 : 1;
    return n;
}

// [SECTION] text report

const char* yesNo(bool v) {
    return v ? "yes" : "no";
}

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

void textScene(std::string& o, const Scene& s) {
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

    o += "\nrender settings (" + u64(s.settings.entries.size()) + "):\n";
    for (const Setting& e : s.settings.entries)
        o += "  " + textEscape(s.str(e.key)) + "=" + textEscape(s.str(e.value)) + "\n";

    o += "\nshaders (" + u64(s.shaders.size()) + "):\n";
    if (!s.shaders.empty()) {
        TextTable t({"#", "name", "stage", "source bytes"}, "rllr");
        for (size_t i = 0; i < s.shaders.size(); ++i)
            t.add({u64(i), nameText(s, s.shaders[i].name), nameOf(s.shaders[i].stage, kStageNames),
                   u64(s.shaders[i].source.size())});
        t.print(o);
    }

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

    if (const auto& e = s.environment) {
        auto texture = [&](uint32_t t) { return t == kNone ? std::string("none") : "texture " + u64(t); };
        o += "\nenvironment: " + nameText(s, e->name) + " (" + nameOf(e->source, kEnvironmentSourceNames) +
             "), radiance " + texture(e->radiance) + ", specular " + texture(e->specular) + ", BRDF table " +
             texture(e->brdfLut) + "\n";
        o += "  irradiance SH band 0 (lux): " + vecText(e->irradianceSh[0]) + "\n";
        if (e->source == EnvironmentSource::AnalyticSky)
            o += "  sky: sun " + vecText(e->sunDirection) + ", turbidity " + num(e->turbidity) + ", ground " +
                 vecText(e->groundAlbedo) + ", sun " + num(e->sunIlluminance) + " lux\n";
    }
}

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

void jsonScene(Json& j, const Scene& s) {
    j.key("scene").beginObject();
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

    // An array, not an object: keys may repeat in a file and order is meaningful to readers.
    j.key("render_settings").beginArray();
    for (const Setting& e : s.settings.entries) {
        j.beginObject(true);
        j.key("key").name(s, e.key);
        j.key("value").name(s, e.value);
        j.endObject();
    }
    j.endArray();

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
    j.endObject();
}

// [SECTION] runInspect

void writeAll(std::FILE* f, const std::string& s) {
    std::fwrite(s.data(), 1, s.size(), f);
}

int fail(std::FILE* err, const Error& e) {
    std::fprintf(err, "Error: %s\n", textEscape(e.describe()).c_str());
    bool unsupported = e.code == FormatError::UnsupportedVersion ||
                       e.code == FormatError::UnsupportedChunkVersion;
    return unsupported ? kInspectUnsupported : kInspectInputError;
}

// Opens, checks every byte, decodes everything: the first error wins. A chunk written without a
// checksum (pnb-convert --no-checksums) has nothing its payload can be checked against: strict
// mode fails on it, the default says so beside the verdict.
Result<Container> verifyFile(const InspectOptions& opt, const ReadOptions& ro) {
    auto c = Container::open(opt.path, ro);
    if (!c) return c.error();
    if (Status s = c->verifyAll(); !isOk(s)) return s;
    auto scene = readScene(*c);
    if (!scene) return scene.error();
    if (opt.strict) {
        for (const ChunkInfo& info : c->chunks())
            if (!info.header.hasChecksum())
                return makeError(FormatError::Missing, info.headerOffset,
                                 "strict: chunk %llu ('%s') carries no checksum, its payload "
                                 "cannot be verified",
                                 (unsigned long long)info.header.sequence,
                                 info.header.tag.str().c_str());
    }
    return c;
}

int runVerify(const InspectOptions& opt, const ReadOptions& ro, std::FILE* out, std::FILE* err) {
    auto c = verifyFile(opt, ro);
    if (!opt.json) {
        if (!c) return fail(err, c.error());
        const size_t unchecked = chunksWithoutChecksum(*c);
        std::fprintf(out, "verify: ok (%zu chunks, %zu bytes)\n", c->chunks().size(),
                     c->bytes().size());
        if (unchecked > 0)
            std::fprintf(out,
                         "verify: %zu of %zu chunks carry no checksum: their structure was checked, "
                         "their payload bytes could not be (--strict fails on this)\n",
                         unchecked, c->chunks().size());
        return kInspectOk;
    }
    Json j;
    j.beginObject();
    j.key("file").str(opt.path);
    j.key("verify").beginObject();
    j.key("ok").boolean(c.ok());
    if (c) {
        j.key("chunks").uint(c->chunks().size());
        j.key("chunks_without_checksum").uint(chunksWithoutChecksum(*c));
        j.key("size_bytes").uint(c->bytes().size());
    } else {
        jsonError(j, c.error());
    }
    j.endObject();
    j.endObject();
    writeAll(out, j.out);
    return c ? kInspectOk : fail(err, c.error());
}

} // namespace

InspectOptions inspectDefaults() {
    return InspectOptions{};
}

int runInspect(const InspectOptions& opt, std::FILE* out, std::FILE* err) {
    if (opt.path.empty()) {
        std::fprintf(err, "Error: no input file\n");
        return kInspectUsageError;
    }
    ReadOptions ro;
    ro.verifyChecksums = opt.verifyChecksums;
    ro.useToc = opt.useToc;
    if (opt.verify) return runVerify(opt, ro, out, err);

    auto container = Container::open(opt.path, ro);
    if (!container) {
        if (opt.json) {
            Json j;
            j.beginObject();
            j.key("file").str(opt.path);
            jsonError(j, container.error());
            j.endObject();
            writeAll(out, j.out);
        }
        return fail(err, container.error());
    }
    const ChunkTable table = buildChunkTable(*container);
    // Decoded after the table so that a damaged payload still leaves the frame visible.
    auto scene = readScene(*container);

    std::string text;
    if (opt.json) {
        Json j;
        j.beginObject();
        j.key("file").str(opt.path);
        jsonHeader(j, opt, *container, table);
        if (scene) {
            jsonScene(j, *scene);
        } else {
            j.key("scene").null();
            jsonError(j, scene.error());
        }
        j.endObject();
        text = std::move(j.out);
    } else {
        textHeader(text, opt, *container, table);
        if (scene) textScene(text, *scene);
    }
    writeAll(out, text);
    return scene ? kInspectOk : fail(err, scene.error());
}

} // namespace pnb
