// pnb-convert: OBJ/MTL, glTF 2.0 (and what else assimp reads) → .pnb container.
// A thin command line over convertScene() (pnb_converter/convert.h).

#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <fstream>
#include <iostream>
#include <set>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pnb/output_guard.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/user_cache_directory.h"
#include "pnb_cli/options.h"
#include "pnb_converter/convert.h"
#include "pnb_converter/memory_budget.h"
#include "summary_json.h"

namespace {

using pnb::converter::ConvertErrorKind;
using pnb::converter::ConvertSettings;
using pnb::converter::ConvertSummary;
namespace fs = std::filesystem;

constexpr int kExitOk = 0, kExitUsage = 1, kExitInput = 2, kExitUnsupported = 3, kExitOutput = 4;

struct CliState {
    // The command line adds the neutral default environment unless --no-default-environment.
    ConvertSettings settings = [] {
        ConvertSettings s;
        s.defaultEnvironment = true;
        return s;
    }();
    bool verbose = false, quiet = false;
    std::string testDir;
    std::string batchList; // --batch LIST ("-" = standard input)
    std::string summaryJson; // --summary-json FILE
};

bool parseUnsigned(const char* text, uint32_t lo, uint32_t hi, uint32_t& out) {
    char* end = nullptr;
    long v = std::strtol(text, &end, 10);
    if (!*text || *end || v < long(lo) || v > long(hi)) return false;
    out = uint32_t(v);
    return true;
}

bool parseFloat(const char* text, float lo, float hi, float& out) {
    char* end = nullptr;
    float v = std::strtof(text, &end);
    if (!*text || *end || !(v >= lo && v <= hi)) return false;
    out = v;
    return true;
}

static_assert(pnb::kDefaultLightCutoffLux == 0.01f, "--light-cutoff's help states the default");

// Declarative option table (pnb_cli): it parses the command line and prints --help (docs/STYLE.md §7).
std::vector<pnb::cli::Option> options(CliState& c, bool& help) {
    using pnb::cli::flag;
    using pnb::cli::valued;
    return {
        valued("Input and output", "-o, --output", "FILE|DIR",
             "the .pnb file to write; with several inputs or --batch, the directory to write "
             "<input stem>.pnb files into (created if missing)",
             [&c](const char* a) { c.settings.output = a; return true; }),
        valued("Input and output", "--batch", "LIST",
             "convert every input listed in LIST (one per line: INPUT, or INPUT<tab>OUTPUT; '#' "
             "comments; '-' reads standard input) in this one process",
             [&c](const char* a) { c.batchList = a; return true; }),
        valued("Input and output", "--sidecar", "FILE",
             "material overrides (default: <input stem>.pnb.json next to the input, if present)",
             [&c](const char* a) { c.settings.sidecar = a; return true; }),
        flag("Input and output", "--no-sidecar", "ignore any sidecar file",
             [&c](const char*) { c.settings.noSidecar = true; return true; }),
        valued("Input and output", "--path", "FILE",
             "camera path keyframes (JSON; default: an orbit around the scene)",
             [&c](const char* a) { c.settings.cameraPath = a; return true; }),
        valued("Input and output", "--depfile", "FILE",
             "write a Make-style dependency file listing every file read (for Ninja)",
             [&c](const char* a) { c.settings.depfile = a; return true; }),
        valued("Input and output", "--summary-json", "FILE",
             "also write the summary (sizes, counts, quantisation and LOD errors, worst texture "
             "PSNR, stage times) as JSON, for tools that compare conversions",
             [&c](const char* a) { c.summaryJson = a; return true; }),
        flag("Meshes", "--quantize",
             "16-bit positions, octahedral normals, half-float UVs; prints the error introduced",
             [&c](const char*) { c.settings.mesh.quantize = true; return true; }),
        valued("Meshes", "--lods", "N", "add N simplified levels of detail (0..8, default 0)",
             [&c](const char* a) { return parseUnsigned(a, 0, 8, c.settings.mesh.lodCount); }),
        valued("Meshes", "--lod-ratio", "R", "index count of each level vs the previous (default 0.5)",
             [&c](const char* a) {
                 char* end = nullptr;
                 float r = std::strtof(a, &end);
                 c.settings.mesh.lodRatio = r;
                 return *a && !*end && r > 0.01f && r < 1.0f;
             }),
        flag("Meshes", "--lod-free-borders",
             "let LODs move open-boundary vertices (more reduction for open meshes; meshes that meet "
             "edge to edge then crack at their seams)",
             [&c](const char*) { c.settings.mesh.lodLockBorders = false; return true; }),
        flag("Meshes", "--no-mesh-proxies",
             "with --lods: write each mesh once, all levels in its MESH chunk (default: a coarse proxy "
             "first and the full detail after the first frame's data, for streaming players)",
             [&c](const char*) { c.settings.mesh.proxies = false; return true; }),
        flag("Meshes", "--no-optimize", "skip vertex-cache/overdraw/fetch optimisation",
             [&c](const char*) { c.settings.mesh.optimize = false; return true; }),
        flag("Textures", "--compress-textures", "BC1/BC3/BC4/BC5 block compression; prints the PSNR it cost",
             [&c](const char*) { c.settings.texture.compress = true; return true; }),
        valued("Textures", "--max-texture-size", "N", "scale textures down to at most N texels a side",
             [&c](const char* a) {
                 return parseUnsigned(a, 1, 65536, c.settings.texture.maxSize);
             }),
        valued("Textures", "--max-memory", "SIZE",
             "memory textures may use while they are decoded and mip-mapped, e.g. 512M or 2G, "
             "shared by the parallel jobs; an image whose header declares more is refused before "
             "it is read (default: see below)",
             [&c](const char* a) {
                 std::optional<uint64_t> bytes = pnb::converter::parseByteSize(a);
                 c.settings.texture.maxMemoryBytes = bytes.value_or(0);
                 return bytes.has_value();
             }),
        valued("Environment", "--environment", "FILE",
             "image-based lighting from an equirectangular HDR image (.hdr, .exr, anything "
             "OpenImageIO reads; row 0 is the zenith, the centre column looks along +X)",
             [&c](const char* a) { c.settings.environment.image = a; return *a != 0; }),
        flag("Environment", "--sky",
             "image-based lighting from the analytic Preetham sky, lit by the scene's sun (its "
             "first directional light, or the default sun)",
             [&c](const char*) { c.settings.environment.sky = true; return true; }),
        flag("Environment", "--no-default-environment",
             "do not add the neutral default environment ('default-studio': a grey studio with soft "
             "highlights) that a source with no lights and no --environment/--sky otherwise gets",
             [&c](const char*) { c.settings.defaultEnvironment = false; return true; }),
        valued("Environment", "--sky-turbidity", "T", "haze of the sky, 2..10 (default 3)",
             [&c](const char* a) {
                 return parseFloat(a, 2.0f, 10.0f, c.settings.environment.skyTurbidity);
             }),
        valued("Environment", "--sky-ground-albedo", "A",
             "reflectance of the ground below the horizon, 0..1 (default 0.2)",
             [&c](const char* a) {
                 return parseFloat(a, 0.0f, 1.0f, c.settings.environment.skyGroundAlbedo);
             }),
        valued("Environment", "--environment-size", "N",
             "halve the radiance image until it is at most N texels high (default 1024)",
             [&c](const char* a) {
                 return parseUnsigned(a, 1, 65536, c.settings.environment.maxRadianceHeight);
             }),
        valued("Environment", "--specular-size", "N",
             "face size of the prefiltered specular cube, a power of two 4..2048 (default 128)",
             [&c](const char* a) {
                 uint32_t& n = c.settings.environment.specularSize;
                 return parseUnsigned(a, 4, 2048, n) && (n & (n - 1)) == 0;
             }),
        valued("Lights", "--light-cutoff", "LUX",
             "a point or spot light without a range stops where its illuminance falls to LUX "
             "(> 0; default 0.01): the range written for it, warned",
             [&c](const char* a) {
                 return parseFloat(a, std::numeric_limits<float>::denorm_min(),
                                   std::numeric_limits<float>::max(), c.settings.lights.cutoffLux);
             }),
        flag("Container", "--compress",
             "zstd-compress meshes and texels too (smaller file; loads can no longer be zero-copy)",
             [&c](const char*) { c.settings.compressBulk = true; return true; }),
        flag("Container", "--no-checksums", "do not store payload checksums",
             [&c](const char*) { c.settings.checksums = false; return true; }),
        valued("Container", "--set", "KEY=VALUE",
             "store a render setting, e.g. shadows.cascades=4 (repeatable)",
             [&c](const char* a) {
                 const char* eq = std::strchr(a, '=');
                 if (!eq || eq == a) return false;
                 c.settings.renderSettings.emplace_back(std::string(a, eq), std::string(eq + 1));
                 return true;
             }),
        flag("Container", "--gi",
             "pack the global-illumination programs and turn GI on (same as --set gi.enabled=true)",
             [&c](const char*) {
                 c.settings.renderSettings.emplace_back("gi.enabled", "true");
                 return true;
             }),
        valued("General", "-j, --jobs", "N", "worker threads (default: all cores)",
             [&c](const char* a) { return parseUnsigned(a, 1, 256, c.settings.jobs); }),
        flag("General", "--no-validate-shaders", "skip the glslang check of packed shaders",
             [&c](const char*) { c.settings.validateShaders = false; return true; }),
        flag("General", "--no-shader-cache",
             "validate every shader program again instead of trusting the cache of programs "
             "validated before (see below)",
             [&c](const char*) { c.settings.shaderCache = false; return true; }),
        flag("General", "-v, --verbose", "also print per-chunk-kind size statistics",
             [&c](const char*) { c.verbose = true; return true; }),
        flag("General", "-q, --quiet", "print errors only",
             [&c](const char*) { c.quiet = true; return true; }),
        valued("General", "--test", "DIR",
             "convert every scene under DIR to a temporary file and verify it; one line each",
             [&c](const char* a) { c.testDir = a; return true; }),
        flag("General", "-h, --help", "print this help", [&help](const char*) {
            help = true;
            return pnb::cli::Verdict::stopHere();
        }),
    };
}

void printHelp(const std::vector<pnb::cli::Option>& table) {
    std::printf("usage: pnb-convert INPUT -o OUTPUT.pnb [options]\n"
                "       pnb-convert INPUT... -o DIR [options]      (batch: one process)\n"
                "       pnb-convert --batch LIST [-o DIR] [options]\n"
                "       pnb-convert --test DIR [options]\n\n"
                "Converts OBJ/MTL and glTF 2.0 (.gltf, .glb, Draco) scenes, and the other formats\n"
                "assimp reads, into a Penumbra container.\n");
    std::fputs(pnb::cli::helpText(table, {.column = 29}).c_str(), stdout);
    std::printf("\n--max-memory defaults to half of the memory this process may use (physical "
                "RAM,\nulimit -v and the cgroup limit, whichever is least): %s here.\n",
                pnb::converter::formatBytes(pnb::converter::defaultMemoryBudget()).c_str());
    std::printf("\nShader programs glslang accepted are remembered by a hash of their text and the\n"
                "glslang version, in memory and in %s/shader-validation\n"
                "($PNB_CACHE_DIR, else $XDG_CACHE_HOME/penumbra, else ~/.cache/penumbra); a\n"
                "damaged or unwritable cache only means validating again.\n",
                [] {
                    std::string d = pnb::userCacheDirectory("PNB_CACHE_DIR");
                    return d.empty() ? std::string("(no cache directory here)") : d;
                }()
                    .c_str());
    std::printf("\nBatch mode (several inputs, or --batch) converts each input as a separate run\n"
                "would, byte for byte, and goes on after a failed input; it exits 0 if all\n"
                "converted, else with the code of the first failure, and names every failure.\n");
    std::printf("\nExit codes:\n  0  ok\n  1  usage error\n"
                "  2  input error (missing, malformed or inconsistent source; the message names "
                "the file and item)\n"
                "  3  unsupported (a required glTF extension we do not implement)\n"
                "  4  output error (the container could not be written; any old file is intact)\n");
}

int exitCodeOf(ConvertErrorKind k) {
    switch (k) {
    case ConvertErrorKind::Input: return kExitInput;
    case ConvertErrorKind::Unsupported: return kExitUnsupported;
    case ConvertErrorKind::Output: return kExitOutput;
    }
    return kExitInput;
}

// Progress: a redrawn bar on a terminal, one line per stage otherwise.
class Progress {
public:
    explicit Progress(bool enabled) : mEnabled(enabled), mTty(isatty(STDERR_FILENO)) {}
    void operator()(const std::string& stage, size_t done, size_t total) {
        if (!mEnabled) return;
        if (mTty) {
            int width = 30;
            int filled = total ? int(double(done) / double(total) * width) : width;
            std::fprintf(stderr, "\r%-9s [%.*s%*s] %zu/%zu", stage.c_str(), filled,
                         "##############################", width - filled, "", done, total);
            if (done == total) std::fprintf(stderr, "\n");
            std::fflush(stderr);
        } else if (stage != mLastStage) {
            std::fprintf(stderr, "%s: %zu items\n", stage.c_str(), total);
        }
        mLastStage = stage;
    }

private:
    bool mEnabled, mTty;
    std::string mLastStage;
};

std::string bytesText(uint64_t n) {
    char buf[32];
    if (n >= (1u << 20)) std::snprintf(buf, sizeof(buf), "%.2f MiB", double(n) / (1 << 20));
    else if (n >= 1024) std::snprintf(buf, sizeof(buf), "%.1f KiB", double(n) / 1024);
    else std::snprintf(buf, sizeof(buf), "%llu B", (unsigned long long)n);
    return buf;
}

// The converter's additions, one line (not warnings: nothing in the source was wrong):
// "added: default sun, default environment, default camera, default orbit (flagged generated;
// ...)", or "" when it added nothing.
std::string addedLine(const ConvertSummary& r) {
    const std::vector<std::string> added = pnb::converter::addedDefaults(r);
    if (added.empty()) return {};
    std::string line = "added:";
    for (size_t i = 0; i < added.size(); ++i) line += (i ? ", " : " ") + added[i];
    line += " (flagged generated";
    if (r.defaultEnvironment) line += "; --no-default-environment leaves the environment out";
    if (r.defaultPath) line += "; --path gives your own camera path";
    return line + ")";
}

void printSummary(const ConvertSettings& s, const ConvertSummary& r) {
    std::printf("wrote %s (%s)\n", s.output.c_str(), bytesText(r.outputBytes).c_str());
    std::printf("  meshes %zu (%zu submeshes), nodes %zu, materials %zu (%zu deferred in %zu "
                "layer%s, %zu forward), textures %zu, lights %zu, cameras %zu, paths %zu\n",
                r.meshes, r.submeshes, r.nodes, r.materials, r.deferredMaterials,
                r.deferredLayers.size(), r.deferredLayers.size() == 1 ? "" : "s",
                r.forwardMaterials, r.textures, r.lights, r.cameras, r.cameraPaths);
    if (r.instances)
        std::printf("  instances %zu (EXT_mesh_gpu_instancing: each mesh stored once, one draw "
                    "item per copy)\n", r.instances);
    if (r.skins || r.clips || r.morphedMeshes)
        std::printf("  skins %zu (%zu joints), animations (%zu clips, the longest %.3f s), morphed "
                    "meshes %zu: played by the deform pass\n",
                    r.skins, r.joints, r.clips, r.longestClipSeconds, r.morphedMeshes);
    std::printf("  triangles %llu in, %llu out (%llu degenerate, %llu non-finite removed); "
                "vertices %llu in, %llu out\n",
                (unsigned long long)r.inputTriangles, (unsigned long long)r.outputTriangles,
                (unsigned long long)r.degenerateTriangles,
                (unsigned long long)r.nonFiniteTriangles, (unsigned long long)r.inputVertices,
                (unsigned long long)r.outputVertices);
    if (s.mesh.quantize)
        std::printf("  quantisation: max position error %.3g units, max normal error %.3g deg\n",
                    r.maxPositionError, r.maxNormalErrorRadians * 57.2957795);
    for (size_t l = 0; l < r.lodErrors.size(); ++l)
        std::printf("  LOD %zu: max simplification error %.3g units\n", l + 1, r.lodErrors[l]);
    std::printf("  mesh data %s, texture data %s", bytesText(r.meshBytes).c_str(),
                bytesText(r.textureBytes).c_str());
    if (r.minTexturePsnrDb > 0) std::printf(" (block compressed, worst PSNR %.1f dB)", r.minTexturePsnrDb);
    std::printf("\n  programs (%zu", r.programs.size());
    if (r.programsValidated + r.programsFromCache > 0)
        std::printf("; %zu validated, %zu known valid from the cache", r.programsValidated,
                    r.programsFromCache);
    std::printf("):");
    for (const std::string& p : r.programs) std::printf(" %s", p.c_str());
    std::printf("\n");
    if (r.environment) {
        const pnb::converter::EnvironmentSummary& e = *r.environment;
        std::printf("  environment: %s %ux%u %s, specular cube %u^2 x %u levels %s, LUT %u^2, "
                    "%s, %.2f s",
                    e.name.c_str(), e.radianceWidth, e.radianceHeight,
                    pnb::converter::textureFormatName(e.radianceFormat), e.specularSize,
                    e.specularLevels, pnb::converter::textureFormatName(e.specularFormat),
                    e.lutSize, bytesText(e.bytes).c_str(), e.seconds);
        if (e.downsampled) std::printf(" (image halved %u time(s))", e.downsampled);
        std::printf("\n");
    }
    for (const std::string& o : r.omitted) std::printf("  not written: %s\n", o.c_str());
    for (const std::string& n : r.notRendered) std::printf("  not rendered: %s\n", n.c_str());
    if (const std::string added = addedLine(r); !added.empty()) std::printf("  %s\n", added.c_str());
    std::printf("  time:");
    double total = 0;
    for (const auto& st : r.stages) {
        std::printf(" %s %.3fs", st.stage.c_str(), st.seconds);
        total += st.seconds;
    }
    std::printf(" (total %.3fs)\n", total);
}

void printChunkStats(const std::string& path) {
    auto c = pnb::Container::open(path);
    if (!c) return;
    std::map<std::string, std::array<uint64_t, 3>> byTag; // count, stored, raw
    std::vector<std::string> order;
    for (const pnb::ChunkInfo& ch : c->chunks()) {
        std::string tag = ch.header.tag.str();
        if (!byTag.count(tag)) order.push_back(tag);
        auto& e = byTag[tag];
        e[0] += 1;
        e[1] += ch.header.storedSize;
        e[2] += ch.header.rawSize;
    }
    std::printf("  chunks:  tag   count      stored         raw  ratio\n");
    for (const std::string& t : order) {
        auto& e = byTag[t];
        std::printf("           %s %6llu %11s %11s  %.2fx\n", t.c_str(), (unsigned long long)e[0],
                    bytesText(e[1]).c_str(), bytesText(e[2]).c_str(),
                    e[1] ? double(e[2]) / double(e[1]) : 1.0);
    }
}

bool isSceneFile(const fs::path& p) {
    static const char* kExtensions[] = {".gltf", ".glb", ".obj", ".fbx", ".dae", ".3ds", ".ply",
                                        ".stl", ".blend", ".off", ".x", ".ac", ".ase", ".lwo"};
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
    for (const char* e : kExtensions)
        if (ext == e) return true;
    return false;
}

// --test DIR: every scene file converts and verifies, or fails with a one-line error.
int runTest(CliState& c) {
    std::error_code ec;
    std::vector<fs::path> files;
    for (auto it = fs::recursive_directory_iterator(c.testDir, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
        if (it->is_regular_file() && isSceneFile(it->path())) files.push_back(it->path());
    if (ec) {
        std::fprintf(stderr, "Error: cannot list %s: %s\n", c.testDir.c_str(), ec.message().c_str());
        return kExitInput;
    }
    std::sort(files.begin(), files.end());
    fs::path out = fs::temp_directory_path() / ("pnb-convert-test-" + std::to_string(getpid()) + ".pnb");
    size_t ok = 0, failed = 0;
    for (const fs::path& f : files) {
        ConvertSettings s = c.settings;
        s.input = f.string();
        s.output = out.string();
        auto r = pnb::converter::convertScene(s);
        std::string line;
        if (r) {
            auto container = pnb::Container::open(s.output);
            pnb::Status st = container ? container->verifyAll() : container.error();
            if (pnb::isOk(st)) {
                auto scene = pnb::readScene(*container);
                if (!scene) st = scene.error();
            }
            if (pnb::isOk(st)) {
                ++ok;
                line = "ok " + std::to_string(r->outputTriangles) + " triangles";
            } else {
                ++failed;
                line = "VERIFY FAILED: " + st.describe();
            }
        } else {
            ++failed;
            std::string m = r.error().message;
            std::replace(m.begin(), m.end(), '\n', ' ');
            line = std::string("error ") + std::to_string(exitCodeOf(r.error().kind)) + ": " + m;
        }
        std::printf("%s\t%s\n", fs::relative(f, c.testDir).string().c_str(), line.c_str());
        std::fflush(stdout);
    }
    fs::remove(out, ec);
    std::printf("%zu converted and verified, %zu failed with an error\n", ok, failed);
    return kExitOk;
}

// [SECTION] batch mode

struct BatchItem {
    std::string input, output;
    std::string origin; // "LIST:12" or "argument 3", for messages
};

std::string trimmedCopy(const std::string& s) {
    size_t b = s.find_first_not_of(" \t\r"), e = s.find_last_not_of(" \t\r");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

// Reads LIST: one input per line, optionally a tab and its output; blank lines and lines whose
// first non-blank character is '#' are skipped. Relative paths are taken from the current
// directory, as on the command line.
bool readBatchList(const std::string& list, std::vector<BatchItem>& items) {
    std::ifstream file;
    std::istream* in = &std::cin;
    if (list != "-") {
        file.open(list);
        if (!file) {
            std::fprintf(stderr, "Error: cannot read the batch list %s\n", list.c_str());
            return false;
        }
        in = &file;
    }
    std::string line;
    for (size_t n = 1; std::getline(*in, line); ++n) {
        std::string origin = (list == "-" ? std::string("stdin") : list) + ":" + std::to_string(n);
        size_t tab = line.find('\t');
        std::string input = trimmedCopy(line.substr(0, tab));
        std::string output = tab == std::string::npos ? "" : trimmedCopy(line.substr(tab + 1));
        if (input.empty() && output.empty()) continue;
        if (!input.empty() && input[0] == '#') continue;
        if (input.empty()) {
            std::fprintf(stderr, "Error: %s: an output without an input\n", origin.c_str());
            return false;
        }
        if (line.find('\0') != std::string::npos) { // no file name holds one: a damaged list
            std::fprintf(stderr, "Error: %s: a NUL byte in the line (no path can contain one)\n",
                         origin.c_str());
            return false;
        }
        items.push_back({input, output, origin});
    }
    if (file.bad() || (list == "-" && std::cin.bad())) {
        std::fprintf(stderr, "Error: cannot read the batch list %s\n", list.c_str());
        return false;
    }
    return true;
}

// Converts every item in this process, in list order, each exactly as `pnb-convert INPUT -o
// OUTPUT` with the same options would. A failure is reported and the batch goes on.
int runBatch(CliState& c, std::vector<BatchItem> items) {
    if (items.empty()) {
        std::fprintf(stderr, "Error: no inputs to convert%s%s\n",
                     c.batchList.empty() ? "" : ": the batch list has none: ", c.batchList.c_str());
        return kExitUsage;
    }
    if (!c.settings.depfile.empty() || !c.settings.sidecar.empty() || !c.summaryJson.empty()) {
        std::fprintf(stderr, "Error: --depfile, --sidecar and --summary-json name one file each "
                             "and cannot be used with several inputs (each input's <stem>.pnb.json sidecar "
                             "still applies)\n");
        return kExitUsage;
    }
    const std::string dir = c.settings.output;
    bool dirNeeded = false;
    for (BatchItem& it : items) {
        if (!it.output.empty()) continue;
        if (dir.empty()) {
            std::fprintf(stderr, "Error: %s: no output for %s: give one after a tab, or -o DIR\n",
                         it.origin.c_str(), it.input.c_str());
            return kExitUsage;
        }
        it.output = (fs::path(dir) / (fs::path(it.input).stem().string() + ".pnb")).string();
        dirNeeded = true;
    }
    // Two inputs writing one file would silently keep only the last, and an output that is
    // another item's input would replace it: refuse before converting (real paths, symlinked
    // directories and hard links included; each conversion then checks its own output against
    // every file it reads).
    std::vector<pnb::RoleFile> inputs, outputs;
    if (c.batchList != "-") inputs.push_back({c.batchList, "the batch list"});
    for (const BatchItem& it : items) {
        inputs.push_back({it.input, "the input of " + it.origin});
        outputs.push_back({it.output, "the output of " + it.origin});
    }
    if (pnb::Status st = pnb::checkOutputs(inputs, outputs); !pnb::isOk(st)) {
        std::fprintf(stderr, "Error: %s\n", st.message.c_str());
        return kExitUsage;
    }
    if (dirNeeded) {
        std::error_code ec;
        fs::create_directories(dir, ec);
        if (ec) {
            std::fprintf(stderr, "Error: cannot create the output directory %s: %s\n",
                         dir.c_str(), ec.message().c_str());
            return kExitOutput;
        }
    }

    // Inputs are converted concurrently, by as many workers as --jobs allows (each conversion
    // gets an equal part of the threads and of the memory budget); results are reported in list
    // order. Outputs do not depend on either (convert.h: identical bytes for any job count).
    const unsigned threads =
        c.settings.jobs ? c.settings.jobs : std::max(1u, std::thread::hardware_concurrency());
    const unsigned workers = unsigned(std::min<size_t>(threads, items.size()));
    ConvertSettings base = c.settings;
    base.jobs = std::max(1u, threads / workers);
    const uint64_t budget = c.settings.texture.maxMemoryBytes
                                ? c.settings.texture.maxMemoryBytes
                                : pnb::converter::defaultMemoryBudget();
    base.texture.maxMemoryBytes = std::max<uint64_t>(1, budget / workers);

    using Outcome = std::optional<pnb::Result<ConvertSummary, pnb::converter::ConvertError>>;
    std::vector<Outcome> outcomes(items.size());
    std::vector<std::pair<const BatchItem*, int>> failures;
    // How many inputs got each addition: one line at the end instead of one per file.
    std::map<std::string, size_t> additions;
    std::mutex reportMutex;
    size_t nextToReport = 0;
    auto report = [&](size_t i) { // under reportMutex, in list order
        const BatchItem& it = items[i];
        const auto& r = *outcomes[i];
        if (!r) {
            int code = exitCodeOf(r.error().kind);
            std::fprintf(stderr, "Error: [%zu/%zu] %s: %s\n", i + 1, items.size(),
                         it.input.c_str(), r.error().message.c_str());
            failures.emplace_back(&it, code);
        } else if (!c.quiet) {
            for (const std::string& a : pnb::converter::addedDefaults(*r)) ++additions[a];
            for (const std::string& w : r->warnings)
                std::fprintf(stderr, "Warning: %s: %s\n", it.input.c_str(), w.c_str());
            ConvertSettings shown = c.settings;
            shown.output = it.output;
            if (c.verbose) {
                printSummary(shown, *r);
                for (const std::string& n : r->notes) std::printf("  note: %s\n", n.c_str());
                printChunkStats(it.output);
            } else {
                double seconds = 0;
                for (const auto& st : r->stages) seconds += st.seconds;
                std::printf("[%zu/%zu] %s -> %s (%s, %llu triangles, %.3f s)\n", i + 1,
                            items.size(), it.input.c_str(), it.output.c_str(),
                            bytesText(r->outputBytes).c_str(),
                            (unsigned long long)r->outputTriangles, seconds);
                for (const std::string& n : r->notRendered)
                    std::printf("    not rendered: %s\n", n.c_str());
            }
        }
        std::fflush(stdout);
        outcomes[i].reset(); // the summary is no longer needed
    };
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t i = next++; i < items.size(); i = next++) {
            ConvertSettings s = base;
            s.input = items[i].input;
            s.output = items[i].output;
            Outcome r;
            // One input's exhausted memory (or any other escape) must not end the others.
            try {
                r.emplace(pnb::converter::convertScene(s));
            } catch (const std::exception& e) {
                r.emplace(pnb::converter::ConvertError{
                    ConvertErrorKind::Input, s.input + ": conversion aborted: " + e.what()});
            }
            std::lock_guard lock(reportMutex);
            outcomes[i] = std::move(r);
            while (nextToReport < items.size() && outcomes[nextToReport])
                report(nextToReport++);
        }
    };
    std::vector<std::thread> pool;
    for (unsigned w = 1; w < workers; ++w) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    if (!c.quiet) {
        std::printf("batch: %zu converted, %zu failed\n", items.size() - failures.size(),
                    failures.size());
        if (!additions.empty()) {
            std::string line = "batch: added";
            const char* sep = " ";
            // In addedDefaults' order, with the number of inputs that got each.
            for (const char* name : {"default sun", "default environment", "default camera",
                                     "default orbit"})
                if (auto it = additions.find(name); it != additions.end()) {
                    line += sep + std::string(name) + " to " + std::to_string(it->second);
                    sep = ", ";
                }
            std::printf("%s (flagged generated; --no-default-environment, --path)\n", line.c_str());
        }
    }
    if (failures.empty()) return kExitOk;
    std::fprintf(stderr, "batch: %zu of %zu input(s) failed:\n", failures.size(), items.size());
    for (const auto& [it, code] : failures)
        std::fprintf(stderr, "  %s (%s, exit code %d)\n", it->input.c_str(), it->origin.c_str(),
                     code);
    return failures.front().second;
}

} // namespace

int main(int argc, char** argv) {
    // Serve allocations up to 32 MiB from the heap and keep freed memory (up to 512 MiB) for
    // reuse, instead of glibc's default of a fresh mmap for each one over 128 KiB returned at
    // once: the stages allocate and free buffers of megabytes per mesh and texture, and a fresh
    // page costs a page fault and its zeroing each time, which on the VMs we measured cost more
    // than the work (docs/CONVERTER.md, "Issue 30": the benchmark OBJ's conversion took 25 %
    // less CPU). The peak memory is the same; the process keeps it until it exits.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    CliState c;
    std::vector<std::string> positional;
    bool help = false;
    const std::vector<pnb::cli::Option> table = options(c, help);
    auto input = [&positional](const char* arg) {
        positional.push_back(arg);
        return true;
    };
    if (auto e = pnb::cli::parse(table, input, argc, argv)) {
        switch (e->kind) {
        case pnb::cli::ParseError::Kind::UnknownOption:
            std::fprintf(stderr, "Error: unknown option '%s' (see --help)\n", e->option.c_str());
            break;
        case pnb::cli::ParseError::Kind::MissingValue:
            std::fprintf(stderr, "Error: %s needs %s\n", e->option.c_str(), e->valueName.c_str());
            break;
        case pnb::cli::ParseError::Kind::BadValue:
            std::fprintf(stderr, "Error: invalid value '%s' for %s (see --help)\n", e->value.c_str(),
                         e->option.c_str());
            break;
        default: std::fprintf(stderr, "Error: %s (see --help)\n", pnb::cli::describe(*e).c_str());
        }
        return kExitUsage;
    }
    if (help) {
        printHelp(table);
        return kExitOk;
    }
    if (c.settings.environment.sky && !c.settings.environment.image.empty()) {
        std::fprintf(stderr, "Error: --environment and --sky both give the environment; "
                             "choose one\n");
        return kExitUsage;
    }
    if (!c.testDir.empty()) return runTest(c);
    if (!c.batchList.empty() && c.batchList != "-") { // a FIFO or device list would never end
        const pnb::RoleFile list[] = {{c.batchList, "the batch list"}};
        if (pnb::Status st = pnb::checkInputs(list); !pnb::isOk(st)) {
            std::fprintf(stderr, "Error: %s\n", st.message.c_str());
            return kExitUsage;
        }
    }
    if (!c.quiet) // the output's lock (pnb/file_lock.h): a save of pnb-edit is in progress
        c.settings.outputLock.onWait = [] {
            std::fprintf(stderr, "waiting: another program is saving the output\n");
        };
    if (!c.batchList.empty() || positional.size() > 1) {
        std::vector<BatchItem> items;
        if (!c.batchList.empty() && !readBatchList(c.batchList, items)) return kExitUsage;
        for (size_t k = 0; k < positional.size(); ++k)
            items.push_back({positional[k], "", "argument " + std::to_string(k + 1)});
        if (c.settings.output.empty() && positional.size() > 1) {
            std::fprintf(stderr, "Error: several inputs need -o DIR (see --help)\n");
            return kExitUsage;
        }
        return runBatch(c, std::move(items));
    }
    if (positional.size() != 1 || c.settings.output.empty()) {
        std::fprintf(stderr, "Error: expected one INPUT and -o OUTPUT (see --help)\n");
        return kExitUsage;
    }
    c.settings.input = positional[0];
    {
        const pnb::RoleFile inputs[] = {{c.settings.input, "the input"},
                                        {c.settings.sidecar, "the sidecar (--sidecar)"},
                                        {c.settings.environment.image, "the environment (--environment)"},
                                        {c.settings.cameraPath, "the camera path (--path)"}};
        const pnb::RoleFile outputs[] = {{c.settings.output, "the output (-o)"},
                                         {c.summaryJson, "the summary (--summary-json)"},
                                         {c.settings.depfile, "the dependency file (--depfile)"}};
        if (pnb::Status st = pnb::checkOutputs(inputs, outputs); !pnb::isOk(st)) {
            std::fprintf(stderr, "Error: %s\n", st.message.c_str());
            return kExitUsage;
        }
        // The files the import reads are known only then: the conversion checks them.
        if (!c.summaryJson.empty())
            c.settings.alsoWrites.push_back({c.summaryJson, "the summary (--summary-json)"});
    }
    Progress progress(!c.quiet);
    auto result = pnb::converter::convertScene(
        c.settings, [&](const std::string& stage, size_t done, size_t total) {
            progress(stage, done, total);
        });
    if (!result) {
        std::fprintf(stderr, "Error: %s\n", result.error().message.c_str());
        return exitCodeOf(result.error().kind);
    }
    if (!c.summaryJson.empty()) {
        const std::string error = pnb::converter::writeSummaryJson(c.summaryJson, c.settings, *result);
        if (!error.empty()) {
            std::fprintf(stderr, "Error: %s (the container was written)\n", error.c_str());
            return kExitOutput;
        }
    }
    if (!c.quiet) {
        for (const std::string& w : result->warnings)
            std::fprintf(stderr, "Warning: %s\n", w.c_str());
        printSummary(c.settings, *result);
        if (c.verbose) {
            for (const std::string& n : result->notes) std::printf("  note: %s\n", n.c_str());
            printChunkStats(c.settings.output);
        }
    }
    return kExitOk;
}
