// pnb-reference --whole-frame (reference_whole_frame.h).
#include "reference_whole_frame.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "pnb/reader.h"
#include "pnb_lighting/tonemap.h"
#include "reference_io.h"
#include "reference_irradiance.h" // tracerFailure
#include "reference_pose.h"

namespace pnb::reference_tool {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The camera frame.json records (bench_report.cpp tracerFrameJson).
Expected<pnb::reference::FrameCamera> frameCamera(const Frame& frame, const std::string& path) {
    auto missing = [&](const std::string& key) {
        return Failure{kExitInput, path + ": --whole-frame needs \"" + key +
                                       "\" (pnb-play writes it since issue 40; dump the frame again)"};
    };
    pnb::reference::FrameCamera c;
    c.position = frame.cameraPosition;
    c.width = frame.width;
    c.height = frame.height;
    if (!frame.worldFromView) return missing("camera_world_from_view");
    if (!frame.projection) return missing("projection");
    c.worldFromView = *frame.worldFromView;
    c.orthographic = *frame.projection == "orthographic";
    if (c.orthographic) {
        if (!frame.ymag || !(*frame.ymag > 0)) return missing("ymag");
        c.ymag = *frame.ymag;
        c.xmag = frame.xmag && *frame.xmag > 0 ? *frame.xmag : c.ymag * double(c.width) / double(c.height);
    } else {
        if (!frame.yfov || !(*frame.yfov > 0 && *frame.yfov < kPi)) return missing("yfov");
        c.yfovRadians = *frame.yfov;
        c.aspect = frame.aspect && *frame.aspect > 0 ? *frame.aspect : double(c.width) / double(c.height);
    }
    return c;
}

Expected<bool> writeImages(const std::string& outDir, const pnb::reference::FrameImage& image, float exposure) {
    const size_t pixels = image.mean.size();
    std::vector<float> hdr(pixels * 3), stderrRgb(pixels * 3);
    std::vector<unsigned char> png(pixels * 3);
    for (size_t p = 0; p < pixels; ++p) {
        const glm::vec3 shown = pnb::lighting::displayColor(image.mean[p], exposure);
        for (int c = 0; c < 3; ++c) {
            hdr[p * 3 + size_t(c)] = image.mean[p][c];
            stderrRgb[p * 3 + size_t(c)] = image.standardError[p][c];
            png[p * 3 + size_t(c)] = (unsigned char)(std::lround(shown[c] * 255.0f));
        }
    }
    if (auto w = writeImage(outDir + "/whole_frame.exr", image.width, image.height, 3, OIIO::TypeDesc::FLOAT, hdr.data()); !w)
        return w;
    if (auto w = writeImage(outDir + "/whole_frame_stderr.exr", image.width, image.height, 3, OIIO::TypeDesc::FLOAT,
                            stderrRgb.data());
        !w)
        return w;
    return writeImage(outDir + "/whole_frame.png", image.width, image.height, 3, OIIO::TypeDesc::UINT8, png.data());
}

nlohmann::ordered_json wholeFrameJson(const pnb::reference::FrameImage& image,
                                      const pnb::reference::FrameTraceSettings& s, float exposure) {
    nlohmann::ordered_json j;
    j["width"] = image.width;
    j["height"] = image.height;
    j["samples"] = image.samples;
    j["passes"] = image.passes;
    j["bounces"] = s.maxBounces;
    j["relative_noise"] = image.relativeNoise;
    j["noise_target"] = s.noiseTarget;
    j["converged"] = s.noiseTarget > 0 && image.relativeNoise <= s.noiseTarget;
    j["max_samples"] = s.maxSamples;
    j["time_limit_s"] = s.timeLimitSeconds;
    j["seed"] = s.seed;
    j["ms"] = image.ms;
    j["build_ms"] = image.stats.buildMs;
    j["rays"] = image.rays;
    j["rays_per_second"] = image.ms > 0 ? double(image.rays) / (image.ms / 1000.0) : 0.0;
    j["non_finite_samples"] = image.stats.nonFiniteSamples;
    j["exposure"] = exposure;
    j["triangles"] = image.stats.triangles;
    j["instances"] = image.stats.instances;
    j["lights"] = image.stats.lights;
    j["environment"] = image.stats.environment;
    j["textures"] = image.stats.textures;
    j["textures_factor_only"] = image.stats.texturesFactorOnly;
    j["meshes_without_normals"] = image.stats.meshesWithoutNormals;
    return j;
}

} // namespace

int runWholeFrame(const Settings& settings) {
    const std::string in = settings.frameDir + "/" + settings.prefix;
    const std::string outDir = settings.outDir.empty() ? settings.frameDir : settings.outDir;
    auto frame = readFrameJson(in + "frame.json");
    if (!frame) return fail(frame.error());
    auto camera = frameCamera(*frame, in + "frame.json");
    if (!camera) return fail(camera.error());
    auto container = pnb::Container::open(settings.scene);
    if (!container) return fail({kExitInput, settings.scene + ": " + container.error().describe()});
    auto scene = pnb::readScene(*container);
    if (!scene) return fail({kExitInput, settings.scene + ": " + scene.error().describe()});

    pnb::reference::FrameTraceSettings s = settings.frameSettings;
    s.iblRotationRadians = settings.skyRotationDegrees.value_or(frame->iblRotationDegrees.value_or(0.0)) * kPi / 180.0;
    s.iblIntensity = settings.skyIntensity.value_or(frame->iblIntensity.value_or(1.0));
    auto pose = resolvePose(settings, *frame, *scene, in + "frame.json");
    if (!pose) return fail(pose.error());
    auto tracer = pnb::reference::FrameTracer::build(*scene, frame->cameraPosition, *pose);
    if (!tracer) return fail(tracerFailure(settings.scene, tracer.error()));
    const pnb::reference::FrameImage image = (*tracer)->render(*camera, s);
    const float exposure = float(frame->exposure.value_or(1.0));
    std::error_code ec;
    std::filesystem::create_directories(outDir, ec); // a failure shows as the first write's
    if (auto images = writeImages(outDir, image, exposure); !images) return fail(images.error());

    // metrics.json keeps what an earlier run of this frame wrote (the shadow verdict, ...).
    const std::string metricsPath = outDir + "/metrics.json";
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    if (std::ifstream old(metricsPath, std::ios::binary); old) {
        auto parsed = nlohmann::ordered_json::parse(old, nullptr, /*allow_exceptions=*/false);
        if (!parsed.is_discarded() && parsed.is_object()) j = std::move(parsed);
    }
    j["whole_frame"] = wholeFrameJson(image, s, exposure);
    j["whole_frame"]["pose"] = poseJson(*pose, *scene);
    if (auto json = writeText(metricsPath, j.dump(2) + "\n"); !json) return fail(json.error());
    if (!settings.quiet)
        std::printf("whole frame: %dx%d, %u samples/pixel in %u passes, %u bounces, relative noise %.2e "
                    "(target %.2e), %.1f s, %.2f Mrays/s%s\n  wrote %s/{whole_frame.exr,whole_frame_stderr.exr,"
                    "whole_frame.png,metrics.json}\n",
                    image.width, image.height, image.samples, image.passes, s.maxBounces, image.relativeNoise,
                    s.noiseTarget, image.ms / 1000.0, image.ms > 0 ? double(image.rays) / image.ms / 1000.0 : 0.0,
                    image.stats.nonFiniteSamples ? (", " + std::to_string(image.stats.nonFiniteSamples) +
                                                    " non-finite samples (black)").c_str()
                                                 : "",
                    outDir.c_str());
    return kExitOk;
}

} // namespace pnb::reference_tool
