// converter/src/convert_environment.cpp — convertScene's environment stage (convert_internal.h):
// which environment the scene gets (an image, the analytic sky at the scene's sun, the default
// studio, or none) and its bake.

#include <chrono>
#include <filesystem>
#include <utility>

#include "convert_internal.h"

namespace pnb::converter::convert_detail {

namespace {

namespace fs = std::filesystem;

// The node that places light `light` (the first one, as the player takes it), or -1.
int nodeOfLight(const IrScene& scene, size_t light) {
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (scene.nodes[i].light == int(light)) return int(i);
    return -1;
}

// The radiance to bake and what it is: an image file, or the Preetham sky.
struct EnvironmentRadiance {
    RadianceImage radiance;
    std::string name;
    EnvironmentSource source = EnvironmentSource::Image;
    std::optional<PreethamSkyParams> sky;
    float sunIlluminance = 0; // the scene sun's lux, with the sky
};

// The analytic sky at the scene's sun, in the scene's units.
EnvironmentRadiance skyAtTheScenesSun(const EnvironmentSettings& env, const IrScene& scene,
                                      const NodePlacement& placement) {
    EnvironmentRadiance out;
    // The sun: the first directional light that casts shadows, else the first
    // directional (every directional casts shadows, processLights, so the two agree
    // today). Towards the sun is its node's +Z axis: lights shine down -Z.
    int sunLight = -1;
    for (size_t i = 0; i < scene.lights.size() && sunLight < 0; ++i)
        if (scene.lights[i].type == LightType::Directional) sunLight = int(i);
    PreethamSkyParams p;
    p.turbidity = env.skyTurbidity;
    p.groundAlbedo = glm::dvec3(env.skyGroundAlbedo);
    if (sunLight >= 0) {
        const IrLight& l = scene.lights[size_t(sunLight)];
        if (int node = nodeOfLight(scene, size_t(sunLight)); node >= 0) {
            const Mat4d& m = placement.world[size_t(node)];
            glm::dvec3 z(m.m[8], m.m[9], m.m[10]);
            if (glm::length(z) > 0) p.sunDirection = glm::normalize(z);
        }
        out.sunIlluminance = l.intensity;
    }
    // The model is in physical units (a clear sky is ~10^4 nits), a scene's sun in any
    // (the default sun is 3 lux): bake it beside its physical sun, whose light the
    // ground below the horizon reflects too, in the light's colour, then scale the
    // whole sky by (the scene's sun) / (that physical sun). Sky and sun then keep their
    // physical ratio under one exposure (FORMAT.md "ENVM").
    const double physicalSun = lighting::preethamSunIlluminance(p.turbidity, p.sunDirection);
    const glm::dvec3 colour = sunLight >= 0 ? glm::dvec3(scene.lights[size_t(sunLight)].color.x,
                                                         scene.lights[size_t(sunLight)].color.y,
                                                         scene.lights[size_t(sunLight)].color.z)
                                            : glm::dvec3(1.0);
    p.sunIlluminance = colour * physicalSun;
    out.sky = p;
    out.radiance = bakePreethamSky(p, env.skyWidth);
    const float scale = float(double(out.sunIlluminance) / physicalSun);
    for (float& v : out.radiance.rgb)
        v *= scale;
    out.name = "preetham";
    out.source = EnvironmentSource::AnalyticSky;
    return out;
}

// The environment image the settings name, loaded within the texture memory budget.
Result<EnvironmentRadiance, ConvertError> loadEnvironmentImage(const ConvertSettings& s,
                                                               const EnvironmentSettings& env,
                                                               ConvertSummary& sum) {
    auto loaded = loadRadianceImage(env.image, s.texture.maxMemoryBytes);
    if (!loaded) return loaded.error();
    EnvironmentRadiance out;
    out.radiance = std::move(*loaded);
    for (std::string& w : out.radiance.warnings)
        sum.warnings.push_back(std::move(w));
    out.name = fs::path(env.image).filename().string();
    sum.dependencies.push_back(env.image);
    return out;
}

// The environment the settings ask for, baked for this scene.
Result<BakedEnvironment, ConvertError>
bakeOwnEnvironment(const ConvertSettings& s, const EnvironmentSettings& env, const IrScene& scene,
                   const NodePlacement& placement, ConvertSummary& sum) {
    const auto environmentStart = std::chrono::steady_clock::now();
    EnvironmentRadiance source;
    if (!env.image.empty()) {
        auto loaded = loadEnvironmentImage(s, env, sum);
        if (!loaded) return loaded.error();
        source = std::move(*loaded);
    } else {
        source = skyAtTheScenesSun(env, scene, placement);
    }
    auto baked = bakeEnvironment(source.radiance, env, source.source, source.name, s.jobs,
                                 source.sky ? &*source.sky : nullptr);
    if (!baked) return baked.error();
    // The light's lux, not a channel.
    if (source.sky) baked->envm.sunIlluminance = source.sunIlluminance;
    // The summary's time is the whole stage: loading or baking the sky image too.
    baked->summary.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - environmentStart).count();
    return std::move(*baked);
}

} // namespace

Result<SceneEnvironment, ConvertError>
bakeSceneEnvironment(const ConvertSettings& s, const EnvironmentSettings& env, const IrScene& scene,
                     const SceneGraph& graph, StageClock& clock, const Progress& report,
                     ConvertSummary& sum) {
    SceneEnvironment out;
    if (!env.any() && s.defaultEnvironment && !graph.sourceHasLights) {
        // The neutral studio (environment.h "default-studio"), baked once per process.
        clock.start("environment");
        out.shared = &defaultStudioEnvironment(s.jobs);
        sum.defaultEnvironment = true;
        clock.stop();
    }
    if (env.any()) {
        clock.start("environment");
        report("environment", 0, 1); // the bake can take a while (--specular-size 2048)
        auto baked = bakeOwnEnvironment(s, env, scene, graph.placement, sum);
        if (!baked) return baked.error();
        out.own = std::move(*baked);
        report("environment", 1, 1);
        clock.stop();
    }
    return out;
}

} // namespace pnb::converter::convert_detail
