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
//
// Files: make_stream_scene_main.cpp (this: the command line), make_stream_scene_layout.cpp (the
// scene and its writing), make_stream_scene_textures.cpp (texels), make_stream_scene_geometry.cpp
// (meshes and rocks); make_stream_scene.h between them.

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "make_stream_scene.h"

namespace stream_scene {

namespace {

// [SECTION] command line

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

} // namespace

} // namespace stream_scene

int main(int argc, char** argv) {
    using namespace stream_scene;
    Options o;
    if (auto code = parseArgs(argc, argv, o)) return *code;
    return run(o);
}
