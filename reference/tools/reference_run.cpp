// pnb-reference's run (reference_run.h), as stages: read the dumped frame, place the judged
// light, trace its (colour) visibility, compare it with the player's shadow factor and, when
// dumped, its colour visibility (reference_color.h), write the images and metrics.json (with
// the irradiance truths asked for), print the summary.
#include "reference_run.h"
#include "reference_whole_frame.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_reference/local_light.h"
#include "pnb_reference/shadow_metrics.h"
#include "pnb_reference/shadow_tracer.h"
#include "diff_palette.h"
#include "reference_color.h"
#include "reference_io.h"
#include "reference_irradiance.h"
#include "reference_pose.h"

namespace pnb::reference_tool {

namespace {

namespace fs = std::filesystem;
using pnb::reference::ShadowTracer;

// The dumped frame: frame.json and its buffers (normal, shadow, shadow_color and hdr are
// optional).
struct Inputs {
    Frame frame;
    FloatImage position;
    std::optional<FloatImage> normal, shadow, shadowColor, hdr;
};

// The judged light when it is a point or spot light, placed by its node; its position is
// relative to the eye (the origin of position.exr and of the tracer). Empty: the sun.
struct JudgedLight {
    std::optional<pnb::reference::LocalLight> local;
    glm::dvec3 position{0.0};
};

// What the ray tracer found at every pixel.
struct Truth {
    std::vector<glm::vec3> positions, normals; // normals: empty without normal.exr
    std::vector<glm::vec3> color;              // colour visibility: through glass (issue 43)
    std::vector<float> visibility;             // its mean over the channels (binary without glass)
    double rayMs = 0;
    uint64_t rays = 0, litPixels = 0, nonfiniteVerdicts = 0, nonfiniteImagePixels = 0;
};

// The player's shadow factor against the truth (metrics only with shadow.exr).
struct Comparison {
    pnb::reference::LocalLightWeights reach; // a local light's: where it reaches and what it gives
    std::vector<float> sunWeights;           // the sun's: max(N.L, 0) (with shadow or shadow_color)
    std::vector<float> playerShadow;
    pnb::reference::ShadowErrorMetrics metrics;
    std::vector<pnb::reference::RatioStats> ratios;
};

// All inputs are read and checked before any work is done.
Expected<Inputs> readInputs(const Settings& settings, const std::string& in) {
    auto frame = readFrameJson(in + "frame.json");
    if (!frame) return frame.error();
    auto position = readExr(in + "position.exr", {"R", "G", "B"}, 3, *frame);
    if (!position) return position.error();
    Inputs inputs{*frame, std::move(*position), {}, {}, {}, {}};
    std::error_code ec;
    if (fs::exists(in + "normal.exr", ec)) {
        auto n = readExr(in + "normal.exr", {"R", "G", "B"}, 3, *frame);
        if (!n) return n.error();
        inputs.normal = std::move(*n);
    } else if (!settings.quiet) {
        std::fprintf(stderr, "Warning: %snormal.exr missing: the irradiance weights use normals "
                             "from the positions (no normal mapping)\n", in.c_str());
    }
    if (fs::exists(in + "shadow.exr", ec)) {
        auto s = readExr(in + "shadow.exr", {"R", "G", "B"}, 3, *frame);
        if (!s) return s.error();
        inputs.shadow = std::move(*s);
    }
    // The player's colour visibility (light through glass), when dumped.
    if (fs::exists(in + "shadow_color.exr", ec)) {
        auto s = readExr(in + "shadow_color.exr", {"R", "G", "B"}, 3, *frame);
        if (!s) return s.error();
        inputs.shadowColor = std::move(*s);
    }
    // The player's HDR image, when dumped: only checked for non-finite pixels (the extremes
    // matrix asks "is the image finite?" beside "is the verdict right?").
    if (fs::exists(in + "hdr.exr", ec)) {
        auto h = readExr(in + "hdr.exr", {"R", "G", "B"}, 3, *frame);
        if (!h) return h.error();
        inputs.hdr = std::move(*h);
    }
    return inputs;
}

Expected<JudgedLight> placeJudgedLight(const Settings& settings, const pnb::Scene& scene, const Frame& frame,
                                       const std::string& in) {
    JudgedLight light;
    if (!frame.shadowLightIndex) return light;
    auto placed = pnb::reference::placeLocalLight(scene, *frame.shadowLightIndex, frame.pose);
    if (!placed)
        return Failure{kExitInput, in + "frame.json: \"shadow_light_index\" " +
                                       std::to_string(*frame.shadowLightIndex) + ": " + placed.error().message +
                                       " in " + settings.scene};
    light.local = std::move(*placed);
    light.position = light.local->position - frame.cameraPosition;
    if (light.local->placementNodes > 1 && !settings.quiet)
        std::fprintf(stderr,
                     "Warning: %s is placed by %u nodes; judged where the first (node %u) "
                     "puts it\n",
                     light.local->name.c_str(), light.local->placementNodes, light.local->node);
    return light;
}

Truth traceVisibility(ShadowTracer& tracer, const Inputs& inputs, const JudgedLight& light) {
    const Frame& frame = inputs.frame;
    const size_t pixels = size_t(frame.width) * size_t(frame.height);
    Truth t;
    t.positions.resize(pixels);
    t.normals.resize(inputs.normal ? pixels : 0);
    for (size_t p = 0; p < pixels; ++p) {
        t.positions[p] = {inputs.position.at(p, 0), inputs.position.at(p, 1), inputs.position.at(p, 2)};
        if (inputs.normal) t.normals[p] = {inputs.normal->at(p, 0), inputs.normal->at(p, 1), inputs.normal->at(p, 2)};
    }
    t.color.resize(pixels);
    t.visibility.resize(pixels);
    auto traceStart = std::chrono::steady_clock::now();
    if (light.local)
        tracer.colorVisibilityToPoint(t.positions, glm::vec3(light.position), t.color);
    else
        tracer.colorVisibility(t.positions, frame.towardLight, t.color); // the eye is the origin
    // The scalar truth the player's shadow dump is judged against: the opaque visibility times
    // the mean transmittance (the contract of issue 43), exactly 0 or 1 without glass.
    for (size_t p = 0; p < pixels; ++p) t.visibility[p] = (t.color[p].x + t.color[p].y + t.color[p].z) / 3.0f;
    t.rayMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - traceStart).count();
    for (size_t p = 0; p < pixels; ++p) {
        const float v = t.visibility[p];
        t.rays += std::isfinite(v) ? 1 : 0;
        t.litPixels += v == 1.0f ? 1 : 0;
        const glm::vec3 q = t.positions[p];
        t.nonfiniteVerdicts += std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && !std::isfinite(v);
    }
    if (inputs.hdr)
        for (size_t p = 0; p < pixels; ++p)
            t.nonfiniteImagePixels += !(std::isfinite(inputs.hdr->at(p, 0)) && std::isfinite(inputs.hdr->at(p, 1)) &&
                                        std::isfinite(inputs.hdr->at(p, 2)));
    return t;
}

Comparison compareWithPlayer(const Inputs& inputs, const Truth& truth, const JudgedLight& light) {
    const Frame& frame = inputs.frame;
    const size_t pixels = truth.positions.size();
    // Where a local light reaches and what it gives there (its binary metric counts those pixels,
    // its weighted one weighs by that irradiance): the player's shading normal where it wrote one,
    // else the normal of the positions themselves, as for the sun.
    std::vector<glm::vec3> geometric;
    if (light.local || inputs.shadow || inputs.shadowColor)
        geometric = pnb::reference::normalsFromPositions(truth.positions, frame.width, frame.height);
    Comparison c;
    if (light.local)
        c.reach = pnb::reference::localLightWeights(*light.local, light.position, truth.positions, truth.normals,
                                                    geometric);
    else if (inputs.shadow || inputs.shadowColor)
        // Irradiance weights: the player's shading normal where it wrote one, else the normal
        // of the positions themselves.
        c.sunWeights = pnb::reference::lambertWeights(truth.normals, geometric, frame.towardLight);
    if (!inputs.shadow) return c;
    std::vector<float> cascade(pixels), ratio(pixels);
    c.playerShadow.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) {
        c.playerShadow[p] = inputs.shadow->at(p, 0);
        cascade[p] = inputs.shadow->at(p, 1);
        ratio[p] = inputs.shadow->at(p, 2);
    }
    if (light.local) {
        c.metrics = pnb::reference::compareLocalShadow(c.playerShadow, truth.visibility, c.reach);
    } else {
        c.metrics = pnb::reference::compareShadow(c.playerShadow, truth.visibility, c.sunWeights);
    }
    c.ratios = pnb::reference::texelRatioByCascade(cascade, ratio);
    return c;
}

// visibility.exr, visibility.png and (with shadow.exr) shadow_diff.png.
Expected<bool> writeShadowImages(const std::string& outDir, const Inputs& inputs, const Truth& truth,
                                 const Comparison& c, const JudgedLight& light) {
    const Frame& frame = inputs.frame;
    const size_t pixels = truth.visibility.size();
    std::error_code ec;
    fs::create_directories(outDir, ec);
    if (!fs::is_directory(outDir, ec)) return Failure{kExitOutput, outDir + ": cannot create the output directory"};
    auto visExr = writeImage(outDir + "/visibility.exr", frame.width, frame.height, 1, OIIO::TypeDesc::FLOAT,
                             truth.visibility.data());
    if (!visExr) return visExr.error();
    std::vector<uint8_t> rgb(pixels * 3);
    for (size_t p = 0; p < pixels; ++p)
        put(rgb, p, std::isnan(truth.visibility[p]) ? kNoGeometry : truth.visibility[p] > 0.5f ? kLit : kShadow);
    auto visPng = writeImage(outDir + "/visibility.png", frame.width, frame.height, 3, OIIO::TypeDesc::UINT8,
                             rgb.data());
    if (!visPng) return visPng.error();
    if (!inputs.shadow) return true;
    for (size_t p = 0; p < pixels; ++p) {
        const float pv = c.playerShadow[p], rv = truth.visibility[p];
        const bool playerGeometry = std::isfinite(pv) && pv >= 0.0f, referenceGeometry = std::isfinite(rv);
        Rgb8 colour = kNoGeometry;
        if (light.local && !c.reach.reached[p] && (playerGeometry || referenceGeometry))
            colour = kNotReached;
        else if (playerGeometry != referenceGeometry)
            colour = kCoverage;
        else if (playerGeometry) {
            const bool playerLit = pv >= pnb::reference::kLitThreshold, trulyLit = rv >= 0.5f;
            colour = playerLit == trulyLit ? (trulyLit ? kAgreeLit : kAgreeShadow)
                     : playerLit           ? kFalseLit
                                           : kFalseShadow;
        }
        put(rgb, p, colour);
    }
    return writeImage(outDir + "/shadow_diff.png", frame.width, frame.height, 3, OIIO::TypeDesc::UINT8, rgb.data());
}

nlohmann::ordered_json lightJson(const pnb::reference::LocalLight& local) {
    const bool spot = local.type == pnb::LightType::Spot;
    nlohmann::ordered_json light = {{"index", local.index},
                                    {"name", local.name},
                                    {"type", spot ? "spot" : "point"},
                                    {"node", local.node},
                                    {"placement_nodes", local.placementNodes},
                                    {"position", {local.position.x, local.position.y, local.position.z}},
                                    {"intensity", local.intensity},
                                    {"range", local.range},
                                    {"range_from", local.ownRange ? "light" : "cutoff"},
                                    {"casts_shadows", local.castsShadows}};
    if (spot) {
        light["direction"] = {local.direction.x, local.direction.y, local.direction.z};
        light["cos_outer"] = local.cosOuter;
        light["cos_inner"] = local.cosInner;
    }
    return light;
}

// metrics.json, before the irradiance truths add their objects.
nlohmann::ordered_json metricsJson(const Settings& settings, const Inputs& inputs, const Truth& truth,
                                   const Comparison& c, const JudgedLight& light,
                                   const pnb::reference::TracerStats& ts) {
    nlohmann::ordered_json j;
    j["scene"] = settings.scene;
    j["frame"] = settings.frameDir;
    j["width"] = inputs.frame.width;
    j["height"] = inputs.frame.height;
    j["reference"] = {{"pixels_with_geometry", truth.rays},
                      {"lit_percent", truth.rays ? 100.0 * double(truth.litPixels) / double(truth.rays) : 0.0},
                      {"nonfinite_verdicts", truth.nonfiniteVerdicts}}; // at finite positions: a bug
    if (light.local) {
        j["light"] = lightJson(*light.local);
        j["reference"]["reached_pixels"] = c.reach.reachedCount;
    }
    if (inputs.hdr) j["player_image"] = {{"nonfinite_pixels", truth.nonfiniteImagePixels}};
    if (inputs.shadow) {
        const pnb::reference::ShadowErrorMetrics& m = c.metrics;
        j["shadow"] = {{"pixels", m.pixels},
                       {"misclassified_percent", m.misclassifiedPercent},
                       {"false_lit_percent", m.falseLitPercent},
                       {"false_shadow_percent", m.falseShadowPercent},
                       {"mean_abs_error", m.meanAbsError},
                       {"weighted_error_percent", m.weightedErrorPercent},
                       {"weighted_false_lit_percent", m.weightedFalseLitPercent},
                       {"weighted_false_shadow_percent", m.weightedFalseShadowPercent},
                       {"coverage_mismatch_pixels", m.coverageMismatch}};
        nlohmann::ordered_json list = nlohmann::ordered_json::array();
        for (const auto& r : c.ratios)
            list.push_back({{"cascade", r.cascade}, {"pixels", r.pixels}, {"median", r.median}, {"p95", r.p95}});
        j["texel_ratio"] = list;
    }
    j["tracer"] = {{"triangles", ts.triangles},
                   {"caster_instances", ts.casterInstances},
                   {"masked_casters_treated_opaque", ts.maskedCastersTreatedOpaque},
                   {"translucent_casters", ts.translucentCasters},
                   {"excluded_instances", ts.excludedInstances},
                   {"build_ms", ts.buildMs}};
    j["rays"] = {{"count", truth.rays},
                 {"ms", truth.rayMs},
                 {"rays_per_second", truth.rayMs > 0 ? double(truth.rays) / (truth.rayMs / 1000.0) : 0.0}};
    return j;
}

void printSummary(const std::string& outDir, const Inputs& inputs, const Truth& truth, const Comparison& c,
                  const JudgedLight& light, const pnb::reference::TracerStats& ts,
                  const std::optional<pnb::reference::ShadowColorMetrics>& color) {
    std::printf("pnb-reference: %llu triangles (built in %.1f ms), %llu rays in %.1f ms "
                "(%.2f Mrays/s), %.1f%% lit\n",
                (unsigned long long)ts.triangles, ts.buildMs, (unsigned long long)truth.rays, truth.rayMs,
                truth.rayMs > 0 ? double(truth.rays) / truth.rayMs / 1000.0 : 0.0,
                truth.rays ? 100.0 * double(truth.litPixels) / double(truth.rays) : 0.0);
    if (truth.nonfiniteImagePixels)
        std::printf("  warning: the player's hdr.exr has %llu non-finite pixels\n",
                    (unsigned long long)truth.nonfiniteImagePixels);
    if (const auto& local = light.local)
        std::printf("  %s (%s) at (%.4g, %.4g, %.4g), range %.4g m (%s): reaches %llu pixels\n",
                    local->name.c_str(), local->type == pnb::LightType::Spot ? "spot" : "point",
                    local->position.x, local->position.y, local->position.z, local->range,
                    local->ownRange ? "its own" : "0.01 lux cut-off", (unsigned long long)c.reach.reachedCount);
    if (ts.maskedCastersTreatedOpaque)
        std::printf("  note: %u alpha-masked caster instance(s) traced as opaque\n", ts.maskedCastersTreatedOpaque);
    if (ts.translucentCasters)
        std::printf("  note: %u blended caster instance(s) traced as translucent\n", ts.translucentCasters);
    if (inputs.shadow) {
        const pnb::reference::ShadowErrorMetrics& m = c.metrics;
        std::printf("  player vs reference over %llu pixels: misclassified %.3f%% (false lit "
                    "%.3f%%, false shadow %.3f%%), mean abs error %.4f; irradiance-weighted "
                    "error %.3f%% (false lit %.3f%%, false shadow %.3f%%)\n",
                    (unsigned long long)m.pixels, m.misclassifiedPercent, m.falseLitPercent, m.falseShadowPercent,
                    m.meanAbsError, m.weightedErrorPercent, m.weightedFalseLitPercent, m.weightedFalseShadowPercent);
    }
    if (color) printShadowColorSummary(*color);
    std::printf("  wrote %s/{visibility.exr,visibility.png%s%s,metrics.json}\n", outDir.c_str(),
                inputs.shadow ? ",shadow_diff.png" : "",
                inputs.shadowColor ? ",shadow_color_reference.exr,shadow_color_diff.png" : "");
}

} // namespace

int run(const Settings& settings) {
    if (settings.wholeFrame) return runWholeFrame(settings); // needs frame.json only
    const std::string& dir = settings.frameDir;
    const std::string in = dir + "/" + settings.prefix; // input files: in + "position.exr", ...
    const std::string outDir = settings.outDir.empty() ? dir : settings.outDir;

    auto inputs = readInputs(settings, in);
    if (!inputs) return fail(inputs.error());
    auto container = pnb::Container::open(settings.scene);
    if (!container) return fail({kExitInput, settings.scene + ": " + container.error().describe()});
    auto scene = pnb::readScene(*container);
    if (!scene) return fail({kExitInput, settings.scene + ": " + scene.error().describe()});
    auto pose = resolvePose(settings, inputs->frame, *scene, in + "frame.json");
    if (!pose) return fail(pose.error());
    inputs->frame.pose = *pose;
    auto light = placeJudgedLight(settings, *scene, inputs->frame, in);
    if (!light) return fail(light.error());

    auto tracer = ShadowTracer::build(*scene, inputs->frame.cameraPosition, inputs->frame.pose);
    if (!tracer) return fail(tracerFailure(settings.scene, tracer.error()));
    const Truth truth = traceVisibility(**tracer, *inputs, *light);
    const Comparison comparison = compareWithPlayer(*inputs, truth, *light);

    if (auto images = writeShadowImages(outDir, *inputs, truth, comparison, *light); !images)
        return fail(images.error());
    nlohmann::ordered_json j = metricsJson(settings, *inputs, truth, comparison, *light, (*tracer)->stats());
    j["pose"] = poseJson(inputs->frame.pose, *scene);
    std::optional<pnb::reference::ShadowColorMetrics> color;
    if (inputs->shadowColor) {
        auto judged = judgeShadowColor(outDir, inputs->frame, *inputs->shadowColor, truth.color,
                                       light->local ? &comparison.reach : nullptr, comparison.sunWeights);
        if (!judged) return fail(judged.error());
        color = *judged;
        j["shadow_color"] = shadowColorJson(*color);
    }
    if (settings.indirect) {
        auto indirect = runIndirect(settings, *scene, inputs->frame, truth.positions, truth.normals, in, outDir);
        if (!indirect) return fail(indirect.error());
        j["indirect"] = *indirect;
    }
    if (settings.sky) {
        auto sky = runSky(settings, *scene, inputs->frame, truth.positions, truth.normals, in, outDir);
        if (!sky) return fail(sky.error());
        j["sky"] = *sky;
    }
    if (auto json = writeText(outDir + "/metrics.json", j.dump(2) + "\n"); !json) return fail(json.error());
    if (!settings.quiet) printSummary(outDir, *inputs, truth, comparison, *light, (*tracer)->stats(), color);
    return kExitOk;
}

} // namespace pnb::reference_tool
