// Point and spot lights for the shadow truth (see local_light.h).
#include "pnb_reference/local_light.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "mesh_decode.h"
#include "posed_scene.h"
#include "pnb/light_range.h"
#include "pnb/node_transform.h"
#include "pnb_lighting/scene_lights.h"

namespace pnb::reference {

TracerResult<LocalLight> placeLocalLight(const Scene& scene, uint32_t index, const FramePose& at) {
    auto inputError = [](std::string message) {
        return TracerError{TracerErrorKind::Input, std::move(message)};
    };
    const std::vector<Light>& lights = scene.lights.lights;
    if (index >= lights.size())
        return inputError("light " + std::to_string(index) + " does not exist: the scene has " +
                          std::to_string(lights.size()) + " light(s) (LGHT)");
    const Light& l = lights[index];
    LocalLight out;
    out.index = index;
    out.name = detail::lightName(scene, index);
    out.type = l.type;
    if (l.type != LightType::Point && l.type != LightType::Spot)
        return inputError(out.name + " is directional, not a point or spot light (a sun is judged "
                                     "by its direction, without a light index)");

    const std::vector<Node>& nodes = scene.nodes.nodes;
    // The node placement of the instant traced (posed_scene.h; no vertex is deformed for this).
    auto posed = detail::PosedScene::make(scene, at);
    if (!posed) return posed.error();
    const std::vector<Matrix4d>& world = posed->world();
    for (uint32_t i = 0; i < nodes.size(); ++i) {
        if (nodes[i].light != index) continue;
        if (out.placementNodes++ > 0) continue; // the first node places it
        const glm::dmat4 m = glm::make_mat4(world[i].data());
        out.node = i;
        out.position = glm::dvec3(m[3]);
        // A degenerate (zero-scale) node has no direction; the spot then reaches nothing.
        out.direction = lighting::lightTravel(m);
    }
    if (out.placementNodes == 0)
        return inputError(out.name + " is placed by no node (no NODE references it): it has no "
                                     "position");
    out.intensity = l.intensity;
    out.castsShadows = l.castsShadows;
    out.range = effectiveLightRange(l);
    out.ownRange = l.range > 0 && std::isfinite(l.range);
    if (l.type == LightType::Spot) {
        out.cosOuter = std::cos(l.outerConeRadians);
        out.cosInner = std::cos(l.innerConeRadians);
    } else {
        out.cosOuter = -1.0f;
        out.cosInner = 1.0f;
    }
    return out;
}

// shaders/include/lights.glsl rangeAttenuation: the same formula and constants.
double rangeAttenuation(double distanceSquared, double range) {
    const double inverseSquare = 1.0 / std::max(distanceSquared, 1e-4);
    if (range <= 0.0) return inverseSquare;
    const double r = distanceSquared / (range * range);
    const double window = std::clamp(1.0 - r * r, 0.0, 1.0);
    return window * window * inverseSquare;
}

// shaders/include/lights.glsl's spot term (t = clamp((cd - cone.x) * cone.y, 0, 1),
// cone.y = 1 / max(cos(inner) - cos(outer), 1e-4) as renderer.cpp fills it), squared.
double spotConeFactor(double cosAngle, double cosOuter, double cosInner) {
    const double t =
        std::clamp((cosAngle - cosOuter) / std::max(cosInner - cosOuter, 1e-4), 0.0, 1.0);
    return t * t;
}

namespace {

// What localLightIrradiance and localLightReaches share: d^2, n.l and the cosine from the spot's
// axis; valid = false when the point is at the light or a value is not finite.
struct Geometry {
    double d2 = 0, nDotL = 0, cosAxis = 1;
    bool valid = false;
};

Geometry geometry(const LocalLight& light, glm::dvec3 toLight, glm::dvec3 normal) {
    Geometry g;
    g.d2 = glm::dot(toLight, toLight);
    if (!(g.d2 > 0) || !std::isfinite(g.d2)) return g; // at the light, or not a point
    const glm::dvec3 l = toLight / std::sqrt(g.d2);
    g.nDotL = glm::dot(normal, l);
    g.cosAxis = glm::dot(light.direction, -l);
    g.valid = std::isfinite(g.nDotL);
    return g;
}

} // namespace

double localLightIrradiance(const LocalLight& light, glm::dvec3 toLight, glm::dvec3 normal) {
    const Geometry g = geometry(light, toLight, normal);
    if (!g.valid) return 0.0;
    double e =
        double(light.intensity) * std::max(g.nDotL, 0.0) * rangeAttenuation(g.d2, light.range);
    if (light.type == LightType::Spot)
        e *= spotConeFactor(g.cosAxis, light.cosOuter, light.cosInner);
    return e;
}

bool localLightReaches(const LocalLight& light, glm::dvec3 toLight, glm::dvec3 normal) {
    const Geometry g = geometry(light, toLight, normal);
    const double range = light.range;
    return g.valid && g.d2 < range * range && g.nDotL > 0 &&
           (light.type != LightType::Spot || g.cosAxis > double(light.cosOuter));
}

LocalLightWeights localLightWeights(const LocalLight& light, glm::dvec3 lightPosition,
                                    std::span<const glm::vec3> positions,
                                    std::span<const glm::vec3> normals,
                                    std::span<const glm::vec3> fallback) {
    const std::vector<glm::vec3> chosen = weightNormals(normals, fallback);
    LocalLightWeights w;
    w.irradiance.assign(positions.size(), 0.0f);
    w.reached.assign(positions.size(), 0);
    for (size_t i = 0; i < positions.size() && i < chosen.size(); ++i) {
        const glm::vec3 p = positions[i];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) continue;
        const glm::dvec3 toLight = lightPosition - glm::dvec3(p), n(chosen[i]);
        if (!localLightReaches(light, toLight, n)) continue;
        w.reached[i] = 1;
        ++w.reachedCount;
        w.irradiance[i] = float(localLightIrradiance(light, toLight, n));
    }
    return w;
}

ShadowErrorMetrics compareLocalShadow(std::span<const float> player,
                                      std::span<const float> reference,
                                      const LocalLightWeights& weights) {
    assert(player.size() == reference.size() && weights.reached.size() == player.size());
    const size_t n = std::min({player.size(), reference.size(), weights.reached.size()});
    // Outside the reach neither side has a verdict (NaN and -1 are compareShadow's "no
    // geometry"): those pixels are counted nowhere, not even as coverage mismatches.
    std::vector<float> p(player.begin(), player.begin() + std::ptrdiff_t(n)),
        r(reference.begin(), reference.begin() + std::ptrdiff_t(n));
    for (size_t i = 0; i < n; ++i)
        if (!weights.reached[i]) {
            p[i] = -1.0f;
            r[i] = std::numeric_limits<float>::quiet_NaN();
        }
    return compareShadow(p, r, std::span<const float>(weights.irradiance).first(n));
}

ShadowColorMetrics compareLocalShadowColor(std::span<const glm::vec3> player,
                                           std::span<const glm::vec3> reference,
                                           const LocalLightWeights& weights) {
    assert(player.size() == reference.size() && weights.reached.size() == player.size());
    const size_t n = std::min({player.size(), reference.size(), weights.reached.size()});
    // Outside the reach neither side is judged, as in compareLocalShadow.
    std::vector<glm::vec3> p(player.begin(), player.begin() + std::ptrdiff_t(n)),
        r(reference.begin(), reference.begin() + std::ptrdiff_t(n));
    for (size_t i = 0; i < n; ++i)
        if (!weights.reached[i]) {
            p[i] = glm::vec3(-1.0f);
            r[i] = glm::vec3(std::numeric_limits<float>::quiet_NaN());
        }
    return compareShadowColor(p, r, std::span<const float>(weights.irradiance).first(n));
}

} // namespace pnb::reference
