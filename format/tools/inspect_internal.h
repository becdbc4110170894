// inspect_internal.h — what pnb-inspect's files share (inspect.cpp runs the modes; the text
// and JSON views are inspect_text.cpp and inspect_json.cpp; inspect_print.cpp holds the escaping,
// numbers, chunk table and derived values both views print). Internal to pnb_inspect_lib.
//
// Both views print from the same sources: a chunk table built from the container index (valid
// even when payloads are damaged) and the Scene from readScene(). Derived values (triangle
// counts, stage lists, durations) come from one helper each so text and JSON agree.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "inspect.h"
#include "pnb/container.h"
#include "pnb/error.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/tags.h"

namespace pnb::inspect_detail {

// [SECTION] enum names
// These strings are part of the tool's output contract (scripts match on them): snake_case,
// never renamed. The static_asserts catch an enum growing without a name here.

inline constexpr const char* kStageNames[] = {"vertex",  "fragment",     "geometry",
                                              "compute", "tess_control", "tess_evaluation"};
inline constexpr const char* kDimensionNames[] = {"2d", "cube"};
inline constexpr const char* kFormatNames[] = {"r8",    "rg8",     "rgb8", "rgba8", "r16f",
                                               "rg16f", "rgba16f", "r32f", "rg32f", "rgba32f",
                                               "bc1",   "bc3",     "bc4",  "bc5",   "bc7"};
inline constexpr const char* kColorSpaceNames[] = {"linear", "srgb"};
inline constexpr const char* kSwizzleNames[] = {"r", "g", "b", "a", "0", "1"};
inline constexpr const char* kMinFilterNames[] = {
    "nearest",          "linear", "nearest_mip_nearest", "linear_mip_nearest", "nearest_mip_linear",
    "linear_mip_linear"};
inline constexpr const char* kMagFilterNames[] = {"nearest", "linear"};
inline constexpr const char* kWrapNames[] = {"repeat", "mirrored_repeat", "clamp_to_edge"};
inline constexpr const char* kAlphaModeNames[] = {"opaque", "mask", "blend"};
inline constexpr const char* kShadingPathNames[] = {"deferred", "forward"};
inline constexpr const char* kSlotNames[] = {"base_color", "metallic_roughness", "normal",
                                             "occlusion", "emissive"};
inline constexpr const char* kPrimitiveNames[] = {"triangles", "lines", "points"};
inline constexpr const char* kIndexTypeNames[] = {"u16", "u32"};
inline constexpr const char* kSemanticNames[] = {"position",  "normal", "tangent", "texcoord0",
                                                 "texcoord1", "color0", "joints0", "weights0"};
inline constexpr const char* kComponentNames[] = {"f32", "f16", "i8",  "u8",
                                                  "i16", "u16", "i32", "u32"};
inline constexpr const char* kEncodingNames[] = {"plain", "octahedral"};
inline constexpr const char* kLightTypeNames[] = {"directional", "point", "spot"};
inline constexpr const char* kProjectionNames[] = {"perspective", "orthographic"};
inline constexpr const char* kInterpolationNames[] = {"linear", "catmull_rom"};
inline constexpr const char* kEnvironmentSourceNames[] = {"image", "analytic_sky"};
inline constexpr const char* kCompressionNames[] = {"none", "zstd"};

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

// [SECTION] escaping and numbers (inspect_print.cpp)

// Strings from the file printed to a terminal: control bytes (C0, DEL, and C1 as U+0080..U+009F,
// which some terminals obey) and invalid UTF-8 become visible \xNN escapes, so a hostile name
// cannot move the cursor or hide text.
std::string textEscape(std::string_view s);

// A JSON string literal (RFC 8259). Invalid UTF-8 becomes U+FFFD so the document stays valid
// UTF-8 for strict parsers; DEL and C1 controls are escaped for the same terminal reason as text.
std::string jsonQuote(std::string_view s);

// Shortest text that reads back as the same float: stable across runs and platforms, and short
// for round values ("0.8", not "0.800000012"). Non-finite values are spelled as printf does.
std::string num(float v);

std::string fixed(double v, int decimals); // printf's %.*f
std::string u64(uint64_t v);

// "(x, y, z)" of num() values.
std::string vecText(std::initializer_list<float> values);
std::string vecText(const Vec3& v);
std::string vecText(const Vec4& v);

bool isEmpty(const Aabb& b);           // min > max on some axis
std::string boundsText(const Aabb& b); // "empty" or "(min)..(max)"

// A name for text output: "-" for none or empty, escaped otherwise.
std::string nameText(const Scene& s, StringRef ref);

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

// [SECTION] chunk table (inspect_print.cpp)

enum class ChunkKind { Known, Unknown, Toc };

const char* kindName(ChunkKind k);

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

// The rows of every chunk in file order (the table of contents last, found through the footer)
// and the totals by tag, from the container index alone.
ChunkTable buildChunkTable(const Container& c);

// raw / stored; nullopt for an empty payload, where a ratio means nothing.
std::optional<double> ratio(uint64_t raw, uint64_t stored);
std::string ratioText(uint64_t raw, uint64_t stored); // "2.50x", or "-" for no ratio

// [SECTION] derived values (inspect_print.cpp)

uint64_t indexCount(const Mesh& m);
// Counts every LOD level: the index buffer holds them all (chunks.h, Mesh::indices).
uint64_t triangleCount(const Mesh& m);
std::string streamLabel(const VertexStream& v); // "position:f32x3", "normal:i8x4,norm,..."
std::vector<const char*> programStages(const Scene& s, const Program& p);
std::string swizzleLabel(const std::array<Swizzle, 4>& sw); // "rgba"
// Seconds from the first key to the last (0 with fewer than two keys).
float pathDuration(const CameraPath& p);
uint32_t storedMipCount(const Scene& s, uint32_t texture);
// An animation clip's totals: its keys over all channels, and its duration (animation_pose.h).
struct ClipCounts {
    uint64_t keys = 0;
    double durationSeconds = 0;
};
ClipCounts countClip(const Animation& clip);
// The delta streams of a morph target as "position,normal" (the semantics it moves).
std::string morphDeltaLabel(const MorphTarget& t);

struct NodeCounts {
    uint64_t roots = 0, withMesh = 0, withLight = 0, withCamera = 0;
};

NodeCounts countNodes(const NodeGraph& g);
uint64_t mipBytes(const Scene& s);                  // texel bytes of every stored mip
std::string shadowLabel(bool casts, bool receives); // "cast+receive", "cast", "receive", "none"

// Chunks written without a payload checksum (pnb-convert --no-checksums): their bytes decode,
// but nothing says they are the bytes that were written.
size_t chunksWithoutChecksum(const Container& c);

// [SECTION] views

// inspect_text.cpp: the file header and chunk table, then the scene's typed summaries.
void textHeader(std::string& o, const InspectOptions& opt, const Container& c, const ChunkTable& t);
void textScene(std::string& o, const Scene& s);

// inspect_json.cpp: the same as members of the open top-level object, and an error object.
void jsonError(Json& j, const Error& e);
void jsonHeader(Json& j, const InspectOptions& opt, const Container& c, const ChunkTable& t);
void jsonScene(Json& j, const Scene& s);

} // namespace pnb::inspect_detail
