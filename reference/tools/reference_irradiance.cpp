// pnb-reference's irradiance truths (reference_irradiance.h).
#include "reference_irradiance.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include <glm/geometric.hpp>

#include "pnb_reference/indirect_metrics.h"
#include "pnb_reference/indirect_tracer.h"
#include "pnb_reference/shadow_metrics.h"
#include "pnb_reference/sky_tracer.h"

namespace pnb::reference_tool {

namespace fs = std::filesystem;
using pnb::reference::TracerErrorKind;

Failure tracerFailure(const std::string& scenePath, const pnb::reference::TracerError& e) {
    int code = e.kind == TracerErrorKind::Input         ? kExitInput
               : e.kind == TracerErrorKind::Unsupported ? kExitUnsupported
                                                        : kExitEmbree;
    return Failure{code, scenePath + ": " + e.message};
}

namespace {

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

} // namespace

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
    auto tracer = IndirectTracer::build(scene, frame.cameraPosition, frame.pose);
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
    j["bounces"] = pnb::reference::indirectBouncesName(settings.indirectSettings.bounces);
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
            std::printf("  indirect (%s lights, %s bounces, %u samples): relative RMSE %.1f%% (reference noise %.1f%%, "
                        "without it %.1f%%), "
                        "energy ratio %.3f (R %.3f G %.3f B %.3f), leak %.2f%%\n",
                        settings.indirectSettings.lights == pnb::reference::IndirectLights::Sun ? "sun" : "all",
                        pnb::reference::indirectBouncesName(settings.indirectSettings.bounces).c_str(),
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
    auto tracer = SkyTracer::build(scene, frame.cameraPosition, frame.pose);
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

} // namespace pnb::reference_tool
