// pnb-make-stream-scene: writes a large, texture-heavy .pnb container for streaming tests and
// benchmarks, chunk by chunk with pnb::Writer, in bounded memory: two level-0 TMIP payloads
// (2 x 16 MiB at 2048 texels; peak RSS about 45 MiB whatever --size, 140 MiB at 4096 texels).
//
//   pnb-make-stream-scene OUT.pnb (--size SIZE | --textures N) [--texture-size N]
//                         [--spacing M] [--speed M/S] [--no-shadows] [--no-checksums]
//                         [--threads 1|2] [-q] [--lod-rocks [--rock-triangles N]]
//
//   --size SIZE        make the file at least SIZE bytes (suffix K, M, G = KiB, MiB, GiB; e.g.
//                      1G, 5G, 64M): as many textures as that takes (the last one may overshoot
//                      by less than one texture's mip chain)
//   --textures N       exactly N textured objects (1..100000) instead
//   --texture-size N   texels a side of every texture, a power of two 8..4096 (default 2048)
//   --spacing M        metres between consecutive objects on one side (default 6)
//   --speed M/S        camera path speed (default 5)
//   --no-shadows       no shadow-casting sun (and so no shadow program)
//   --no-checksums     no payload checksums (default: XXH3 on every payload)
//   --threads 1|2      2 (default): texels are generated on a second thread while the previous
//                      chunk is written; 1: everything on one thread. Output is identical.
//   -q                 no summary line
//   --lod-rocks        a rock beside every panel, each its own mesh with levels of detail (see
//                      below); the texture count stays what --size gives, the file grows
//   --rock-triangles N about N triangles a rock at full detail, 100..1000000 (default 20000)
//
// The scene: N boxes (4 m x 4 m x 0.25 m panels) alternating on both sides of a straight street
// along -Z, each with its own material and its own RGBA8 sRGB texture with a full mip chain; a
// grey ground plane; one directional sun (shadows on unless --no-shadows); one camera; one camera
// path (PATH "street") flying down the street at eye height, swaying its yaw a little. At any
// time only the nearby panels need fine mips, so a streaming player can keep only those resident.
//
// With --lod-rocks, in front of every panel a rock about 1 to 1.5 m across stands on the ground:
// its own mesh (a sphere cut by random facets and roughened, from a per-rock seed), with normals
// and uv0, drawn with its panel's material (no texels of its own), casting shadows like the
// panels. Each goes through the converter's mesh pipeline (processMesh, 4 levels at ratio 0.5,
// pnb-convert's defaults otherwise) and is written as pnb-convert --lods 4 writes it: its coarse
// proxy (buildCoarseProxy) as the MESH chunk, its full detail as an MDET chunk after every
// texture's smallest TMIP level and before any larger one (FORMAT.md §4.1, where writeScene puts
// them). The scene keeps only the proxies (about 37 KB a rock at 20000 triangles); the details
// (560 KB a rock) wait in an unlinked temporary file beside the output until their place comes,
// so memory does not grow with the rock count beyond the proxies. With --threads 2 two rocks are
// processed at once (each on its own: the output is the same).
//
// Chunk order is FORMAT.md §4.1; the TMIP chunks come smallest level first across all textures
// (every texture's coarsest level, ..., every texture's level 0 last). The shader programs are
// the ones pnb-convert would pack for such materials (planShaders + resolveShaderSource of the
// converter library: gbuffer with HAS_BASE_COLOR_MAP HAS_UV0, gbuffer for the ground,
// deferred_lighting, shadow, tonemap), so no template file is needed.
//
// Texels: a per-texture hue, a 64-texel checker, an 8-texel fine checker, a border, the texture
// number in large digits and its last digit in small (8-texel stroke) digits in every checker
// square. Everything is built on a grid of 8x8-texel cells, so a level's texels are the exact box
// filter (in linear light, then sRGB-encoded) of level 0: coarser levels are averages of the
// cell grid, never aliased. Fine features vanish level by level, so one can tell which mip is
// shown. Each level is computed at its own resolution; no full chain is ever held.
//
// Deterministic: the same arguments give identical bytes. The file is written under a temporary
// name and renamed into place on success (pnb::Writer), so a failed run leaves no partial file.
// Exit codes: 0 ok, 1 usage error, 2 write error (e.g. disk full), 3 internal error.

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <future>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "pnb/chunks.h"
#include "pnb/mesh_levels.h"
#include "pnb/scene.h"
#include "pnb/scene_builder.h"
#include "pnb/writer.h"
#include "pnb_converter/mesh_processing.h"
#include "pnb_converter/shader_permutations.h"

namespace {

using namespace pnb;

constexpr int kExitUsage = 1;
constexpr int kExitWrite = 2;
constexpr int kExitInternal = 3;

// [SECTION] command line

struct Options {
    std::string output;
    uint64_t sizeBytes = 0;    // 0 = use textures
    uint32_t textures = 0;     // 0 = derive from sizeBytes
    uint32_t textureSize = 2048;
    float spacing = 6.0f;
    float speed = 5.0f;
    bool shadows = true;
    bool checksums = true;
    unsigned threads = 2;
    bool quiet = false;
    bool lodRocks = false;
    uint32_t rockTriangles = 20000;
    bool rockTrianglesGiven = false;
};

void printUsage(std::FILE* out) {
    std::fprintf(out,
                 "usage: pnb-make-stream-scene OUT.pnb (--size SIZE | --textures N)\n"
                 "                             [--texture-size N] [--spacing M] [--speed M/S]\n"
                 "                             [--no-shadows] [--no-checksums] [--threads 1|2] [-q]\n"
                 "                             [--lod-rocks [--rock-triangles N]]\n"
                 "\n"
                 "  --size SIZE       file of at least SIZE bytes (K, M, G suffix = KiB, MiB, GiB)\n"
                 "  --textures N      exactly N textured panels (1..100000)\n"
                 "  --texture-size N  texels a side, power of two 8..4096 (default 2048)\n"
                 "  --spacing M       metres between panels on one side, 1..1000 (default 6)\n"
                 "  --speed M/S       camera path speed, 0.1..1000 (default 5)\n"
                 "  --no-shadows      the sun casts no shadows\n"
                 "  --no-checksums    write no payload checksums\n"
                 "  --threads 1|2     generate texels on a second thread (default 2)\n"
                 "  -q                print nothing on success\n"
                 "  --lod-rocks       a rock beside every panel: its own mesh with 4 levels of\n"
                 "                    detail: a coarse proxy (MESH) + its full detail (MDET)\n"
                 "  --rock-triangles N  about N triangles a rock, 100..1000000 (default 20000)\n");
}

int usageError(const std::string& message) {
    std::fprintf(stderr, "pnb-make-stream-scene: %s\n\n", message.c_str());
    printUsage(stderr);
    return kExitUsage;
}

bool parseU64(const char* text, uint64_t& out) {
    if (!text || *text < '0' || *text > '9') return false;
    errno = 0;
    char* end = nullptr;
    unsigned long long v = std::strtoull(text, &end, 10);
    if (errno != 0 || *end != '\0') return false;
    out = v;
    return true;
}

// "123", "64K", "64M", "5G" (binary units); false on junk, zero or overflow.
bool parseSize(const char* text, uint64_t& out) {
    if (!text || !*text) return false;
    std::string s = text;
    uint64_t mult = 1;
    char last = s.back();
    if (last == 'K' || last == 'k') mult = 1ull << 10;
    if (last == 'M' || last == 'm') mult = 1ull << 20;
    if (last == 'G' || last == 'g') mult = 1ull << 30;
    if (mult != 1) s.pop_back();
    uint64_t v = 0;
    if (!parseU64(s.c_str(), v) || v == 0 || v > (uint64_t(1) << 50) / mult) return false;
    out = v * mult;
    return true;
}

bool parseFloat(const char* text, float lo, float hi, float& out) {
    if (!text || !*text) return false;
    errno = 0;
    char* end = nullptr;
    double v = std::strtod(text, &end);
    if (errno != 0 || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) return false;
    out = float(v);
    return true;
}

// Returns an exit code if the program should stop (usage error or --help).
std::optional<int> parseArgs(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        const char* value = i + 1 < argc ? argv[i + 1] : nullptr;
        auto needs = [&](const char* what) -> std::optional<int> {
            if (!value) return usageError(a + " needs " + what);
            ++i;
            return std::nullopt;
        };
        if (a == "-h" || a == "--help") {
            printUsage(stdout);
            return 0;
        } else if (a == "--size") {
            if (auto e = needs("a size")) return e;
            if (!parseSize(value, o.sizeBytes))
                return usageError(std::string("bad --size '") + value + "' (e.g. 64M, 1G, 5G)");
        } else if (a == "--textures") {
            if (auto e = needs("a count")) return e;
            uint64_t n = 0;
            if (!parseU64(value, n) || n < 1 || n > 100000)
                return usageError(std::string("bad --textures '") + value + "' (1..100000)");
            o.textures = uint32_t(n);
        } else if (a == "--texture-size") {
            if (auto e = needs("a size")) return e;
            uint64_t n = 0;
            if (!parseU64(value, n) || n < 8 || n > 4096 || (n & (n - 1)) != 0)
                return usageError(std::string("bad --texture-size '") + value +
                                  "' (a power of two 8..4096)");
            o.textureSize = uint32_t(n);
        } else if (a == "--spacing") {
            if (auto e = needs("metres")) return e;
            if (!parseFloat(value, 1, 1000, o.spacing))
                return usageError(std::string("bad --spacing '") + value + "' (1..1000)");
        } else if (a == "--speed") {
            if (auto e = needs("metres per second")) return e;
            if (!parseFloat(value, 0.1f, 1000, o.speed))
                return usageError(std::string("bad --speed '") + value + "' (0.1..1000)");
        } else if (a == "--threads") {
            if (auto e = needs("1 or 2")) return e;
            uint64_t n = 0;
            if (!parseU64(value, n) || n < 1 || n > 2)
                return usageError(std::string("bad --threads '") + value + "' (1 or 2)");
            o.threads = unsigned(n);
        } else if (a == "--lod-rocks") {
            o.lodRocks = true;
        } else if (a == "--rock-triangles") {
            if (auto e = needs("a count")) return e;
            uint64_t n = 0;
            if (!parseU64(value, n) || n < 100 || n > 1000000)
                return usageError(std::string("bad --rock-triangles '") + value +
                                  "' (100..1000000)");
            o.rockTriangles = uint32_t(n);
            o.rockTrianglesGiven = true;
        } else if (a == "--no-shadows") {
            o.shadows = false;
        } else if (a == "--no-checksums") {
            o.checksums = false;
        } else if (a == "-q") {
            o.quiet = true;
        } else if (!a.empty() && a[0] == '-') {
            return usageError("unknown option '" + a + "'");
        } else if (o.output.empty()) {
            o.output = a;
        } else {
            return usageError("more than one output file ('" + o.output + "', '" + a + "')");
        }
    }
    if (o.output.empty()) return usageError("no output file");
    if ((o.sizeBytes == 0) == (o.textures == 0))
        return usageError("give exactly one of --size and --textures");
    if (o.rockTrianglesGiven && !o.lodRocks)
        return usageError("--rock-triangles needs --lod-rocks");
    return std::nullopt;
}

// [SECTION] texels

uint32_t mipCountFor(uint32_t size) {
    uint32_t n = 1;
    while (size > 1) {
        size >>= 1;
        ++n;
    }
    return n;
}

// Bytes one TMIP chunk adds to the file: chunk header + payload (16 bytes of fields, the blob's
// u64 size, padding to 16, texels), aligned, plus its TOC entry.
constexpr uint64_t kTmipPrefix = 32;
constexpr uint64_t kTocEntryBytes = 40;
uint64_t tmipFileBytes(uint32_t w, uint32_t h) {
    return alignUp(kChunkHeaderSize + kTmipPrefix + uint64_t(w) * h * 4) + kTocEntryBytes;
}

// 3x5 digit glyphs, one row per 3 bits (bit 2 = left column), top row first.
constexpr std::array<std::array<uint8_t, 5>, 10> kDigits = {{
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 2, 2, 2}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
}};

bool glyphPixel(uint32_t digit, int gx, int gy) {
    if (gx < 0 || gx > 2 || gy < 0 || gy > 4) return false;
    return (kDigits[digit % 10][size_t(gy)] >> (2 - gx)) & 1u;
}

struct Rgb {
    float r = 0, g = 0, b = 0;
};

// Linear RGB of hue h (0..1) at saturation s and value v.
Rgb hsv(float h, float s, float v) {
    float h6 = (h - std::floor(h)) * 6.0f;
    int sector = int(h6) % 6;
    float f = h6 - float(int(h6));
    float p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    switch (sector) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
    }
}

// Linear [0,1] -> sRGB byte, through a table fine enough that every byte is reachable.
class SrgbEncoder {
public:
    SrgbEncoder() {
        for (size_t i = 0; i < kSteps; ++i) {
            double l = double(i) / double(kSteps - 1);
            double s = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
            mTable[i] = uint8_t(std::lround(std::clamp(s, 0.0, 1.0) * 255.0));
        }
    }
    uint8_t operator()(float linear) const {
        float c = std::clamp(linear, 0.0f, 1.0f);
        return mTable[size_t(c * float(kSteps - 1) + 0.5f)];
    }

private:
    static constexpr size_t kSteps = 16384;
    std::array<uint8_t, kSteps> mTable{};
};

// The texture of panel `index`: a grid of cells x cells linear colours, each cell 8x8 level-0
// texels (for textures smaller than 64 texels, fewer texels a cell; the grid is then 8x8).
struct CellGrid {
    uint32_t cells = 0;       // a side
    uint32_t cellTexels = 0;  // level-0 texels a side of one cell
    std::vector<Rgb> colour;  // row-major, row 0 = top of the image
};

CellGrid makeCellGrid(uint32_t index, uint32_t textureSize) {
    CellGrid g;
    g.cellTexels = std::min<uint32_t>(8, textureSize / 8);
    g.cells = textureSize / g.cellTexels;
    const int n = int(g.cells);
    g.colour.resize(size_t(n) * size_t(n));
    // Hue by the golden ratio: neighbouring panels differ clearly.
    const float hue = std::fmod(0.13f + float(index) * 0.6180339887f, 1.0f);
    const Rgb base = hsv(hue, 0.65f, 0.75f);
    const Rgb dark = hsv(hue + 0.5f, 0.5f, 0.12f);
    const Rgb light{0.9f, 0.9f, 0.88f};
    const int block = std::max(1, n / 32);  // 32 checker squares a side (64 texels at 2048)
    // The big number: the panel index in decimal, 3x5 glyphs with one blank column between.
    std::string number = std::to_string(index);
    const int digits = int(number.size());
    const int glyphW = digits * 4 - 1; // in glyph pixels
    const int bigPixel = std::max(1, std::min(n * 3 / 4 / glyphW, n / 2 / 5));
    const int bigX0 = (n - glyphW * bigPixel) / 2, bigY0 = (n - 5 * bigPixel) / 2;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            int bx = x / block, by = y / block;
            float shade = ((bx + by) & 1) ? 1.0f : 0.55f;
            shade *= ((x + y) & 1) ? 1.0f : 0.85f; // the fine checker (one cell)
            Rgb c{base.r * shade, base.g * shade, base.b * shade};
            // Small digit (last digit of the index) in each checker square, 1-cell strokes.
            if (block >= 8 && glyphPixel(index % 10, x % block - 2, y % block - 1)) c = dark;
            // Border, two cells wide.
            if (x < 2 || y < 2 || x >= n - 2 || y >= n - 2) c = dark;
            int gx = x - bigX0, gy = y - bigY0;
            if (gx >= 0 && gy >= 0 && gx < glyphW * bigPixel && gy < 5 * bigPixel) {
                int px = gx / bigPixel, py = gy / bigPixel;
                int d = px / 4;
                if (px % 4 != 3 && glyphPixel(uint32_t(number[size_t(d)] - '0'), px % 4, py))
                    c = light;
            }
            g.colour[size_t(y) * size_t(n) + size_t(x)] = c;
        }
    }
    return g;
}

// Level `level` of a texture of `textureSize` texels: the exact box filter of level 0.
// Levels whose texels are no bigger than a cell repeat cells; coarser ones average cells.
void makeLevel(const CellGrid& g, uint32_t textureSize, uint32_t level, const SrgbEncoder& srgb,
               std::byte* out) {
    const uint32_t size = std::max(1u, textureSize >> level);
    const uint32_t texelSpan = 1u << level; // level-0 texels a side of one texel here
    if (texelSpan <= g.cellTexels) {
        const uint32_t repeat = g.cellTexels / texelSpan; // texels a side of one cell here
        std::vector<uint32_t> row(size);
        for (uint32_t cy = 0; cy < g.cells; ++cy) {
            for (uint32_t cx = 0; cx < g.cells; ++cx) {
                const Rgb& c = g.colour[size_t(cy) * g.cells + cx];
                uint32_t px = uint32_t(srgb(c.r)) | uint32_t(srgb(c.g)) << 8 |
                              uint32_t(srgb(c.b)) << 16 | 0xFF000000u;
                std::fill_n(row.begin() + cx * repeat, repeat, px);
            }
            for (uint32_t r = 0; r < repeat; ++r)
                std::memcpy(out + (size_t(cy) * repeat + r) * size * 4, row.data(), size * 4);
        }
        return;
    }
    const uint32_t k = texelSpan / g.cellTexels; // cells a side averaged into one texel
    const float inv = 1.0f / float(k * k);
    for (uint32_t y = 0; y < size; ++y) {
        for (uint32_t x = 0; x < size; ++x) {
            Rgb sum;
            for (uint32_t j = 0; j < k; ++j)
                for (uint32_t i = 0; i < k; ++i) {
                    const Rgb& c = g.colour[size_t(y * k + j) * g.cells + x * k + i];
                    sum.r += c.r;
                    sum.g += c.g;
                    sum.b += c.b;
                }
            std::byte* p = out + (size_t(y) * size + x) * 4;
            p[0] = std::byte(srgb(sum.r * inv));
            p[1] = std::byte(srgb(sum.g * inv));
            p[2] = std::byte(srgb(sum.b * inv));
            p[3] = std::byte(0xFF);
        }
    }
}

// One TMIP payload, built in place: the fields, the blob header, then the texels generated
// straight into the payload (no second copy). The layout is checked against encodeChunk for
// every small level (see checkPayload).
struct MipJob {
    uint32_t texture = 0, level = 0, size = 0;
    std::vector<std::byte> payload;
};

void putU32(std::byte* p, uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = std::byte((v >> (8 * i)) & 0xFF);
}
void putU64(std::byte* p, uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = std::byte((v >> (8 * i)) & 0xFF);
}

void buildMip(MipJob& job, uint32_t textureSize, const SrgbEncoder& srgb) {
    const uint64_t bytes = uint64_t(job.size) * job.size * 4;
    job.payload.resize(kTmipPrefix + bytes); // capacity is reused from job to job
    std::byte* p = job.payload.data();
    putU32(p + 0, job.texture);
    putU32(p + 4, job.level);
    putU32(p + 8, job.size);
    putU32(p + 12, job.size);
    putU64(p + 16, bytes);
    putU64(p + 24, 0); // padding to the 16-byte boundary of the payload
    CellGrid g = makeCellGrid(job.texture, textureSize);
    makeLevel(g, textureSize, job.level, srgb, p + kTmipPrefix);
}

// The hand-made layout must be encodeChunk's.
bool checkPayload(const MipJob& job) {
    TextureMip m{job.texture, job.level, job.size, job.size,
                 Blob(job.payload.data() + kTmipPrefix, job.payload.size() - kTmipPrefix)};
    std::vector<std::byte> reference = encodeChunk(m);
    return reference == job.payload;
}

// [SECTION] geometry

Vec3 add(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 scale(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// The rotation taking unit vector a to unit vector b (not antiparallel).
Vec4 rotationBetween(Vec3 a, Vec3 b) {
    Vec3 c = cross(a, b);
    Vec4 q{c.x, c.y, c.z, 1 + dot(a, b)};
    float n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return {q.x / n, q.y / n, q.z / n, q.w / n};
}
Vec4 yawRotation(float radians) { return {0, std::sin(radians / 2), 0, std::cos(radians / 2)}; }

struct MeshData {
    std::vector<float> positions, normals, uvs;
    std::vector<uint16_t> indices;
    Aabb bounds;
};

// A box centred on the origin with half extents h; every face shows the whole texture upright
// as seen from outside (v = 0 at the top, glTF convention).
MeshData makeBox(Vec3 h) {
    MeshData m;
    const std::array<Vec3, 6> normals = {{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
    for (Vec3 n : normals) {
        Vec3 up = n.y != 0 ? Vec3{0, 0, -1} : Vec3{0, 1, 0};
        Vec3 right = cross(scale(n, -1), up);
        auto extent = [&](Vec3 axis) {
            return std::abs(axis.x) * h.x + std::abs(axis.y) * h.y + std::abs(axis.z) * h.z;
        };
        Vec3 centre{n.x * h.x, n.y * h.y, n.z * h.z};
        float er = extent(right), eu = extent(up);
        uint16_t first = uint16_t(m.positions.size() / 3);
        for (int corner = 0; corner < 4; ++corner) {
            float u = float(corner & 1), v = float(corner >> 1); // TL, TR, BL, BR
            Vec3 p = add(centre, add(scale(right, (2 * u - 1) * er), scale(up, (1 - 2 * v) * eu)));
            m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
            m.normals.insert(m.normals.end(), {n.x, n.y, n.z});
            m.uvs.insert(m.uvs.end(), {u, v});
            m.bounds.grow(p);
        }
        // Counter-clockwise seen from outside: BL BR TR, BL TR TL.
        for (uint16_t i : {2, 3, 1, 2, 1, 0}) m.indices.push_back(uint16_t(first + i));
    }
    return m;
}

MeshData makeGround(float x0, float x1, float z0, float z1) {
    MeshData m;
    for (int corner = 0; corner < 4; ++corner) {
        Vec3 p{corner & 1 ? x1 : x0, 0, corner >> 1 ? z1 : z0};
        m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
        m.normals.insert(m.normals.end(), {0, 1, 0});
        m.bounds.grow(p);
    }
    // Corners: 0 (x0,z0) 1 (x1,z0) 2 (x0,z1) 3 (x1,z1), z1 < z0; counter-clockwise from +Y.
    m.indices = {0, 1, 2, 1, 3, 2};
    return m;
}

Mesh toMesh(SceneBuilder& b, const std::string& name, const MeshData& d, uint32_t material) {
    Mesh m;
    m.name = b.intern(name);
    m.indexType = IndexType::U16;
    m.vertexCount = uint32_t(d.positions.size() / 3);
    auto stream = [&](VertexSemantic s, uint8_t components, const std::vector<float>& data) {
        VertexStream v;
        v.semantic = s;
        v.componentCount = components;
        v.data = b.keep(data);
        m.streams.push_back(v);
    };
    stream(VertexSemantic::Position, 3, d.positions);
    stream(VertexSemantic::Normal, 3, d.normals);
    if (!d.uvs.empty()) stream(VertexSemantic::TexCoord0, 2, d.uvs);
    m.indices = b.keep(d.indices);
    m.submeshes.push_back(Submesh{material, 0, uint32_t(d.indices.size()), 0, 0.0f, d.bounds});
    m.bounds = d.bounds;
    Vec3 e = scale(add(d.bounds.max, scale(d.bounds.min, -1)), 0.5f);
    m.boundingSphere = {scale(add(d.bounds.max, d.bounds.min), 0.5f), std::sqrt(dot(e, e))};
    return m;
}

// The world box of `local` turned by `yaw` about +Y, then moved by t.
Aabb placed(Aabb local, float yaw, Vec3 t) {
    Aabb out;
    const float c = std::cos(yaw), s = std::sin(yaw);
    for (int corner = 0; corner < 8; ++corner) {
        Vec3 p{corner & 1 ? local.max.x : local.min.x, corner & 2 ? local.max.y : local.min.y,
               corner & 4 ? local.max.z : local.min.z};
        out.grow(add(Vec3{c * p.x + s * p.z, p.y, -s * p.x + c * p.z}, t));
    }
    return out;
}

// [SECTION] rocks (--lod-rocks)

// splitmix64: a tiny deterministic generator, the same numbers on every platform.
class Random {
public:
    explicit Random(uint64_t seed) : mState(seed) {}
    uint64_t next() {
        uint64_t z = (mState += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform(float lo, float hi) {
        return lo + (hi - lo) * float(next() >> 40) / float(1 << 24);
    }
    Vec3 direction() { // uniform on the unit sphere
        float z = uniform(-1, 1), a = uniform(0, 6.2831853f), r = std::sqrt(1 - z * z);
        return {r * std::cos(a), r * std::sin(a), z};
    }

private:
    uint64_t mState;
};

// Grid rows of a rock of about `triangles` triangles: a latitude-longitude sphere of r rows and
// 2r columns has 4r(r - 1) (one triangle a column in each polar row, two elsewhere).
uint32_t rockRows(uint32_t triangles) {
    return std::max(3u, uint32_t(std::lround((1 + std::sqrt(1.0 + double(triangles))) / 2)));
}

// Rock `index`: a sphere cut by a handful of random planes (flat facets, which simplify well,
// beside curved parts, which do not), roughened by low-amplitude waves, flattened and stretched
// a little; about 1 to 1.5 m across, centred on the origin. Everything comes from the index, so
// the output does not depend on which thread made the rock.
// Positions and normals are computed once per grid point, so the seam column and the poles,
// whose vertices are repeated for their uvs, get identical ones (nothing cracks or shades apart
// there). uv0: longitude and latitude, v = 0 at the top, the texture upright seen from outside.
converter::IrMesh makeRock(uint32_t index, uint32_t triangles, uint32_t material) {
    Random rnd(0x5EED0000ull + index);
    const float radius = rnd.uniform(0.5f, 0.62f);
    const Vec3 stretch{rnd.uniform(1.0f, 1.18f), rnd.uniform(0.7f, 0.85f), rnd.uniform(0.9f, 1.1f)};
    struct Cut {
        Vec3 normal;
        float distance;
    };
    std::vector<Cut> cuts(size_t(7 + rnd.next() % 5));
    for (Cut& c : cuts) c = {rnd.direction(), radius * rnd.uniform(0.74f, 0.95f)};
    struct Wave {
        Vec3 axis;
        float frequency, phase, amplitude;
    };
    std::array<Wave, 4> waves;
    for (size_t k = 0; k < waves.size(); ++k)
        waves[k] = {rnd.direction(), rnd.uniform(5, 13), rnd.uniform(0, 6.2831853f),
                    0.012f / float(k + 1)};
    auto surface = [&](Vec3 d) {
        float r = radius;
        for (const Cut& c : cuts) {
            float facing = dot(d, c.normal);
            if (facing > 1e-3f) r = std::min(r, c.distance / facing);
        }
        float rough = 1;
        for (const Wave& w : waves)
            rough += w.amplitude * std::sin(w.frequency * dot(d, w.axis) + w.phase);
        r *= rough;
        return Vec3{d.x * r * stretch.x, d.y * r * stretch.y, d.z * r * stretch.z};
    };

    // Grid points: the north pole, (rows - 1) rings of `columns`, the south pole.
    const uint32_t rows = rockRows(triangles), columns = 2 * rows;
    const uint32_t points = 2 + (rows - 1) * columns;
    auto point = [&](uint32_t row, uint32_t column) -> uint32_t {
        if (row == 0) return 0;
        if (row == rows) return points - 1;
        return 1 + (row - 1) * columns + column % columns;
    };
    std::vector<Vec3> position(points), normal(points, Vec3{0, 0, 0});
    position[0] = surface({0, 1, 0});
    position[points - 1] = surface({0, -1, 0});
    for (uint32_t row = 1; row < rows; ++row) {
        const float theta = 3.14159265f * float(row) / float(rows);
        for (uint32_t column = 0; column < columns; ++column) {
            const float phi = 6.2831853f * float(column) / float(columns);
            position[point(row, column)] = surface({std::sin(theta) * std::cos(phi),
                                                    std::cos(theta),
                                                    std::sin(theta) * std::sin(phi)});
        }
    }
    // Triangles as grid points, counter-clockwise seen from outside; area-weighted normals.
    std::vector<std::array<uint32_t, 2>> corners; // (row, column) of every triangle corner
    using Corner = std::array<uint32_t, 2>;
    auto triangle = [&](Corner a, Corner b, Corner c) {
        corners.insert(corners.end(), {a, b, c});
        Vec3 pa = position[point(a[0], a[1])], pb = position[point(b[0], b[1])],
             pc = position[point(c[0], c[1])];
        Vec3 n = cross(add(pb, scale(pa, -1)), add(pc, scale(pa, -1)));
        for (Corner k : {a, b, c}) normal[point(k[0], k[1])] = add(normal[point(k[0], k[1])], n);
    };
    for (uint32_t row = 0; row < rows; ++row)
        for (uint32_t column = 0; column < columns; ++column) {
            if (row != 0) triangle({row, column}, {row, column + 1}, {row + 1, column});
            if (row != rows - 1)
                triangle({row, column + 1}, {row + 1, column + 1}, {row + 1, column});
        }

    // Vertices: a grid point once per uv it is seen with (the seam column twice, the poles once
    // per column, at the middle of the column).
    converter::IrPrimitive p;
    p.material = int(material);
    std::vector<uint32_t> vertexOf(size_t(rows + 1) * (columns + 1), UINT32_MAX);
    for (auto [row, column] : corners) {
        uint32_t& v = vertexOf[size_t(row) * (columns + 1) + column];
        if (v == UINT32_MAX) {
            v = uint32_t(p.positions.size() / 3);
            Vec3 x = position[point(row, column)], n = normal[point(row, column)];
            n = scale(n, 1 / std::sqrt(dot(n, n)));
            float u = float(column) / float(columns);
            if (row == 0) u -= 0.5f / float(columns); // a top pole corner is at column + 1
            if (row == rows) u += 0.5f / float(columns);
            p.positions.insert(p.positions.end(), {x.x, x.y, x.z});
            p.normals.insert(p.normals.end(), {n.x, n.y, n.z});
            p.uv0.insert(p.uv0.end(), {1 - u, float(row) / float(rows)});
        }
        p.indices.push_back(v);
    }
    converter::IrMesh m;
    m.name = "rock" + std::to_string(index);
    m.primitives.push_back(std::move(p));
    return m;
}

// Rock `index` through the converter's mesh pipeline with pnb-convert's --lods 4 settings.
Result<converter::ProcessedMesh, converter::ConvertError>
processRock(uint32_t index, uint32_t triangles, uint32_t material) {
    converter::StreamNeeds needs;
    needs.uv0 = true; // the panel's material samples its texture
    converter::MeshSettings settings;
    settings.lodCount = 4;
    settings.lodRatio = 0.5f;
    converter::MeshStats stats;
    return converter::processMesh(makeRock(index, triangles, material), needs, settings, stats);
}

// Rocks 0..count-1 through processRock, handed to `use(index, result)` in index order. With two
// threads, rock i + 1 is processed beside rock i (each is independent of the others, so the
// results are the same): two rocks in memory at a time. Stops at use's first exit code.
using ProcessedRock = Result<converter::ProcessedMesh, converter::ConvertError>;
template <class Use>
std::optional<int> forEachRock(uint32_t count, uint32_t triangles, unsigned threads, Use&& use) {
    for (uint32_t i = 0; i < count; i += threads > 1 ? 2 : 1) {
        std::future<ProcessedRock> next;
        if (threads > 1 && i + 1 < count)
            next = std::async(std::launch::async,
                              [=] { return processRock(i + 1, triangles, i + 1); });
        ProcessedRock rock = processRock(i, triangles, i);
        if (auto e = use(i, rock)) return e; // (the future's destructor waits for its rock)
        if (next.valid()) {
            ProcessedRock second = next.get();
            if (auto e = use(i + 1, second)) return e;
        }
    }
    return std::nullopt;
}

// An unlinked temporary file beside the output, holding the rocks' MDET payloads from their
// making (with the proxies, before the scene is written) until their place in the file (after the
// smallest texel levels): on disk rather than in memory, so RSS does not grow with the rock
// count, and no rock is processed twice. It vanishes when closed, even if the program dies.
class SpillFile {
public:
    SpillFile() = default;
    SpillFile(const SpillFile&) = delete;
    SpillFile& operator=(const SpillFile&) = delete;
    ~SpillFile() {
        if (mFile) std::fclose(mFile);
    }
    // False (errno set) if no file can be made in the directory of `output`.
    bool open(const std::string& output) {
        std::filesystem::path dir = std::filesystem::path(output).parent_path();
        std::string name = (dir.empty() ? std::string(".") : dir.string()) +
                           "/.pnb-make-stream-scene-rocks.XXXXXX";
        int fd = ::mkstemp(name.data());
        if (fd < 0) return false;
        ::unlink(name.c_str());
        mFile = ::fdopen(fd, "w+b");
        if (!mFile) ::close(fd);
        return mFile != nullptr;
    }
    uint64_t size() const { return mSize; }
    bool append(std::span<const std::byte> bytes) {
        if (std::fwrite(bytes.data(), 1, bytes.size(), mFile) != bytes.size()) return false;
        mSize += bytes.size();
        return true;
    }
    bool read(uint64_t offset, uint64_t bytes, std::vector<std::byte>& out) {
        out.resize(bytes);
        return ::fseeko(mFile, off_t(offset), SEEK_SET) == 0 &&
               std::fread(out.data(), 1, out.size(), mFile) == out.size();
    }

private:
    std::FILE* mFile = nullptr;
    uint64_t mSize = 0;
};

// [SECTION] the texel pipeline: one producer thread, the writer on the main thread

// Produces the TMIP payloads in file order. With threads = 2 the next payload is built while the
// current one is written; two buffers circulate, so memory stays at two level-0 payloads.
class MipProducer {
public:
    MipProducer(uint32_t textures, uint32_t textureSize, unsigned threads)
        : mTextures(textures), mTextureSize(textureSize), mLevels(mipCountFor(textureSize)),
          mThreaded(threads > 1) {
        mFree.resize(2);
        if (mThreaded) mThread = std::thread([this] { run(); });
    }
    ~MipProducer() {
        {
            std::lock_guard lock(mMutex);
            mStop = true;
        }
        mCv.notify_all();
        if (mThread.joinable()) mThread.join();
    }
    uint64_t total() const { return uint64_t(mTextures) * mLevels; }

    // The next payload in order (coarsest level of texture 0 first); give it back with recycle().
    MipJob next() {
        if (!mThreaded) {
            MipJob job = std::move(mFree.front());
            mFree.pop_front();
            fill(job, mNext++);
            return job;
        }
        std::unique_lock lock(mMutex);
        mCv.wait(lock, [&] { return !mReady.empty(); });
        MipJob job = std::move(mReady.front());
        mReady.pop_front();
        mCv.notify_all();
        return job;
    }
    void recycle(MipJob job) {
        std::lock_guard lock(mMutex);
        mFree.push_back(std::move(job));
        mCv.notify_all();
    }

private:
    void fill(MipJob& job, uint64_t n) {
        job.level = mLevels - 1 - uint32_t(n / mTextures);
        job.texture = uint32_t(n % mTextures);
        job.size = std::max(1u, mTextureSize >> job.level);
        buildMip(job, mTextureSize, mSrgb);
    }
    void run() {
        for (uint64_t n = 0; n < total(); ++n) {
            MipJob job;
            {
                std::unique_lock lock(mMutex);
                mCv.wait(lock, [&] { return mStop || !mFree.empty(); });
                if (mStop) return;
                job = std::move(mFree.front());
                mFree.pop_front();
            }
            fill(job, n);
            {
                std::lock_guard lock(mMutex);
                mReady.push_back(std::move(job));
            }
            mCv.notify_all();
        }
    }

    uint32_t mTextures, mTextureSize, mLevels;
    bool mThreaded;
    SrgbEncoder mSrgb;
    uint64_t mNext = 0;
    std::mutex mMutex;
    std::condition_variable mCv;
    std::deque<MipJob> mFree, mReady;
    bool mStop = false;
    std::thread mThread;
};

// [SECTION] main

int run(const Options& o) {
    const auto start = std::chrono::steady_clock::now();
    const uint32_t levels = mipCountFor(o.textureSize);
    // Texel chunks alone: with ceil(size / perTexture) textures the file is at least --size.
    uint64_t perTexture = 0;
    for (uint32_t l = 0; l < levels; ++l) {
        uint32_t s = std::max(1u, o.textureSize >> l);
        perTexture += tmipFileBytes(s, s);
    }
    uint32_t count = o.textures;
    if (count == 0) {
        uint64_t n = (o.sizeBytes + perTexture - 1) / perTexture;
        if (n > 100000) {
            std::fprintf(stderr,
                         "pnb-make-stream-scene: --size needs %llu textures of %u texels, more "
                         "than 100000; use a larger --texture-size\n",
                         (unsigned long long)n, o.textureSize);
            return kExitUsage;
        }
        count = uint32_t(std::max<uint64_t>(1, n));
    }

    // Layout: panel i on the left (even i) or right (odd i) of the street, rows `spacing` apart,
    // turned 35 degrees towards the oncoming camera (and the sun behind it).
    const float halfStreet = 5.0f;
    const Vec3 panelHalf{0.125f, 2.0f, 2.0f};
    const float panelY = 2.25f;
    const uint32_t rows = (count + 1) / 2;
    const float streetEnd = -float(rows) * o.spacing - o.spacing; // z of the last row and a bit
    auto panelYaw = [&](uint32_t i) { return (i % 2 == 0 ? -1.0f : 1.0f) * 0.6108652f; };
    auto panelCentre = [&](uint32_t i) {
        float side = (i % 2 == 0) ? -1.0f : 1.0f;
        return Vec3{side * (halfStreet + panelHalf.x), panelY, -float(i / 2 + 1) * o.spacing};
    };

    SceneBuilder b;
    Scene& s = b.scene;
    s.info.name = b.intern("stream-street");
    s.info.generator = b.intern("pnb-make-stream-scene");
    s.info.source = b.intern("procedural");
    s.info.metersPerUnit = 1.0f;

    // Materials first (their programs come from the converter's planner).
    std::vector<Material> materials;
    std::vector<converter::MaterialFeatures> features;
    for (uint32_t i = 0; i < count; ++i) {
        Material m;
        m.name = b.intern("panel" + std::to_string(i));
        m.metallicFactor = 0.0f;
        m.roughnessFactor = 0.7f;
        m.castsShadows = o.shadows;
        m.textures[size_t(TextureSlotKind::BaseColor)].texture = i;
        materials.push_back(m);
        converter::MaterialFeatures f;
        f.baseColorMap = true;
        f.uv0 = true;
        features.push_back(f);
    }
    {
        Material ground;
        ground.name = b.intern("ground");
        ground.baseColorFactor = {0.35f, 0.35f, 0.33f, 1.0f};
        ground.metallicFactor = 0.0f;
        ground.roughnessFactor = 0.9f;
        ground.castsShadows = o.shadows;
        materials.push_back(ground);
        features.push_back({});
    }
    converter::SceneShaderNeeds needs;
    needs.shadows = o.shadows;
    converter::ShaderPlan plan = converter::planShaders(materials, features, needs);
    if (auto r = converter::appendShaderPrograms(plan, converter::builtinShaderFiles(), b); !r) {
        std::fprintf(stderr, "pnb-make-stream-scene: %s\n", r.error().message.c_str());
        return kExitInternal;
    }
    for (size_t i = 0; i < materials.size(); ++i) {
        materials[i].program = plan.materialProgram[i];
        s.materials.push_back(materials[i]);
    }

    for (uint32_t i = 0; i < count; ++i) {
        TextureDesc t;
        t.name = b.intern("panel" + std::to_string(i) + ".basecolor");
        t.format = TextureFormat::RGBA8;
        t.colorSpace = ColorSpace::Srgb;
        t.width = t.height = o.textureSize;
        t.mipCount = levels;
        t.wrapU = t.wrapV = Wrap::ClampToEdge;
        s.textures.push_back(t);
    }

    // Meshes: one box per panel (its own material), then the ground.
    const MeshData box = makeBox(panelHalf);
    for (uint32_t i = 0; i < count; ++i)
        s.meshes.push_back(toMesh(b, "panel" + std::to_string(i), box, i));
    const MeshData groundData = makeGround(-30.0f, 30.0f, 30.0f, streetEnd - 30.0f);
    s.meshes.push_back(toMesh(b, "ground", groundData, count));

    // Rocks (--lod-rocks), after the ground: each through the converter's mesh pipeline, its
    // coarse proxy kept in the scene, its detail's MDET payload put in the spill file until its
    // place in the file comes (after every texture's smallest level). Memory holds one or two
    // rocks' details at a time, whatever the count. Rock i uses panel i's material: no texels of
    // its own.
    struct Rock {
        uint32_t mesh = 0;
        bool detailed = false; // has levels: MESH is its proxy, MDET its detail
        uint64_t spillOffset = 0, spillBytes = 0; // its MDET payload in the spill file
        Vec3 position{0, 0, 0};
    };
    SpillFile spill;
    if (o.lodRocks && !spill.open(o.output)) {
        std::fprintf(stderr, "pnb-make-stream-scene: cannot write %s: no temporary file beside "
                             "it: %s\n", o.output.c_str(), std::strerror(errno));
        return kExitWrite;
    }
    std::vector<Rock> rocks;
    std::vector<uint64_t> rockTriangles; // per level, all rocks (index 0: full detail)
    uint64_t proxyTriangles = 0;
    std::deque<converter::ProcessedMesh> undetailed; // the rare rock without levels, kept whole
    auto addRock = [&](uint32_t i, ProcessedRock& pm) -> std::optional<int> {
        if (!pm) {
            std::fprintf(stderr, "pnb-make-stream-scene: internal error: rock %u: %s\n", i,
                         pm.error().message.c_str());
            return kExitInternal;
        }
        Rock r;
        r.mesh = uint32_t(s.meshes.size());
        Mesh full = converter::toContainerMesh(*pm, b.intern("rock" + std::to_string(i)));
        for (const Submesh& sm : full.submeshes) {
            if (rockTriangles.size() <= sm.lod) rockTriangles.resize(sm.lod + 1u);
            rockTriangles[sm.lod] += sm.indexCount / 3;
        }
        r.detailed = hasLevelChains(full);
        if (r.detailed) {
            s.meshes.push_back(buildCoarseProxy(full, b));
            MeshDetail d{r.mesh, full};
            if (Status st = validateMeshDetail(s, d, i); !isOk(st)) {
                std::fprintf(stderr, "pnb-make-stream-scene: internal error: %s\n",
                             st.message.c_str());
                return kExitInternal;
            }
            std::vector<std::byte> payload = encodeChunk(d);
            r.spillOffset = spill.size();
            r.spillBytes = payload.size();
            if (!spill.append(payload)) {
                std::fprintf(stderr, "pnb-make-stream-scene: cannot write %s: temporary file: "
                                     "%s\n", o.output.c_str(), std::strerror(errno));
                return kExitWrite;
            }
        } else {
            undetailed.push_back(std::move(*pm)); // moving keeps the bytes `full` views
            s.meshes.push_back(full);
        }
        for (const Submesh& sm : s.meshes.back().submeshes) proxyTriangles += sm.indexCount / 3;
        // On the ground in front of the panel's street face, towards its end nearer the
        // oncoming camera, sunk a little so it stands rather than touches.
        const float side = (i % 2 == 0) ? -1.0f : 1.0f;
        const float c = std::cos(panelYaw(i)), sn = std::sin(panelYaw(i));
        const Vec3 face{-side * c, 0, side * sn}, along{sn, 0, c};
        r.position = add(panelCentre(i), add(scale(face, 1.4f), along));
        r.position.y = -0.85f * full.bounds.min.y;
        rocks.push_back(r);
        return std::nullopt;
    };
    if (o.lodRocks)
        if (auto e = forEachRock(count, o.rockTriangles, o.threads, addRock)) return *e;

    // Sun: 40 degrees up, from behind the camera's start and a little to the right, so both rows
    // of panels are lit from the front and cast their shadows down the street.
    Light sun;
    sun.name = b.intern("sun");
    sun.type = LightType::Directional;
    sun.color = {1.0f, 0.97f, 0.92f};
    sun.intensity = 3.0f;
    sun.castsShadows = o.shadows;
    s.lights.lights.push_back(sun);
    Camera cam;
    cam.name = b.intern("camera");
    cam.yfovRadians = 0.9f;
    cam.znear = 0.1f;
    cam.zfar = 0.0f;
    s.cameras.cameras.push_back(cam);

    for (uint32_t i = 0; i < count; ++i) {
        Node n;
        n.name = b.intern("panel" + std::to_string(i));
        n.translation = panelCentre(i);
        n.rotation = yawRotation(panelYaw(i));
        n.mesh = i;
        n.worldBounds = placed(s.meshes[i].bounds, panelYaw(i), n.translation);
        n.worldSphere = {add(s.meshes[i].boundingSphere.center, n.translation),
                         s.meshes[i].boundingSphere.radius};
        s.nodes.nodes.push_back(n);
        s.info.bounds.grow(n.worldBounds.min);
        s.info.bounds.grow(n.worldBounds.max);
    }
    {
        Node n;
        n.name = b.intern("ground");
        n.mesh = count;
        n.worldBounds = s.meshes[count].bounds;
        n.worldSphere = s.meshes[count].boundingSphere;
        s.nodes.nodes.push_back(n);
        s.info.bounds.grow(n.worldBounds.min);
        s.info.bounds.grow(n.worldBounds.max);
    }
    for (uint32_t i = 0; i < rocks.size(); ++i) {
        const Mesh& m = s.meshes[rocks[i].mesh];
        Node n;
        n.name = m.name;
        n.translation = rocks[i].position;
        n.mesh = rocks[i].mesh;
        n.worldBounds = {add(m.bounds.min, n.translation), add(m.bounds.max, n.translation)};
        n.worldSphere = {add(m.boundingSphere.center, n.translation), m.boundingSphere.radius};
        s.nodes.nodes.push_back(n);
        s.info.bounds.grow(n.worldBounds.min);
        s.info.bounds.grow(n.worldBounds.max);
    }
    const float elevation = 0.6981317f, azimuth = 0.1745329f;
    const Vec3 toSun{std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                     std::cos(elevation) * std::cos(azimuth)};
    {
        Node n;
        n.name = b.intern("sun");
        n.translation = scale(toSun, 100.0f);
        n.rotation = rotationBetween({0, 0, -1}, scale(toSun, -1));
        n.light = 0;
        s.nodes.nodes.push_back(n);
    }

    // The path: eye height down the middle of the street, a key per row, the yaw swaying
    // gently towards one side then the other.
    CameraPath path;
    path.name = b.intern("street");
    path.interpolation = Interpolation::CatmullRom;
    const float eye = 1.7f, startZ = 2.0f;
    for (uint32_t k = 0; k <= rows + 1; ++k) {
        float z = startZ - float(k) * o.spacing;
        CameraKey key;
        key.timeSeconds = (startZ - z) / o.speed;
        key.position = {0, eye, z};
        key.rotation = yawRotation(0.18f * std::sin(float(k) * 0.45f));
        key.yfovRadians = cam.yfovRadians;
        path.keys.push_back(key);
    }
    s.cameraPaths.push_back(path);
    {
        Node n;
        n.name = b.intern("camera");
        n.translation = path.keys.front().position;
        n.rotation = path.keys.front().rotation;
        n.camera = 0;
        s.nodes.nodes.push_back(n);
    }

    if (Status st = validateScene(s); !isOk(st)) {
        std::fprintf(stderr, "pnb-make-stream-scene: internal error: %s\n", st.message.c_str());
        return kExitInternal;
    }

    WriteOptions wo;
    wo.checksums = o.checksums;
    auto writer = Writer::create(o.output, wo);
    auto writeError = [&](const std::string& message) {
        std::fprintf(stderr, "pnb-make-stream-scene: cannot write %s: %s\n", o.output.c_str(),
                     message.c_str());
        return kExitWrite;
    };
    if (!writer) return writeError(writer.error().message);
    if (Status st = writeScene(*writer, s); !isOk(st)) return writeError(st.message);

    // The rocks' details, from the spill file, in rock order.
    uint32_t details = 0;
    auto writeDetails = [&]() -> std::optional<int> {
        std::vector<std::byte> payload;
        for (const Rock& r : rocks) {
            if (!r.detailed) continue;
            if (!spill.read(r.spillOffset, r.spillBytes, payload))
                return writeError(std::string("cannot read back the temporary file: ") +
                                  std::strerror(errno));
            if (Status st = writer->addChunk(tags::kMeshDetail, ChunkTraits<MeshDetail>::version,
                                             payload, ChunkTraits<MeshDetail>::compression);
                !isOk(st))
                return writeError(st.message);
            ++details;
        }
        return std::nullopt;
    };

    // Texels: every texture's coarsest level, then the rocks' details (FORMAT.md §4.1: after
    // every smallest level, before any larger one, as writeScene places them), then the next
    // level of every texture, ...
    uint64_t lastNonZeroEnd = 0;
    {
        MipProducer producer(count, o.textureSize, o.threads);
        for (uint64_t n = 0; n < producer.total(); ++n) {
            MipJob job = producer.next();
            if (job.payload.size() <= 4096 && !checkPayload(job)) {
                std::fprintf(stderr, "pnb-make-stream-scene: internal error: TMIP layout differs "
                                     "from encodeChunk\n");
                return kExitInternal;
            }
            if (Status st = writer->addChunk(tags::kTextureMip, ChunkTraits<TextureMip>::version,
                                             job.payload);
                !isOk(st))
                return writeError(st.message);
            if (job.level > 0) lastNonZeroEnd = writer->size();
            producer.recycle(std::move(job));
            if (n + 1 == count)
                if (auto e = writeDetails()) return *e;
        }
    }
    const auto commitStart = std::chrono::steady_clock::now();
    if (Status st = writer->commit(); !isOk(st)) return writeError(st.message);
    const uint64_t fileBytes = writer->size();
    const auto end = std::chrono::steady_clock::now();

    if (!o.quiet) {
        double seconds = std::chrono::duration<double>(end - start).count();
        double commitSeconds = std::chrono::duration<double>(end - commitStart).count();
        std::printf("wrote %s: %llu bytes, %u textures of %ux%u (%u levels), %zu chunks; "
                    "level-0 TMIPs from byte %llu (%.1f%% of the file); %.2f s (commit and fsync %.2f s), %.0f MB/s\n",
                    o.output.c_str(), (unsigned long long)fileBytes, count, o.textureSize,
                    o.textureSize, levels,
                    3 + s.shaders.size() + s.programs.size() + s.textures.size() +
                        s.materials.size() + s.meshes.size() + 3 + s.cameraPaths.size() +
                        size_t(count) * levels + details,
                    (unsigned long long)lastNonZeroEnd,
                    100.0 * double(fileBytes - lastNonZeroEnd) / double(fileBytes), seconds,
                    commitSeconds,
                    double(fileBytes) / 1e6 / seconds);
        if (!rocks.empty()) {
            std::string perLevel;
            for (uint64_t t : rockTriangles)
                perLevel += (perLevel.empty() ? "" : " / ") + std::to_string(t);
            std::printf("  %zu rocks (%u MDET), triangles by level, all rocks: %s; proxies %llu\n",
                        rocks.size(), details, perLevel.c_str(),
                        (unsigned long long)proxyTriangles);
        }
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    if (auto code = parseArgs(argc, argv, o)) return *code;
    return run(o);
}
