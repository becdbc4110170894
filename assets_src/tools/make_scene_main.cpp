// pnb-make-scene: writes a procedural source scene (procedural_scenes.h) as a glTF binary.
//
//   pnb-make-scene NAME OUT.glb [--triangles N] [--seed N] [--lights N] [--texture-size N]
//                  [--unit-scale S] [--origin X,Y,Z] [--sun-elevation DEG] [--sun-azimuth DEG]
//                  [--camera-near M]
//   pnb-make-scene --list
//
// Exit codes: 0 ok, 2 usage error, 4 output error. Output is deterministic: the same arguments
// give identical bytes.

#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/procedural_scenes.h"
#include "pnb_assets/scene_transform.h"

namespace {

void printUsage(std::FILE* out) {
    std::fprintf(out,
                 "usage: pnb-make-scene NAME OUT.glb [--triangles N] [--seed N] [--lights N]\n"
                 "                      [--texture-size N] [--unit-scale S] [--origin X,Y,Z]\n"
                 "                      [--sun-elevation DEG] [--sun-azimuth DEG] [--camera-near M]\n"
                 "       pnb-make-scene --list\n"
                 "\n"
                 "  --triangles N      approximate rendered triangle count (default: the scene's)\n"
                 "  --seed N           layout seed, 0..2^64-1 (default 1; box-room ignores it)\n"
                 "  --lights N         point lights, 0..4096 (light-field only; default 8)\n"
                 "  --texture-size N   texels a side, 4..4096 (load-test only; default 1024)\n"
                 "  --unit-scale S     wrap the scene in a root node scaled by S (cameras' near/far,\n"
                 "                     point-light ranges and intensities follow): the same image\n"
                 "                     in another unit of length\n"
                 "  --origin X,Y,Z     translate that root node (world units)\n"
                 "  --sun-elevation D  turn the sun to D degrees above the horizon (0..90)\n"
                 "  --sun-azimuth D    turn the sun to azimuth D degrees about +Y (from +X to -Z)\n"
                 "  --camera-near M    every camera's near plane, in the scene's own unit\n"
                 "  --list             print the scene names with a one-line description\n");
}

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

} // namespace

int main(int argc, char** argv) {
    std::string name, out;
    pnb::assets::SceneRequest request;
    pnb::assets::SceneTransform transform;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--list") {
            for (const pnb::assets::ProceduralScene& s : pnb::assets::proceduralScenes())
                std::printf("%-14.*s %.*s\n", int(s.name.size()), s.name.data(),
                            int(s.summary.size()), s.summary.data());
            return 0;
        } else if (a == "-h" || a == "--help") {
            printUsage(stdout);
            return 0;
        } else if (a == "--triangles" || a == "--seed") {
            uint64_t v = 0;
            if (i + 1 >= argc || !parseU64(argv[i + 1], v) || (a == "--triangles" && v == 0) ||
                (a == "--triangles" && v > 100'000'000)) {
                std::fprintf(stderr, "Error: %s takes a number%s\n", a.c_str(),
                             a == "--triangles" ? " from 1 to 100000000" : "");
                return 2;
            }
            ++i;
            (a == "--triangles" ? request.targetTriangles : request.seed) = v;
        } else if (a == "--lights") {
            uint64_t v = 0;
            if (i + 1 >= argc || !parseU64(argv[i + 1], v) || v > 4096) {
                std::fprintf(stderr, "Error: --lights takes a number from 0 to 4096\n");
                return 2;
            }
            ++i;
            request.lights = uint32_t(v);
        } else if (a == "--texture-size") {
            uint64_t v = 0;
            if (i + 1 >= argc || !parseU64(argv[i + 1], v) || v < 4 || v > 4096) {
                std::fprintf(stderr, "Error: --texture-size takes a number from 4 to 4096\n");
                return 2;
            }
            ++i;
            request.textureSize = uint32_t(v);
        } else if (a == "--unit-scale" || a == "--sun-elevation" || a == "--sun-azimuth" ||
                   a == "--camera-near") {
            double v = 0;
            if (i + 1 >= argc || !parseDouble(argv[i + 1], v)) {
                std::fprintf(stderr, "Error: %s takes a number\n", a.c_str());
                return 2;
            }
            ++i;
            if (a == "--unit-scale") transform.unitScale = v;
            else if (a == "--sun-elevation") transform.sunElevationDegrees = float(v);
            else if (a == "--sun-azimuth") transform.sunAzimuthDegrees = float(v);
            else transform.cameraNear = float(v);
        } else if (a == "--origin") {
            if (i + 1 >= argc || !parseTriple(argv[i + 1], transform.origin)) {
                std::fprintf(stderr, "Error: --origin takes X,Y,Z (three numbers)\n");
                return 2;
            }
            ++i;
        } else if (!a.empty() && a[0] != '-' && name.empty()) {
            name = a;
        } else if (!a.empty() && a[0] != '-' && out.empty()) {
            out = a;
        } else {
            std::fprintf(stderr, "Error: unexpected argument '%s' (see --help)\n", a.c_str());
            return 2;
        }
    }
    if (name.empty() || out.empty()) {
        std::fprintf(stderr, "Error: need a scene name and an output file\n");
        printUsage(stderr);
        return 2;
    }

    if (request.lights && name != "light-field") {
        std::fprintf(stderr, "Error: --lights applies to light-field only\n");
        return 2;
    }
    if (request.textureSize && name != "load-test") {
        std::fprintf(stderr, "Error: --texture-size applies to load-test only\n");
        return 2;
    }

    auto t0 = std::chrono::steady_clock::now();
    std::optional<pnb::assets::gltf::Document> doc =
        pnb::assets::buildProceduralScene(name, request);
    if (!doc) {
        std::fprintf(stderr, "Error: unknown scene '%s' (see --list)\n", name.c_str());
        return 2;
    }
    if (std::string why = pnb::assets::applySceneTransform(*doc, transform); !why.empty()) {
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
