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
// Files: make_stream_scene_main.cpp (this: the command line, one pnb_cli option table),
// make_stream_scene_layout.cpp (the scene and its writing), make_stream_scene_textures.cpp
// (texels), make_stream_scene_geometry.cpp (meshes and rocks); make_stream_scene.h between them.

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "make_stream_scene.h"
#include "pnb_cli/options.h"

namespace stream_scene {

namespace {

// [SECTION] command line

using pnb::cli::flag;
using pnb::cli::valued;
using pnb::cli::Verdict;

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

// "bad --OPTION 'VALUE' (range)": how this tool has always refused a value.
Verdict bad(const char* option, const char* value, const char* range) {
    return Verdict::error(std::string("bad ") + option + " '" + value + "' (" + range + ")");
}

// A handler storing a whole number lo..hi into `field` (`powerOfTwo`: only powers of two).
template <typename Field>
pnb::cli::Handler count(const char* option, Field& field, uint64_t lo, uint64_t hi,
                        const char* range, bool powerOfTwo = false) {
    return [=, &field](const char* text) {
        uint64_t n = 0;
        if (!parseU64(text, n) || n < lo || n > hi || (powerOfTwo && (n & (n - 1)) != 0))
            return bad(option, text, range);
        field = Field(n);
        return Verdict(true);
    };
}

// What a valued option at the end of the command line is missing, in this tool's words.
const char* needs(const std::string& option) {
    if (option == "--size" || option == "--texture-size") return "a size";
    if (option == "--spacing") return "metres";
    if (option == "--speed") return "metres per second";
    if (option == "--threads") return "1 or 2";
    return "a count"; // --textures, --rock-triangles
}

// The options, laid out in --help as this tool always has (column 20); -h/--help is not listed.
std::vector<pnb::cli::Option> options(Options& o, bool& help) {
    // A flag's handler: sets `field` to `value`.
    auto set = [](bool& field, bool value) {
        return [&field, value](const char*) {
            field = value;
            return true;
        };
    };
    std::vector<pnb::cli::Option> table = {
        valued("", "--size", "SIZE", "file of at least SIZE bytes (K, M, G suffix = KiB, MiB, GiB)",
               [&o](const char* text) {
                   return parseSize(text, o.sizeBytes) ? Verdict(true)
                                                       : bad("--size", text, "e.g. 64M, 1G, 5G");
               }),
        valued("", "--textures", "N", "exactly N textured panels (1..100000)",
               count("--textures", o.textures, 1, 100000, "1..100000")),
        valued("", "--texture-size", "N", "texels a side, power of two 8..4096 (default 2048)",
               count("--texture-size", o.textureSize, 8, 4096, "a power of two 8..4096", true)),
        valued("", "--spacing", "M", "metres between panels on one side, 1..1000 (default 6)",
               [&o](const char* text) {
                   return parseFloat(text, 1, 1000, o.spacing) ? Verdict(true)
                                                               : bad("--spacing", text, "1..1000");
               }),
        valued("", "--speed", "M/S", "camera path speed, 0.1..1000 (default 5)",
               [&o](const char* text) {
                   return parseFloat(text, 0.1f, 1000, o.speed) ? Verdict(true)
                                                                : bad("--speed", text, "0.1..1000");
               }),
        flag("", "--no-shadows", "the sun casts no shadows", set(o.shadows, false)),
        flag("", "--no-checksums", "write no payload checksums", set(o.checksums, false)),
        valued("", "--threads", "1|2", "generate texels on a second thread (default 2)",
               count("--threads", o.threads, 1, 2, "1 or 2")),
        flag("", "-q", "print nothing on success", set(o.quiet, true)),
        flag("", "--lod-rocks",
             "a rock beside every panel: its own mesh with 4 levels of\n"
             "detail: a coarse proxy (MESH) + its full detail (MDET)",
             set(o.lodRocks, true)),
        valued("", "--rock-triangles", "N",
               "about N triangles a rock, 100..1000000 (default 20000)",
               [&o, rocks = count("--rock-triangles", o.rockTriangles, 100, 1000000,
                                  "100..1000000")](const char* text) {
                   o.rockTrianglesGiven = true;
                   return rocks(text);
               }),
        flag("", "-h, --help", "print this help and exit",
             [&help](const char*) {
                 help = true;
                 return Verdict::stopHere();
             }),
    };
    table.back().hidden = true;
    return table;
}

void printUsage(std::FILE* out, const std::vector<pnb::cli::Option>& table) {
    std::fprintf(
        out, "usage: pnb-make-stream-scene OUT.pnb (--size SIZE | --textures N)\n"
             "                             [--texture-size N] [--spacing M] [--speed M/S]\n"
             "                             [--no-shadows] [--no-checksums] [--threads 1|2] [-q]\n"
             "                             [--lod-rocks [--rock-triangles N]]\n"
             "\n");
    std::fputs(pnb::cli::helpText(table, {.column = 20}).c_str(), out);
}

int usageError(const std::string& message, const std::vector<pnb::cli::Option>& table) {
    std::fprintf(stderr, "pnb-make-stream-scene: %s\n\n", message.c_str());
    printUsage(stderr, table);
    return kExitUsage;
}

// This tool's wording of a parse error.
std::string wording(const pnb::cli::ParseError& e) {
    using Kind = pnb::cli::ParseError::Kind;
    switch (e.kind) {
    case Kind::MissingValue:
        return e.option + " needs " + needs(e.option);
    case Kind::BadValue:
    case Kind::Positional:
        return e.why;
    case Kind::FlagWithValue:
        return "unknown option '" + e.option + "=" + e.value + "'";
    case Kind::UnknownOption:
        break;
    }
    return "unknown option '" + e.option + "'";
}

// Returns an exit code if the program should stop (usage error or --help).
std::optional<int> parseArgs(int argc, char** argv, Options& o) {
    bool help = false;
    const std::vector<pnb::cli::Option> table = options(o, help);
    // The output file; "-" is an unknown option, as every other argument starting with '-'.
    auto output = [&o](const char* arg) {
        if (*arg == '-') return Verdict::error("unknown option '" + std::string(arg) + "'");
        if (!o.output.empty())
            return Verdict::error("more than one output file ('" + o.output + "', '" + arg + "')");
        o.output = arg;
        return Verdict(true);
    };
    if (auto e = pnb::cli::parse(table, output, argc, argv)) return usageError(wording(*e), table);
    if (help) {
        printUsage(stdout, table);
        return 0;
    }
    if (o.output.empty()) return usageError("no output file", table);
    if ((o.sizeBytes == 0) == (o.textures == 0))
        return usageError("give exactly one of --size and --textures", table);
    if (o.rockTrianglesGiven && !o.lodRocks)
        return usageError("--rock-triangles needs --lod-rocks", table);
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
