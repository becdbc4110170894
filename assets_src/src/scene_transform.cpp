// The same scene in another unit, place or sun (see scene_transform.h).
#include "pnb_assets/scene_transform.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace pnb::assets {

namespace {

using gltf::Float3;

// The direction a directional light shines along at `elevation` above the horizon, `azimuth`
// about +Y measured from +X towards -Z (the procedural scenes' convention).
Float3 shineDirection(double elevation, double azimuth) {
    const double c = std::cos(elevation);
    return {float(c * std::cos(azimuth)), float(-std::sin(elevation)), float(-c * std::sin(azimuth))};
}

} // namespace

std::string applySceneTransform(gltf::Document& doc, const SceneTransform& t) {
    const double s = t.unitScale;
    if (!std::isfinite(s) || !(s > 0)) return "the unit scale must be a finite number above 0";
    for (float c : t.origin)
        if (!std::isfinite(c)) return "the origin must be finite";
    if (t.sunElevationDegrees && !(*t.sunElevationDegrees >= 0 && *t.sunElevationDegrees <= 90))
        return "the sun elevation must be within 0..90 degrees";
    if (t.sunAzimuthDegrees && !std::isfinite(*t.sunAzimuthDegrees))
        return "the sun azimuth must be finite";
    if (t.cameraNear && !(std::isfinite(*t.cameraNear) && *t.cameraNear > 0))
        return "the camera near plane must be a finite number above 0";
    int32_t sun = -1;
    for (size_t i = 0; i < doc.nodes.size(); ++i)
        if (doc.nodes[i].name == "sun" && doc.nodes[i].light != gltf::kNone) sun = int32_t(i);
    if ((t.sunElevationDegrees || t.sunAzimuthDegrees) && sun < 0)
        return "the scene has no node named \"sun\" with a light";

    if (sun >= 0 && (t.sunElevationDegrees || t.sunAzimuthDegrees)) {
        gltf::Node& n = doc.nodes[size_t(sun)];
        const Float3 d = gltf::rotate(n.rotation, {0, 0, -1});
        const double pi = std::numbers::pi;
        const double elevation = t.sunElevationDegrees ? *t.sunElevationDegrees * pi / 180
                                                       : std::asin(std::clamp(-double(d[1]), -1.0, 1.0));
        const double azimuth = t.sunAzimuthDegrees ? *t.sunAzimuthDegrees * pi / 180
                                                   : std::atan2(-double(d[2]), double(d[0]));
        const Float3 shine = shineDirection(elevation, azimuth);
        // Straight down is parallel to the default up vector: any horizontal up will do.
        const bool vertical = std::fabs(shine[1]) > 0.9999f;
        n.rotation = gltf::lookRotation(shine, vertical ? Float3{0, 0, -1} : Float3{0, 1, 0});
    }
    for (gltf::Camera& c : doc.cameras) {
        if (t.cameraNear) c.znear = *t.cameraNear;
        c.znear = float(c.znear * s);
        c.zfar = float(c.zfar * s); // 0 (infinite) stays 0
    }
    for (gltf::Light& l : doc.lights) {
        if (l.type != gltf::LightType::Point) continue;
        l.range = float(l.range * s);
        l.intensity = float(l.intensity * s * s);
    }
    if (s == 1.0 && t.origin == Float3{0, 0, 0}) return "";

    std::vector<bool> isChild(doc.nodes.size(), false);
    for (const gltf::Node& n : doc.nodes)
        for (uint32_t c : n.children) isChild[c] = true;
    gltf::Node root;
    root.name = "unit-root";
    root.translation = t.origin;
    root.scale = {float(s), float(s), float(s)};
    for (size_t i = 0; i < doc.nodes.size(); ++i)
        if (!isChild[i]) root.children.push_back(uint32_t(i));
    doc.nodes.push_back(std::move(root));
    return "";
}

} // namespace pnb::assets
