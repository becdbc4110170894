// Camera paths: keyframe files (read by pnb/path_json.h) and the default orbit.

#include "pnb_converter/camera_path.h"

#include <algorithm>
#include <cmath>

namespace pnb::converter {

Result<PathSpec, ConvertError> loadCameraPath(const std::string& path) {
    auto p = readCameraPathJson(path);
    if (!p) return ConvertError{ConvertErrorKind::Input, p.error().message};
    return std::move(*p);
}

Framing frameBounds(const Aabb& bounds, float yfovRadians, float aspect) {
    Framing f;
    const bool empty = !(bounds.min.x <= bounds.max.x);
    if (!empty) {
        f.center = {(bounds.min.x + bounds.max.x) / 2, (bounds.min.y + bounds.max.y) / 2,
                    (bounds.min.z + bounds.max.z) / 2};
        const double ex = double(bounds.max.x) - f.center.x, ey = double(bounds.max.y) - f.center.y,
                     ez = double(bounds.max.z) - f.center.z;
        f.radius = std::max(float(std::sqrt(ex * ex + ey * ey + ez * ez)), 1e-3f);
    }
    const double halfY = double(yfovRadians) / 2;
    const double half = std::min(halfY, std::atan(double(aspect) * std::tan(halfY)));
    const double angular = std::atan(std::tan(half) / double(kFramingMargin));
    const double distance = double(f.radius) / std::sin(angular);
    f.distance = float(distance);
    f.znear = float(0.1 * (distance - f.radius));
    f.zfar = float(4.0 * (distance + f.radius));
    return f;
}

Vec3 framingPosition(const Framing& f, float azimuthRadians) {
    const double e = kDefaultFramingElevation, a = azimuthRadians, d = f.distance;
    return {float(f.center.x + d * std::cos(e) * std::sin(a)), float(f.center.y + d * std::sin(e)),
            float(f.center.z + d * std::cos(e) * std::cos(a))};
}

PathSpec defaultCameraPath(const Aabb& bounds) {
    PathSpec p;
    p.name = "default-orbit";
    p.loop = true;
    const Framing f = frameBounds(bounds);
    const int kKeys = 8;
    for (int i = 0; i < kKeys; ++i) {
        const float a = float(i) / kKeys * 6.2831853f;
        CameraKey k;
        k.timeSeconds = float(i) * 2.0f;
        k.position = framingPosition(f, a);
        k.rotation = lookAtRotation(k.position, f.center);
        k.yfovRadians = kDefaultYfovRadians;
        p.keys.push_back(k);
    }
    return p;
}

} // namespace pnb::converter
