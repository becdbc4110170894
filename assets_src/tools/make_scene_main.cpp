// pnb-make-scene: writes a procedural source scene (procedural_scenes.h) as a glTF binary.
//
//   pnb-make-scene NAME OUT.glb [--triangles N] [--seed N] [--lights N] [--texture-size N]
//                  [--count N] [--unit-scale S] [--origin X,Y,Z] [--sun-elevation DEG]
//                  [--sun-azimuth DEG] [--camera-near M]
//   pnb-make-scene --list
//
// Exit codes: 0 ok, 2 usage error, 4 output error. Output is deterministic: the same arguments
// give identical bytes. The options are one pnb_cli table, which also prints --help.

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/procedural_scenes.h"
#include "pnb_assets/scene_transform.h"
#include "pnb_cli/options.h"

namespace {

using pnb::cli::flag;
using pnb::cli::valued;
using pnb::cli::Verdict;

// Parses a whole decimal unsigned number; false on anything else (sign, junk, overflow).
bool parseU64(const char* text, uint64_t& out) {
    if (!text || *text < '0' || *text > '9') return false;
    errno = 0;
    char* end = nullptr;
    unsigned long long v = std::strtoull(text, &end, 10);
    if (errno != 0 || *end != '\0') return false;
    out = v;
    return true;
}

// Parses a whole finite decimal number (strtod syntax); false on anything else.
bool parseDouble(const char* text, double& out) {
    if (!text || !*text) return false;
    errno = 0;
    char* end = nullptr;
    double v = std::strtod(text, &end);
    if (errno != 0 || *end != '\0' || !std::isfinite(v)) return false;
    out = v;
    return true;
}

// Parses "X,Y,Z" into three finite floats.
bool parseTriple(const char* text, pnb::assets::gltf::Float3& out) {
    if (!text) return false;
    std::string s = text;
    for (int k = 0; k < 3; ++k) {
        size_t comma = s.find(',');
        if ((k < 2) != (comma != std::string::npos)) return false;
        double v = 0;
        if (!parseDouble(s.substr(0, comma).c_str(), v)) return false;
        out[size_t(k)] = float(v);
        s = comma == std::string::npos ? "" : s.substr(comma + 1);
    }
    return true;
}

// A handler storing a whole number from lo to hi (the field's own type) into `field`.
template <typename Field> pnb::cli::Handler count(Field& field, uint64_t lo, uint64_t hi) {
    return [&field, lo, hi](const char* text) {
        uint64_t v = 0;
        if (!parseU64(text, v) || v < lo || v > hi) return false;
        field = Field(v);
        return true;
    };
}

// A handler storing a finite number into `field` (double or float).
template <typename Field> pnb::cli::Handler number(Field& field) {
    return [&field](const char* text) {
        double v = 0;
        if (!parseDouble(text, v)) return false;
        field = Field(v);
        return true;
    };
}

// The sentence a missing or refused value of `option` is reported with: the same whether the
// value is absent or wrong, as this tool has always worded it.
std::string valueWanted(const std::string& option) {
    if (option == "--triangles") return "--triangles takes a number from 1 to 100000000";
    if (option == "--lights") return "--lights takes a number from 0 to 4096";
    if (option == "--texture-size") return "--texture-size takes a number from 4 to 4096";
    if (option == "--count") return "--count takes a number from 1 to 1000";
    if (option == "--origin") return "--origin takes X,Y,Z (three numbers)";
    return option + " takes a number";
}

// What the command line asks for; `list` and `help` end parsing where they stand.
struct Request {
    std::string name, out;
    pnb::assets::SceneRequest scene;
    pnb::assets::SceneTransform transform;
    bool list = false, help = false;
};

// The options; the help rows keep the layout this tool's --help has always had (column 21, the
// value names of the synopsis shortened where they would not fit). -h/--help is not listed.
std::vector<pnb::cli::Option> options(Request& r) {
    pnb::assets::SceneTransform& t = r.transform;
    std::vector<pnb::cli::Option> table = {
        valued("", "--triangles", "N", "approximate rendered triangle count (default: the scene's)",
               count(r.scene.targetTriangles, 1, 100'000'000)),
        valued("", "--seed", "N", "layout seed, 0..2^64-1 (default 1; box-room ignores it)",
               count(r.scene.seed, 0, UINT64_MAX)),
        valued("", "--lights", "N", "point lights, 0..4096 (light-field only; default 8)",
               count(r.scene.lights, 0, 4096)),
        valued("", "--texture-size", "N", "texels a side, 4..4096 (load-test only; default 1024)",
               count(r.scene.textureSize, 4, 4096)),
        valued("", "--count", "N", "walkers, 1..1000 (crowd only; default 100)",
               count(r.scene.count, 1, 1000)),
        valued("", "--unit-scale", "S",
               "wrap the scene in a root node scaled by S (cameras' near/far,\n"
               "point-light ranges and intensities follow): the same image\n"
               "in another unit of length",
               number(t.unitScale)),
        valued("", "--origin", "X,Y,Z", "translate that root node (world units)",
               [&t](const char* text) { return parseTriple(text, t.origin); }),
        valued("", "--sun-elevation", "D", "turn the sun to D degrees above the horizon (0..90)",
               number(t.sunElevationDegrees)),
        valued("", "--sun-azimuth", "D",
               "turn the sun to azimuth D degrees about +Y (from +X to -Z)",
               number(t.sunAzimuthDegrees)),
        valued("", "--camera-near", "M", "every camera's near plane, in the scene's own unit",
               number(t.cameraNear)),
        flag("", "--list", "print the scene names with a one-line description",
             [&r](const char*) {
                 r.list = true;
                 return Verdict::stopHere();
             }),
        flag("", "-h, --help", "print this help and exit",
             [&r](const char*) {
                 r.help = true;
                 return Verdict::stopHere();
             }),
    };
    table.back().hidden = true;
    return table;
}

void printUsage(std::FILE* out, const std::vector<pnb::cli::Option>& table) {
    std::fprintf(
        out, "usage: pnb-make-scene NAME OUT.glb [--triangles N] [--seed N] [--lights N]\n"
             "                      [--texture-size N] [--count N] [--unit-scale S] [--origin X,Y,Z]\n"
             "                      [--sun-elevation DEG] [--sun-azimuth DEG] [--camera-near M]\n"
             "       pnb-make-scene --list\n\n");
    std::fputs(pnb::cli::helpText(table, {.column = 21}).c_str(), out);
}

// The scene name, then the output file; anything else (a third argument, "-", "") is refused.
Verdict positional(Request& r, const char* arg) {
    const bool plain = *arg && *arg != '-';
    std::string& slot = r.name.empty() ? r.name : r.out;
    if (!plain || !slot.empty()) return false;
    slot = arg;
    return true;
}

// This tool's wording of a parse error (always "Error: ..." and exit code 2).
void reportParseError(const pnb::cli::ParseError& e) {
    using Kind = pnb::cli::ParseError::Kind;
    std::string sentence;
    switch (e.kind) {
    case Kind::MissingValue:
    case Kind::BadValue:
        sentence = valueWanted(e.option);
        break;
    case Kind::FlagWithValue:
        sentence = "unexpected argument '" + e.option + "=" + e.value + "' (see --help)";
        break;
    case Kind::UnknownOption:
        sentence = "unexpected argument '" + e.option + "' (see --help)";
        break;
    case Kind::Positional:
        sentence = "unexpected argument '" + e.value + "' (see --help)";
        break;
    }
    std::fprintf(stderr, "Error: %s\n", sentence.c_str());
}

} // namespace

int main(int argc, char** argv) {
    Request r;
    const std::vector<pnb::cli::Option> table = options(r);
    const pnb::cli::Handler nameThenOutput = [&r](const char* arg) { return positional(r, arg); };
    if (auto e = pnb::cli::parse(table, nameThenOutput, argc, argv)) {
        reportParseError(*e);
        return 2;
    }
    if (r.list) {
        for (const pnb::assets::ProceduralScene& s : pnb::assets::proceduralScenes())
            std::printf("%-14.*s %.*s\n", int(s.name.size()), s.name.data(), int(s.summary.size()),
                        s.summary.data());
        return 0;
    }
    if (r.help) {
        printUsage(stdout, table);
        return 0;
    }
    const std::string& name = r.name;
    const std::string& out = r.out;
    if (name.empty() || out.empty()) {
        std::fprintf(stderr, "Error: need a scene name and an output file\n");
        printUsage(stderr, table);
        return 2;
    }

    if (r.scene.lights && name != "light-field") {
        std::fprintf(stderr, "Error: --lights applies to light-field only\n");
        return 2;
    }
    if (r.scene.count && name != "crowd") {
        std::fprintf(stderr, "Error: --count applies to crowd only\n");
        return 2;
    }
    if (r.scene.textureSize && name != "load-test") {
        std::fprintf(stderr, "Error: --texture-size applies to load-test only\n");
        return 2;
    }

    auto t0 = std::chrono::steady_clock::now();
    std::optional<pnb::assets::gltf::Document> doc =
        pnb::assets::buildProceduralScene(name, r.scene);
    if (!doc) {
        std::fprintf(stderr, "Error: unknown scene '%s' (see --list)\n", name.c_str());
        return 2;
    }
    if (std::string why = pnb::assets::applySceneTransform(*doc, r.transform); !why.empty()) {
        std::fprintf(stderr, "Error: %s: %s\n", name.c_str(), why.c_str());
        return 2;
    }
    pnb::assets::gltf::GlbStats stats;
    std::vector<uint8_t> bytes = pnb::assets::gltf::encodeGlb(*doc, &stats);
    pnb::Status status = pnb::writeFileAtomic(out, bytes);
    if (!pnb::isOk(status)) {
        std::fprintf(stderr, "Error: %s\n", status.message.c_str());
        return 4;
    }
    double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::printf("wrote %s: %s, %llu triangles rendered (%llu stored, %llu vertices), "
                "%llu bytes, %.0f ms\n",
                out.c_str(), name.c_str(), (unsigned long long)stats.renderedTriangles,
                (unsigned long long)stats.uniqueTriangles, (unsigned long long)stats.vertices,
                (unsigned long long)stats.sizeBytes, ms);
    return 0;
}
