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

PathSpec defaultCameraPath(const Aabb& bounds) {
    PathSpec p;
    p.name = "default-orbit";
    p.loop = true;
    bool empty = bounds.min.x > bounds.max.x;
    Vec3 c = empty ? Vec3{0, 0, 0}
                   : Vec3{(bounds.min.x + bounds.max.x) / 2, (bounds.min.y + bounds.max.y) / 2,
                          (bounds.min.z + bounds.max.z) / 2};
    Vec3 e = empty ? Vec3{1, 1, 1}
                   : Vec3{bounds.max.x - c.x, bounds.max.y - c.y, bounds.max.z - c.z};
    float radius = std::max(1.5f * std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z), 1e-3f);
    const int kKeys = 8;
    for (int i = 0; i < kKeys; ++i) {
        float a = float(i) / kKeys * 6.2831853f;
        CameraKey k;
        k.timeSeconds = float(i) * 2.0f;
        k.position = {c.x + radius * std::cos(0.5236f) * std::sin(a), c.y + radius * std::sin(0.5236f),
                      c.z + radius * std::cos(0.5236f) * std::cos(a)};
        k.rotation = lookAtRotation(k.position, c);
        k.yfovRadians = 0.8f;
        p.keys.push_back(k);
    }
    return p;
}

} // namespace pnb::converter
