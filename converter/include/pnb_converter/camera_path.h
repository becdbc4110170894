// pnb_converter/camera_path.h — camera fly-through paths: read from a keyframe file
// (`pnb-convert --path FILE`) or generated from the scene bounds when the source has none, and
// the default sun and camera the converter adds (flagged as generated) when a scene lacks them.
//
// The keyframe file's schema and reader are pnb/path_json.h (shared with the player).
#pragma once

#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/error.h"
#include "pnb/path_json.h"
#include "pnb_converter/scene_ir.h"

namespace pnb::converter {

using PathSpec = CameraPathFile;

// Reads a keyframe file. Errors (Input) name the file and the key at fault.
Result<PathSpec, ConvertError> loadCameraPath(const std::string& path);

// [SECTION] framing: the default camera and orbit (docs/CONVERTER.md "Defaults")
//
// Both look at the centre of the bounds' sphere (centre of the box, radius its half-diagonal)
// from kDefaultFramingElevation above it, at the distance where the sphere's image spans at most
// 1/kFramingMargin of the half-frame in the narrower direction: for a vertical field of view
// `yfov` and aspect (width / height) `aspect`, the narrower half-angle is
// h = min(yfov/2, atan(aspect tan(yfov/2))), the sphere's angular radius
// a = atan(tan(h) / kFramingMargin), and distance = radius / sin(a). The player's default
// aspect is 16:9 (wider than tall, so the vertical field is the narrower one); the framing is
// computed for aspect 1 (kFramingAspect), which holds for every window at least as wide as tall.
inline constexpr float kDefaultYfovRadians = 0.8f;         // the player's default, 45.8 degrees
inline constexpr float kFramingMargin = 1.1f;              // 10 % of the half-frame left free
inline constexpr float kFramingAspect = 1.0f;
inline constexpr float kDefaultFramingElevation = 0.5235988f; // 30 degrees

struct Framing {
    Vec3 center{0, 0, 0};
    float radius = 1;   // > 0
    float distance = 1; // from the centre
    float znear = 0.1f; // a tenth of the way to the sphere: 0.1 (distance - radius)
    float zfar = 0;     // 4 (distance + radius): room to orbit and fly out
};
// Degenerate (empty) bounds frame a unit sphere at the origin; a one-point box gets a radius of
// 1e-3.
Framing frameBounds(const Aabb& bounds, float yfovRadians = kDefaultYfovRadians,
                    float aspect = kFramingAspect);

// Where the framing puts the camera at `azimuthRadians` (from +Z towards +X), and the rotation
// that looks from there at the centre.
Vec3 framingPosition(const Framing& f, float azimuthRadians);

// A looping orbit around `bounds` (8 keys, 16 s): at frameBounds' distance, 30° above the
// centre, always looking at the centre, yfov kDefaultYfovRadians. Key 0 is at azimuth 0 (+Z),
// where the default camera is.
PathSpec defaultCameraPath(const Aabb& bounds);

} // namespace pnb::converter
