// pnb-reference: ray-traced ground truth for one frame the player dumped
// (`pnb-play --dump position,normal,shadow`), and how far the player's shadows are from it.
//
// Reads SCENE.pnb and DIR/{frame.json, position.exr, normal.exr, shadow.exr}; writes
// OUT/{visibility.exr, visibility.png, shadow_diff.png, metrics.json}; with --indirect and --sky
// also the one-bounce and sky-light irradiance truths (and their comparison with the player's
// indirect.exr, sky.exr). The work is the pnb_reference library (ShadowTracer, IndirectTracer,
// SkyTracer, compareShadow, compareIndirect, texelRatioByCascade); this file is the image and
// JSON I/O around it. The input contract is docs/REFERENCE.md. frame.json's optional
// "shadow_light_index" K makes the judged light LGHT light K, a point or spot light placed by its
// node (local_light.h), instead of the directional light of "toward_light".
//
// Exit codes: 0 ok, 1 usage, 2 input error (missing or malformed file; the message names it),
// 3 unsupported scene data, 4 output error, 5 Embree failure.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "pnb/atomic_file.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_reference/indirect_metrics.h"
#include "pnb_reference/indirect_tracer.h"
#include "pnb_reference/local_light.h"
#include "pnb_reference/shadow_metrics.h"
#include "pnb_reference/shadow_tracer.h"
#include "pnb_reference/sky_tracer.h"

namespace {

namespace fs = std::filesystem;
using pnb::reference::ShadowTracer;
using pnb::reference::TracerErrorKind;

constexpr int kExitOk = 0, kExitUsage = 1, kExitInput = 2, kExitUnsupported = 3,
              kExitOutput = 4, kExitEmbree = 5;

// A failure on the way: the exit code and a sentence naming the file.
struct Failure {
    int exitCode = kExitInput;
    std::string message;
};
template <class T> using Expected = pnb::Result<T, Failure>;

struct Settings {
    std::string scene, frameDir, outDir, prefix;
    bool quiet = false;
    bool indirect = false;
    pnb::reference::IndirectSettings indirectSettings;
    bool sky = false;
    pnb::reference::SkySettings skySettings;
    // Given on the command line (they override what frame.json records).
    std::optional<double> skyRotationDegrees, skyIntensity;
    std::string usageError; // an option's value that could not be used (exit 1)
};

// [SECTION] command line: a declarative table that parses and prints --help (docs/STYLE.md §7)

struct Option {
    const char* name; // "--out" or "-q, --quiet"
    const char* arg;  // nullptr for flags
    const char* help;
    std::function<void(Settings&, const char*)> apply;
};

const std::vector<Option>& options() {
    static const std::vector<Option> table = {
        {"--frame", "DIR",
         "the frame the player dumped: frame.json, position.exr, normal.exr, shadow.exr (required)",
         [](Settings& s, const char* a) { s.frameDir = a; }},
        {"--prefix", "P",
         "input names start with P (pnb-play --dump writes frameK_position.exr: --prefix frameK_)",
         [](Settings& s, const char* a) { s.prefix = a; }},
        {"--out", "DIR", "where to write the outputs (default: the --frame directory)",
         [](Settings& s, const char* a) { s.outDir = a; }},
        {"--indirect", nullptr,
         "also the one-bounce diffuse irradiance (Monte Carlo): indirect_reference.exr, "
         "indirect_stderr.exr, and against the player's indirect.exr when dumped",
         [](Settings& s, const char*) { s.indirect = true; }},
        {"--samples", "N", "cosine-weighted rays per pixel for --indirect (default 256)",
         [](Settings& s, const char* a) { s.indirectSettings.samples = uint32_t(std::max(1L, std::atol(a))); }},
        {"--indirect-lights", "all|sun",
         "light the bounce with every light (default: the scene's truth) or the sun alone (what "
         "the player's GI models)",
         [](Settings& s, const char* a) {
             s.indirectSettings.lights = std::string(a) == "sun" ? pnb::reference::IndirectLights::Sun
                                                                 : pnb::reference::IndirectLights::All;
         }},
        {"--seed", "S", "random seed of --indirect and --sky (default 1)",
         [](Settings& s, const char* a) { s.indirectSettings.seed = s.skySettings.seed = uint64_t(std::atoll(a)); }},
        {"--sky", nullptr,
         "also the sky-light irradiance (Monte Carlo, the ENVM environment hidden by the scene): "
         "sky_reference.exr, sky_stderr.exr, and against the player's sky.exr when dumped",
         [](Settings& s, const char*) { s.sky = true; }},
        {"--sky-samples", "N", "cosine-weighted rays per pixel for --sky (default 256)",
         [](Settings& s, const char* a) { s.skySettings.samples = uint32_t(std::max(1L, std::atol(a))); }},
        {"--sky-source", "image|sh",
         "the sky's radiance: the ENVM image (default: the truth) or the radiance of its irradiance "
         "SH (the player's unoccluded term exactly: isolates its sky-visibility error)",
         [](Settings& s, const char* a) {
             const std::string v = a;
             if (v == "image") s.skySettings.source = pnb::reference::SkySource::Image;
             else if (v == "sh") s.skySettings.source = pnb::reference::SkySource::Sh;
             else s.usageError = "--sky-source must be image or sh, not " + v;
         }},
        {"--sky-visibility", "on|off",
         "trace what hides the sky (default on); off gives the unoccluded irradiance",
         [](Settings& s, const char* a) {
             const std::string v = a;
             if (v == "on" || v == "off") s.skySettings.visibility = v == "on";
             else s.usageError = "--sky-visibility must be on or off, not " + v;
         }},
        {"--sky-rotation-deg", "D",
         "the environment turned by D degrees about +Y (as sh9RotateY: +X towards -Z); default: "
         "frame.json's ibl_rotation_degrees, else 0",
         [](Settings& s, const char* a) {
             char* end = nullptr;
             const double v = std::strtod(a, &end);
             if (end == a || *end || !std::isfinite(v)) s.usageError = std::string("--sky-rotation-deg needs a number, not ") + a;
             else s.skyRotationDegrees = v;
         }},
        {"--sky-intensity", "X",
         "the environment's radiance scale (the player's ibl.intensity); default: frame.json's "
         "ibl_intensity, else 1",
         [](Settings& s, const char* a) {
             char* end = nullptr;
             const double v = std::strtod(a, &end);
             if (end == a || *end || !std::isfinite(v) || v < 0) s.usageError = std::string("--sky-intensity needs a number >= 0, not ") + a;
             else s.skyIntensity = v;
         }},
        {"-q, --quiet", nullptr, "print errors only", [](Settings& s, const char*) { s.quiet = true; }},
        {"-h, --help", nullptr, "print this help", nullptr},
    };
    return table;
}

bool optionMatches(const Option& o, const std::string& arg) {
    std::string names = o.name;
    for (size_t start = 0; start < names.size();) {
        size_t comma = names.find(", ", start);
        if (names.substr(start, comma == std::string::npos ? std::string::npos : comma - start) == arg)
            return true;
        if (comma == std::string::npos) break;
        start = comma + 2;
    }
    return false;
}

void printHelp() {
    std::printf(
        "usage: pnb-reference SCENE.pnb --frame DIR [--prefix P] [--out DIR] [--indirect ...] "
        "[--sky ...] [-q]\n\n"
        "Ray traces (Embree) the true visibility of the shadowing light for every pixel of a\n"
        "frame dumped by `pnb-play --dump position,normal,shadow` (the directional light of\n"
        "frame.json's toward_light, or the point or spot light its shadow_light_index names),\n"
        "and compares the player's shadow factor with it. Writes visibility.exr,\n"
        "visibility.png and metrics.json, and shadow_diff.png when the frame has shadow.exr\n"
        "(and counts non-finite pixels of hdr.exr when present). With --indirect, also the "
        "one-bounce diffuse irradiance\n"
        "(Monte Carlo, with its standard error) and its comparison with the player's\n"
        "indirect.exr (`pnb-play --dump indirect`). With --sky, also the irradiance from the\n"
        "scene's environment (ENVM) with the scene hiding the sky, and its comparison with the\n"
        "player's sky.exr (`pnb-play --dump sky`). See docs/REFERENCE.md.\n\n"
        "options:\n");
    for (const Option& o : options()) {
        std::string left = std::string(o.name) + (o.arg ? std::string(" ") + o.arg : "");
        std::printf("  %-24s %s\n", left.c_str(), o.help);
    }
    std::printf("\nexit codes: 0 ok, 1 usage, 2 input error, 3 unsupported scene data,\n"
                "            4 output error, 5 Embree failure\n");
}

// [SECTION] inputs

struct Frame {
    glm::dvec3 cameraPosition{0.0};
    glm::vec3 towardLight{0.0f}; // the sun's; unused (and optional) with shadowLightIndex
    // The judged light is LGHT light K, a point or spot light (optional key).
    std::optional<uint32_t> shadowLightIndex;
    int width = 0, height = 0;
    // The player's environment settings, when the dump records them (optional keys).
    std::optional<double> iblRotationDegrees, iblIntensity;
};

Expected<Frame> readFrameJson(const std::string& path) {
    auto fail = [&](const std::string& why) { return Failure{kExitInput, path + ": " + why}; };
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return fail("missing (the player writes it with --dump)");
    std::ifstream in(path, std::ios::binary);
    nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) return fail("not a valid JSON object");

    auto vec3 = [&](const char* key, double out[3]) -> std::optional<Failure> {
        auto it = j.find(key);
        if (it == j.end() || !it->is_array() || it->size() != 3)
            return fail(std::string("\"") + key + "\" must be an array of 3 numbers");
        for (size_t i = 0; i < 3; ++i) {
            if (!(*it)[i].is_number()) return fail(std::string("\"") + key + "\" must hold numbers");
            out[i] = (*it)[i].get<double>();
            if (!std::isfinite(out[i])) return fail(std::string("\"") + key + "\" must be finite");
        }
        return std::nullopt;
    };
    auto dimension = [&](const char* key, int& out) -> std::optional<Failure> {
        auto it = j.find(key);
        if (it == j.end() || !it->is_number_integer() || it->get<int64_t>() < 1 ||
            it->get<int64_t>() > 65536)
            return fail(std::string("\"") + key + "\" must be an integer in 1..65536");
        out = int(it->get<int64_t>());
        return std::nullopt;
    };

    Frame f;
    double camera[3], light[3];
    if (auto e = vec3("camera_position", camera)) return *e;
    if (auto it = j.find("shadow_light_index"); it != j.end()) {
        // An index into LGHT; whether it names a point or spot light is checked against the
        // scene once it is read.
        if (!it->is_number_integer() || it->get<int64_t>() < 0 ||
            it->get<int64_t>() > int64_t(UINT32_MAX))
            return fail("\"shadow_light_index\" must be an integer >= 0 (an index into the scene's "
                        "lights), not " +
                        it->dump());
        f.shadowLightIndex = uint32_t(it->get<int64_t>());
    }
    if (auto e = dimension("width", f.width)) return *e;
    if (auto e = dimension("height", f.height)) return *e;
    f.cameraPosition = {camera[0], camera[1], camera[2]};
    if (!f.shadowLightIndex) { // the sun: its direction is the light
        if (auto e = vec3("toward_light", light)) return *e;
        glm::dvec3 l(light[0], light[1], light[2]);
        double length = glm::length(l);
        if (!(length > 1e-12)) return fail("\"toward_light\" must not be zero");
        f.towardLight = glm::vec3(l / length);
    }
    auto optionalNumber = [&](const char* key, std::optional<double>& out) -> std::optional<Failure> {
        auto it = j.find(key);
        if (it == j.end()) return std::nullopt;
        if (!it->is_number() || !std::isfinite(it->get<double>()))
            return fail(std::string("\"") + key + "\" must be a finite number");
        out = it->get<double>();
        return std::nullopt;
    };
    if (auto e = optionalNumber("ibl_rotation_degrees", f.iblRotationDegrees)) return *e;
    if (auto e = optionalNumber("ibl_intensity", f.iblIntensity)) return *e;
    return f;
}

// A float image, channels interleaved, rows in file order.
struct FloatImage {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels;
    float at(size_t pixel, int channel) const { return pixels[pixel * size_t(channels) + size_t(channel)]; }
};

// Reads `path` as float, keeping the channels named in `wanted` (by name, e.g. "R"; a file with
// unnamed or differently named channels is read positionally) in that order.
Expected<FloatImage> readExr(const std::string& path, const std::vector<std::string>& wanted,
                             size_t required, const Frame& frame) {
    auto fail = [&](const std::string& why) { return Failure{kExitInput, path + ": " + why}; };
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return fail("missing (the player writes it with --dump)");
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string why = OIIO::geterror();
        return fail("not a readable image (" + (why.empty() ? std::string("unknown error") : why) + ")");
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width != frame.width || spec.height != frame.height || spec.depth > 1)
        return fail(std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                    " does not match frame.json's " + std::to_string(frame.width) + "x" +
                    std::to_string(frame.height));
    if (size_t(spec.nchannels) < required)
        return fail("has " + std::to_string(spec.nchannels) + " channels, expected at least " +
                    std::to_string(required));
    std::vector<float> all(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data())) {
        std::string why = in->geterror();
        return fail("could not be decoded (" + (why.empty() ? std::string("unknown error") : why) + ")");
    }
    in->close();

    FloatImage img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = int(std::min(wanted.size(), size_t(spec.nchannels)));
    std::vector<int> source(size_t(img.channels));
    for (int c = 0; c < img.channels; ++c) {
        int named = spec.channelindex(wanted[size_t(c)]);
        source[size_t(c)] = named >= 0 ? named : c;
    }
    const size_t pixels = size_t(img.width) * size_t(img.height);
    img.pixels.resize(pixels * size_t(img.channels));
    for (size_t p = 0; p < pixels; ++p)
        for (int c = 0; c < img.channels; ++c)
            img.pixels[p * size_t(img.channels) + size_t(c)] =
                all[p * size_t(spec.nchannels) + size_t(source[size_t(c)])];
    return img;
}

// [SECTION] outputs: encoded in memory, then placed with pnb::writeFileAtomic (readers never see
// a partial file; a failed write leaves the previous one).

Expected<bool> writeImage(const std::string& path, int width, int height, int channels,
                          OIIO::TypeDesc type, const void* pixels) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput memory(bytes);
    auto out = OIIO::ImageOutput::create(path, &memory);
    if (!out || !out->supports("ioproxy"))
        return Failure{kExitOutput, path + ": OpenImageIO cannot write this format to memory"};
    OIIO::ImageSpec spec(width, height, channels, type);
    if (channels == 1) spec.channelnames = {"Y"};
    if (type == OIIO::TypeDesc::FLOAT) spec.attribute("compression", "zip");
    if (!out->open(path, spec) || !out->write_image(type, pixels) || !out->close())
        return Failure{kExitOutput, path + ": encoding failed (" + out->geterror() + ")"};
    pnb::Status s = pnb::writeFileAtomic(path, bytes);
    if (!pnb::isOk(s)) return Failure{kExitOutput, s.describe()};
    return true;
}

Expected<bool> writeText(const std::string& path, const std::string& text) {
    pnb::Status s = pnb::writeFileAtomic(
        path, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    if (!pnb::isOk(s)) return Failure{kExitOutput, s.describe()};
    return true;
}

// Colours of the PNG views (8-bit sRGB-encoded).
struct Rgb8 {
    uint8_t r, g, b;
};
constexpr Rgb8 kLit{255, 255, 255}, kShadow{0, 0, 0}, kNoGeometry{0, 0, 96};
constexpr Rgb8 kAgreeLit{200, 200, 200}, kAgreeShadow{96, 96, 96};
constexpr Rgb8 kFalseShadow{230, 30, 30}; // red: player shadowed, truly lit
constexpr Rgb8 kFalseLit{30, 200, 30};    // green: player lit, truly shadowed
constexpr Rgb8 kCoverage{230, 0, 230};    // magenta: only one of the two has geometry
constexpr Rgb8 kNotReached{64, 48, 80}; // dim violet: a local light does not reach it (not judged)

void put(std::vector<uint8_t>& rgb, size_t pixel, Rgb8 c) {
    rgb[pixel * 3 + 0] = c.r;
    rgb[pixel * 3 + 1] = c.g;
    rgb[pixel * 3 + 2] = c.b;
}

// A tracer's build error as an exit code and a sentence naming the scene.
Failure tracerFailure(const std::string& scenePath, const pnb::reference::TracerError& e) {
    int code = e.kind == TracerErrorKind::Input         ? kExitInput
               : e.kind == TracerErrorKind::Unsupported ? kExitUnsupported
                                                        : kExitEmbree;
    return Failure{code, scenePath + ": " + e.message};
}

// The normals the irradiance truths integrate around: the player's shading normal where it
// dumped one (deferred surfaces), else the surface's own from the positions (forward surfaces,
// no normal dump).
std::vector<glm::vec3> irradianceNormals(const std::vector<glm::vec3>& positions,
                                         const std::vector<glm::vec3>& shadingNormals, const Frame& frame) {
    std::vector<glm::vec3> normals = pnb::reference::normalsFromPositions(positions, frame.width, frame.height);
    for (size_t p = 0; p < positions.size() && p < shadingNormals.size(); ++p)
        if (glm::length(shadingNormals[p]) > 0.5f) normals[p] = shadingNormals[p];
    return normals;
}

// The player's dumped irradiance (rgb) where the frame has a surface; NaN elsewhere, so both
// sides count the same pixels.
std::vector<glm::vec3> playerIrradiance(const FloatImage& image, const std::vector<glm::vec3>& positions) {
    std::vector<glm::vec3> p(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        p[i] = {image.at(i, 0), image.at(i, 1), image.at(i, 2)};
        const glm::vec3 q = positions[i];
        if (!(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z))) p[i] = glm::vec3(NAN);
    }
    return p;
}

// compareIndirect's figures into a metrics.json object (the "indirect" and "sky" objects share
// them).
void putComparison(nlohmann::ordered_json& j, const pnb::reference::IndirectErrorMetrics& m) {
    j["pixels"] = m.pixels;
    j["player_mean_luminance"] = m.playerMean;
    j["relative_rmse_percent"] = m.relativeRmsePercent;
    j["reference_noise_percent"] = m.referenceNoisePercent;
    j["corrected_rmse_percent"] = m.correctedRmsePercent;
    j["energy_ratio"] = m.energyRatio;
    j["channel_ratio"] = {m.channelRatio[0], m.channelRatio[1], m.channelRatio[2]};
    j["leak_percent"] = m.leakPercent;
    // The scorecard (noise removed like corrected_rmse_percent): the baselines in the same pixels.
    j["zero_rmse_percent"] = m.zeroRmsePercent;
    j["best_constant_rmse_percent"] = m.bestConstantRmsePercent;
    j["best_scale"] = m.bestScale;
    j["scaled_rmse_percent"] = m.scaledRmsePercent;
    j["correlation"] = m.correlation;
    j["rmse_over_best_constant"] = m.rmseOverBestConstant;
}

// One line of the scorecard under the comparison's line.
void printScorecard(const pnb::reference::IndirectErrorMetrics& m) {
    std::printf("    scorecard: RMSE / best constant %.3f (constant %.1f%%, zero %.1f%%, player x %.3g %.1f%%), "
                "correlation %.3f\n",
                m.rmseOverBestConstant, m.bestConstantRmsePercent, m.zeroRmsePercent, m.bestScale,
                m.scaledRmsePercent, m.correlation);
}

double meanLuminance(const std::vector<glm::vec3>& values, uint64_t& valid) {
    double sum = 0;
    valid = 0;
    for (const glm::vec3& m : values)
        if (std::isfinite(m.x)) sum += pnb::reference::luminance(m), ++valid;
    return valid ? sum / double(valid) : 0.0;
}

// --indirect: the one-bounce truth at the frame's pixels, its images, and (with the player's
// indirect.exr) the comparison. Returns the "indirect" object of metrics.json.
Expected<nlohmann::ordered_json> runIndirect(const Settings& settings, const pnb::Scene& scene, const Frame& frame,
                                             const std::vector<glm::vec3>& positions,
                                             const std::vector<glm::vec3>& shadingNormals,
                                             const std::string& in, const std::string& outDir) {
    using pnb::reference::IndirectTracer;
    std::error_code ec;
    std::optional<FloatImage> player;
    if (fs::exists(in + "indirect.exr", ec)) {
        auto p = readExr(in + "indirect.exr", {"R", "G", "B"}, 3, frame);
        if (!p) return p.error();
        player = std::move(*p);
    }
    auto tracer = IndirectTracer::build(scene, frame.cameraPosition);
    if (!tracer) return tracerFailure(settings.scene, tracer.error());
    const size_t pixels = positions.size();
    const std::vector<glm::vec3> normals = irradianceNormals(positions, shadingNormals, frame);
    std::vector<glm::vec3> mean(pixels), error(pixels);
    auto start = std::chrono::steady_clock::now();
    (*tracer)->irradiance(positions, normals, settings.indirectSettings, mean, error);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    auto a = writeImage(outDir + "/indirect_reference.exr", frame.width, frame.height, 3, OIIO::TypeDesc::FLOAT,
                        mean.data());
    if (!a) return a.error();
    auto b = writeImage(outDir + "/indirect_stderr.exr", frame.width, frame.height, 3, OIIO::TypeDesc::FLOAT,
                        error.data());
    if (!b) return b.error();
    const auto& st = (*tracer)->stats();
    nlohmann::ordered_json j;
    j["lights"] = settings.indirectSettings.lights == pnb::reference::IndirectLights::Sun ? "sun" : "all";
    j["samples"] = settings.indirectSettings.samples;
    j["seed"] = settings.indirectSettings.seed;
    j["tracer"] = {{"triangles", st.triangles}, {"instances", st.instances},
                   {"textured_materials", st.texturedMaterials},
                   {"textures_factor_only", st.texturesFactorOnly}, {"lights", st.lights},
                   {"build_ms", st.buildMs}, {"trace_ms", ms}};
    uint64_t valid = 0;
    j["reference_mean_luminance"] = meanLuminance(mean, valid);
    if (player) {
        auto m = pnb::reference::compareIndirect(playerIrradiance(*player, positions), mean, error);
        putComparison(j, m);
        if (!settings.quiet)
            std::printf("  indirect (%s lights, %u samples): relative RMSE %.1f%% (reference noise %.1f%%, "
                        "without it %.1f%%), "
                        "energy ratio %.3f (R %.3f G %.3f B %.3f), leak %.2f%%\n",
                        settings.indirectSettings.lights == pnb::reference::IndirectLights::Sun ? "sun" : "all",
                        settings.indirectSettings.samples, m.relativeRmsePercent, m.referenceNoisePercent,
                        m.correctedRmsePercent,
                        m.energyRatio, m.channelRatio[0], m.channelRatio[1], m.channelRatio[2], m.leakPercent);
        if (!settings.quiet) printScorecard(m);
    }
    if (!settings.quiet)
        std::printf("  indirect reference: %zu pixels x %u rays in %.0f ms\n", size_t(valid),
                    settings.indirectSettings.samples, ms);
    return j;
}

// --sky: the sky-light truth at the frame's pixels, its images, and (with the player's sky.exr)
// the comparison. Returns the "sky" object of metrics.json.
Expected<nlohmann::ordered_json> runSky(const Settings& settings, const pnb::Scene& scene, const Frame& frame,
                                        const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::vec3>& shadingNormals, const std::string& in,
                                        const std::string& outDir) {
    using pnb::reference::SkySource;
    using pnb::reference::SkyTracer;
    std::error_code ec;
    std::optional<FloatImage> player;
    if (fs::exists(in + "sky.exr", ec)) {
        auto p = readExr(in + "sky.exr", {"R", "G", "B"}, 3, frame);
        if (!p) return p.error();
        player = std::move(*p);
    }
    auto tracer = SkyTracer::build(scene, frame.cameraPosition);
    if (!tracer) return tracerFailure(settings.scene, tracer.error());
    pnb::reference::SkySettings sky = settings.skySettings;
    if (sky.source == SkySource::Image && !(*tracer)->hasRadianceImage())
        return Failure{kExitInput, settings.scene +
                                       ": the environment (ENVM) has no radiance texture; --sky-source sh "
                                       "traces the radiance of its irradiance SH instead"};
    // The environment's rotation and intensity: the command line's, else what the player
    // recorded in frame.json, else none. Where both exist and differ the comparison would be
    // of two different skies: say so.
    auto pick = [&](const std::optional<double>& option, const std::optional<double>& recorded, double fallback,
                    const char* name, std::string& from) {
        if (option && recorded && *option != *recorded && !settings.quiet)
            std::fprintf(stderr, "Warning: %s %g overrides frame.json's %g: the player drew another sky\n", name,
                         *option, *recorded);
        from = option ? "option" : recorded ? "frame.json" : "default";
        return option ? *option : recorded ? *recorded : fallback;
    };
    std::string rotationFrom, intensityFrom;
    const double degrees = pick(settings.skyRotationDegrees, frame.iblRotationDegrees, 0.0, "--sky-rotation-deg",
                                rotationFrom);
    const double intensity = pick(settings.skyIntensity, frame.iblIntensity, 1.0, "--sky-intensity", intensityFrom);
    sky.rotationRadians = float(degrees * 3.14159265358979323846 / 180.0);
    sky.intensity = float(intensity);

    const size_t pixels = positions.size();
    const std::vector<glm::vec3> normals = irradianceNormals(positions, shadingNormals, frame);
    std::vector<glm::vec3> mean(pixels), error(pixels);
    auto start = std::chrono::steady_clock::now();
    (*tracer)->irradiance(positions, normals, sky, mean, error);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    auto a = writeImage(outDir + "/sky_reference.exr", frame.width, frame.height, 3, OIIO::TypeDesc::FLOAT,
                        mean.data());
    if (!a) return a.error();
    auto b = writeImage(outDir + "/sky_stderr.exr", frame.width, frame.height, 3, OIIO::TypeDesc::FLOAT,
                        error.data());
    if (!b) return b.error();
    uint64_t valid = 0;
    const double referenceMean = meanLuminance(mean, valid);
    const uint64_t rays = sky.visibility ? valid * sky.samples : 0; // occlusion rays
    const auto& st = (*tracer)->stats();
    const char* source = sky.source == SkySource::Sh ? "sh" : "image";
    nlohmann::ordered_json j;
    j["source"] = source;
    j["visibility"] = sky.visibility;
    j["samples"] = sky.samples;
    j["seed"] = sky.seed;
    j["rotation_degrees"] = degrees;
    j["rotation_from"] = rotationFrom;
    j["intensity"] = intensity;
    j["intensity_from"] = intensityFrom;
    j["tracer"] = {{"triangles", st.triangles}, {"instances", st.instances},
                   {"radiance_width", st.radianceWidth}, {"radiance_height", st.radianceHeight},
                   {"build_ms", st.buildMs}, {"trace_ms", ms}, {"rays", rays},
                   {"rays_per_second", ms > 0 ? double(rays) / (ms / 1000.0) : 0.0}};
    j["reference_mean_luminance"] = referenceMean;
    if (player) {
        auto m = pnb::reference::compareIndirect(playerIrradiance(*player, positions), mean, error);
        putComparison(j, m);
        if (!settings.quiet)
            std::printf("  sky (%s, visibility %s, %u samples): relative RMSE %.1f%% (reference noise %.1f%%, "
                        "without it %.1f%%), energy ratio %.3f (R %.3f G %.3f B %.3f), leak %.2f%%\n",
                        source, sky.visibility ? "on" : "off", sky.samples, m.relativeRmsePercent,
                        m.referenceNoisePercent, m.correctedRmsePercent, m.energyRatio, m.channelRatio[0],
                        m.channelRatio[1], m.channelRatio[2], m.leakPercent);
        if (!settings.quiet) printScorecard(m);
    }
    if (!settings.quiet)
        std::printf("  sky reference: %zu pixels x %u rays in %.0f ms (%.2f Mrays/s), mean %.4g lux\n",
                    size_t(valid), sky.samples, ms, ms > 0 ? double(rays) / ms / 1000.0 : 0.0, referenceMean);
    return j;
}

int fail(const Failure& f) {
    std::fprintf(stderr, "Error: %s\n", f.message.c_str());
    return f.exitCode;
}

int run(const Settings& settings) {
    using Clock = std::chrono::steady_clock;
    const std::string dir = settings.frameDir;
    const std::string in = dir + "/" + settings.prefix; // input files: in + "position.exr", ...
    const std::string outDir = settings.outDir.empty() ? dir : settings.outDir;

    // Inputs: all of them are checked before any work is done.
    auto frame = readFrameJson(in + "frame.json");
    if (!frame) return fail(frame.error());
    auto position = readExr(in + "position.exr", {"R", "G", "B"}, 3, *frame);
    if (!position) return fail(position.error());
    std::optional<FloatImage> normal, shadow;
    std::error_code ec;
    if (fs::exists(in + "normal.exr", ec)) {
        auto n = readExr(in + "normal.exr", {"R", "G", "B"}, 3, *frame);
        if (!n) return fail(n.error());
        normal = std::move(*n);
    } else if (!settings.quiet) {
        std::fprintf(stderr, "Warning: %snormal.exr missing: the irradiance weights use normals "
                             "from the positions (no normal mapping)\n", in.c_str());
    }
    if (fs::exists(in + "shadow.exr", ec)) {
        auto s = readExr(in + "shadow.exr", {"R", "G", "B"}, 3, *frame);
        if (!s) return fail(s.error());
        shadow = std::move(*s);
    }
    // The player's HDR image, when dumped: only checked for non-finite pixels (the extremes
    // matrix asks "is the image finite?" beside "is the verdict right?").
    std::optional<FloatImage> hdr;
    if (fs::exists(in + "hdr.exr", ec)) {
        auto h = readExr(in + "hdr.exr", {"R", "G", "B"}, 3, *frame);
        if (!h) return fail(h.error());
        hdr = std::move(*h);
    }

    auto container = pnb::Container::open(settings.scene);
    if (!container) return fail({kExitInput, settings.scene + ": " + container.error().describe()});
    auto scene = pnb::readScene(*container);
    if (!scene) return fail({kExitInput, settings.scene + ": " + scene.error().describe()});

    // The judged light, when it is a point or spot light: placed by its node, relative to the eye
    // (the origin of position.exr and of the tracer).
    std::optional<pnb::reference::LocalLight> local;
    glm::dvec3 localPosition{0.0};
    if (frame->shadowLightIndex) {
        auto placed = pnb::reference::placeLocalLight(*scene, *frame->shadowLightIndex);
        if (!placed)
            return fail({kExitInput, in + "frame.json: \"shadow_light_index\" " +
                                         std::to_string(*frame->shadowLightIndex) + ": " +
                                         placed.error().message + " in " + settings.scene});
        local = std::move(*placed);
        localPosition = local->position - frame->cameraPosition;
        if (local->placementNodes > 1 && !settings.quiet)
            std::fprintf(stderr,
                         "Warning: %s is placed by %u nodes; judged where the first (node %u) "
                         "puts it\n",
                         local->name.c_str(), local->placementNodes, local->node);
    }

    // Trace.
    auto tracer = ShadowTracer::build(*scene, frame->cameraPosition);
    if (!tracer) return fail(tracerFailure(settings.scene, tracer.error()));
    const size_t pixels = size_t(frame->width) * size_t(frame->height);
    std::vector<glm::vec3> positions(pixels), normals(normal ? pixels : 0);
    for (size_t p = 0; p < pixels; ++p) {
        positions[p] = {position->at(p, 0), position->at(p, 1), position->at(p, 2)};
        if (normal) normals[p] = {normal->at(p, 0), normal->at(p, 1), normal->at(p, 2)};
    }
    std::vector<float> visibility(pixels);
    auto traceStart = Clock::now();
    if (local)
        (*tracer)->visibilityToPoint(positions, glm::vec3(localPosition), visibility);
    else
        (*tracer)->visibility(positions, frame->towardLight, visibility); // the eye is the origin
    const double rayMs = std::chrono::duration<double, std::milli>(Clock::now() - traceStart).count();
    uint64_t rays = 0, litPixels = 0, nonfiniteVerdicts = 0;
    for (size_t p = 0; p < pixels; ++p) {
        const float v = visibility[p];
        rays += std::isfinite(v) ? 1 : 0;
        litPixels += v == 1.0f ? 1 : 0;
        const glm::vec3 q = positions[p];
        nonfiniteVerdicts += std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) &&
                             !std::isfinite(v);
    }
    uint64_t nonfiniteImagePixels = 0;
    if (hdr)
        for (size_t p = 0; p < pixels; ++p)
            nonfiniteImagePixels += !(std::isfinite(hdr->at(p, 0)) && std::isfinite(hdr->at(p, 1)) &&
                                      std::isfinite(hdr->at(p, 2)));

    // Where a local light reaches and what it gives there (its binary metric counts those pixels,
    // its weighted one weighs by that irradiance): the player's shading normal where it wrote one,
    // else the normal of the positions themselves, as for the sun.
    std::vector<glm::vec3> geometric;
    if (local || shadow)
        geometric = pnb::reference::normalsFromPositions(positions, frame->width, frame->height);
    pnb::reference::LocalLightWeights reach;
    if (local)
        reach =
            pnb::reference::localLightWeights(*local, localPosition, positions, normals, geometric);

    // Compare.
    std::vector<float> playerShadow, cascade, ratio;
    pnb::reference::ShadowErrorMetrics metrics;
    std::vector<pnb::reference::RatioStats> ratios;
    if (shadow) {
        playerShadow.resize(pixels);
        cascade.resize(pixels);
        ratio.resize(pixels);
        for (size_t p = 0; p < pixels; ++p) {
            playerShadow[p] = shadow->at(p, 0);
            cascade[p] = shadow->at(p, 1);
            ratio[p] = shadow->at(p, 2);
        }
        if (local) {
            metrics = pnb::reference::compareLocalShadow(playerShadow, visibility, reach);
        } else {
            // Irradiance weights: the player's shading normal where it wrote one, else the normal
            // of the positions themselves.
            const std::vector<float> weights =
                pnb::reference::lambertWeights(normals, geometric, frame->towardLight);
            metrics = pnb::reference::compareShadow(playerShadow, visibility, weights);
        }
        ratios = pnb::reference::texelRatioByCascade(cascade, ratio);
    }

    // Outputs.
    fs::create_directories(outDir, ec);
    if (!fs::is_directory(outDir, ec))
        return fail({kExitOutput, outDir + ": cannot create the output directory"});
    auto visExr = writeImage(outDir + "/visibility.exr", frame->width, frame->height, 1,
                             OIIO::TypeDesc::FLOAT, visibility.data());
    if (!visExr) return fail(visExr.error());
    std::vector<uint8_t> rgb(pixels * 3);
    for (size_t p = 0; p < pixels; ++p)
        put(rgb, p, std::isnan(visibility[p]) ? kNoGeometry : visibility[p] > 0.5f ? kLit : kShadow);
    auto visPng = writeImage(outDir + "/visibility.png", frame->width, frame->height, 3,
                             OIIO::TypeDesc::UINT8, rgb.data());
    if (!visPng) return fail(visPng.error());
    if (shadow) {
        for (size_t p = 0; p < pixels; ++p) {
            const float pv = playerShadow[p], rv = visibility[p];
            const bool playerGeometry = std::isfinite(pv) && pv >= 0.0f,
                       referenceGeometry = std::isfinite(rv);
            Rgb8 c = kNoGeometry;
            if (local && !reach.reached[p] && (playerGeometry || referenceGeometry))
                c = kNotReached;
            else if (playerGeometry != referenceGeometry)
                c = kCoverage;
            else if (playerGeometry) {
                const bool playerLit = pv >= pnb::reference::kLitThreshold, trulyLit = rv >= 0.5f;
                c = playerLit == trulyLit ? (trulyLit ? kAgreeLit : kAgreeShadow)
                    : playerLit           ? kFalseLit
                                          : kFalseShadow;
            }
            put(rgb, p, c);
        }
        auto diff = writeImage(outDir + "/shadow_diff.png", frame->width, frame->height, 3,
                               OIIO::TypeDesc::UINT8, rgb.data());
        if (!diff) return fail(diff.error());
    }

    const pnb::reference::TracerStats& ts = (*tracer)->stats();
    nlohmann::ordered_json j;
    j["scene"] = settings.scene;
    j["frame"] = dir;
    j["width"] = frame->width;
    j["height"] = frame->height;
    j["reference"] = {{"pixels_with_geometry", rays},
                      {"lit_percent", rays ? 100.0 * double(litPixels) / double(rays) : 0.0},
                      {"nonfinite_verdicts", nonfiniteVerdicts}}; // at finite positions: a bug
    if (local) {
        const bool spot = local->type == pnb::LightType::Spot;
        nlohmann::ordered_json light = {
            {"index", local->index},
            {"name", local->name},
            {"type", spot ? "spot" : "point"},
            {"node", local->node},
            {"placement_nodes", local->placementNodes},
            {"position", {local->position.x, local->position.y, local->position.z}},
            {"intensity", local->intensity},
            {"range", local->range},
            {"range_from", local->ownRange ? "light" : "cutoff"},
            {"casts_shadows", local->castsShadows}};
        if (spot) {
            light["direction"] = {local->direction.x, local->direction.y, local->direction.z};
            light["cos_outer"] = local->cosOuter;
            light["cos_inner"] = local->cosInner;
        }
        j["light"] = light;
        j["reference"]["reached_pixels"] = reach.reachedCount;
    }
    if (hdr) j["player_image"] = {{"nonfinite_pixels", nonfiniteImagePixels}};
    if (shadow) {
        j["shadow"] = {{"pixels", metrics.pixels},
                       {"misclassified_percent", metrics.misclassifiedPercent},
                       {"false_lit_percent", metrics.falseLitPercent},
                       {"false_shadow_percent", metrics.falseShadowPercent},
                       {"mean_abs_error", metrics.meanAbsError},
                       {"weighted_error_percent", metrics.weightedErrorPercent},
                       {"weighted_false_lit_percent", metrics.weightedFalseLitPercent},
                       {"weighted_false_shadow_percent", metrics.weightedFalseShadowPercent},
                       {"coverage_mismatch_pixels", metrics.coverageMismatch}};
        nlohmann::ordered_json list = nlohmann::ordered_json::array();
        for (const auto& r : ratios)
            list.push_back({{"cascade", r.cascade}, {"pixels", r.pixels}, {"median", r.median},
                            {"p95", r.p95}});
        j["texel_ratio"] = list;
    }
    j["tracer"] = {{"triangles", ts.triangles},
                   {"caster_instances", ts.casterInstances},
                   {"masked_casters_treated_opaque", ts.maskedCastersTreatedOpaque},
                   {"excluded_instances", ts.excludedInstances},
                   {"build_ms", ts.buildMs}};
    j["rays"] = {{"count", rays},
                 {"ms", rayMs},
                 {"rays_per_second", rayMs > 0 ? double(rays) / (rayMs / 1000.0) : 0.0}};
    if (settings.indirect) {
        auto indirect = runIndirect(settings, *scene, *frame, positions, normals, in, outDir);
        if (!indirect) return fail(indirect.error());
        j["indirect"] = *indirect;
    }
    if (settings.sky) {
        auto sky = runSky(settings, *scene, *frame, positions, normals, in, outDir);
        if (!sky) return fail(sky.error());
        j["sky"] = *sky;
    }
    auto json = writeText(outDir + "/metrics.json", j.dump(2) + "\n");
    if (!json) return fail(json.error());

    if (!settings.quiet) {
        std::printf("pnb-reference: %llu triangles (built in %.1f ms), %llu rays in %.1f ms "
                    "(%.2f Mrays/s), %.1f%% lit\n",
                    (unsigned long long)ts.triangles, ts.buildMs, (unsigned long long)rays, rayMs,
                    rayMs > 0 ? double(rays) / rayMs / 1000.0 : 0.0,
                    rays ? 100.0 * double(litPixels) / double(rays) : 0.0);
        if (nonfiniteImagePixels)
            std::printf("  warning: the player's hdr.exr has %llu non-finite pixels\n",
                        (unsigned long long)nonfiniteImagePixels);
        if (local)
            std::printf("  %s (%s) at (%.4g, %.4g, %.4g), range %.4g m (%s): reaches %llu pixels\n",
                        local->name.c_str(), local->type == pnb::LightType::Spot ? "spot" : "point",
                        local->position.x, local->position.y, local->position.z, local->range,
                        local->ownRange ? "its own" : "0.01 lux cut-off",
                        (unsigned long long)reach.reachedCount);
        if (ts.maskedCastersTreatedOpaque)
            std::printf("  note: %u alpha-masked caster instance(s) traced as opaque\n",
                        ts.maskedCastersTreatedOpaque);
        if (shadow)
            std::printf("  player vs reference over %llu pixels: misclassified %.3f%% (false lit "
                        "%.3f%%, false shadow %.3f%%), mean abs error %.4f; irradiance-weighted "
                        "error %.3f%% (false lit %.3f%%, false shadow %.3f%%)\n",
                        (unsigned long long)metrics.pixels, metrics.misclassifiedPercent,
                        metrics.falseLitPercent, metrics.falseShadowPercent, metrics.meanAbsError,
                        metrics.weightedErrorPercent, metrics.weightedFalseLitPercent,
                        metrics.weightedFalseShadowPercent);
        std::printf("  wrote %s/{visibility.exr,visibility.png%s,metrics.json}\n", outDir.c_str(),
                    shadow ? ",shadow_diff.png" : "");
    }
    return kExitOk;
}

} // namespace

int main(int argc, char** argv) {
    Settings settings;
    for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i];
        if (arg == "-h" || arg == "--help") {
            printHelp();
            return kExitOk;
        }
        if (arg.size() > 1 && arg[0] == '-') {
            const Option* match = nullptr;
            for (const Option& o : options())
                if (optionMatches(o, arg)) match = &o;
            if (!match || !match->apply) {
                std::fprintf(stderr, "Error: unknown option %s (see --help)\n", arg.c_str());
                return kExitUsage;
            }
            const char* value = nullptr;
            if (match->arg) {
                if (i + 1 >= argc) {
                    std::fprintf(stderr, "Error: %s needs %s\n", arg.c_str(), match->arg);
                    return kExitUsage;
                }
                value = argv[++i];
            }
            match->apply(settings, value);
            continue;
        }
        if (!settings.scene.empty()) {
            std::fprintf(stderr, "Error: more than one scene given (%s, %s)\n",
                         settings.scene.c_str(), arg.c_str());
            return kExitUsage;
        }
        settings.scene = arg;
    }
    if (!settings.usageError.empty()) {
        std::fprintf(stderr, "Error: %s (see --help)\n", settings.usageError.c_str());
        return kExitUsage;
    }
    if (settings.scene.empty() || settings.frameDir.empty()) {
        std::fprintf(stderr, "Error: need SCENE.pnb and --frame DIR (see --help)\n");
        return kExitUsage;
    }
    return run(settings);
}
