// inspect_print.cpp — pnb-inspect's shared printing helpers: escaping of strings from the file,
// number formatting, the chunk table and the derived values. Both views (inspect_text.cpp,
// inspect_json.cpp) use them, so they live apart from either (inspect_internal.h).
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
#include "pnb/animation_pose.h"

namespace pnb::inspect_detail {

// [SECTION] escaping and numbers

namespace {

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

} // namespace

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

// [SECTION] chunk table

namespace {

bool isKnownTag(Tag t) { return streamOrderRank(t) >= 0; }

} // namespace

const char* kindName(ChunkKind k) {
    return k == ChunkKind::Known ? "known" : k == ChunkKind::Unknown ? "unknown" : "toc";
}

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

ClipCounts countClip(const Animation& clip) {
    ClipCounts c;
    for (const AnimationChannel& ch : clip.channels) c.keys += ch.times.size();
    c.durationSeconds = clipDuration(clip);
    return c;
}

std::string morphDeltaLabel(const MorphTarget& t) {
    static const char* const kNames[] = {"position", "normal", "tangent"};
    std::string out;
    for (const VertexStream& d : t.deltas)
        out += (out.empty() ? "" : ",") +
               std::string(unsigned(d.semantic) < 3 ? kNames[unsigned(d.semantic)] : "?");
    return out.empty() ? "none" : out;
}

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

} // namespace pnb::inspect_detail
