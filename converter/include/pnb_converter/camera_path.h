// pnb_converter/camera_path.h — camera fly-through paths: read from a keyframe file
// (`pnb-convert --path FILE`) or generated from the scene bounds when the source has none, and
// the default sun and camera the converter adds (flagged as generated) when a scene lacks them.
//
// Keyframe file (JSON):
//   { "name": "flythrough", "interpolation": "catmull-rom" | "linear", "loop": false,
//     "keys": [ { "time": 0.0, "position": [x, y, z],
//                 "target": [x, y, z]            (or "rotation": [x, y, z, w]),
//                 "yfov_degrees": 50 }, ... ] }
// Times in seconds, strictly increasing; at least two keys; positions in scene units.
#pragma once

#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/error.h"
#include "pnb_converter/scene_ir.h"

namespace pnb::converter {

struct PathSpec {
    std::string name;
    Interpolation interpolation = Interpolation::CatmullRom;
    bool loop = false;
    std::vector<CameraKey> keys;
};

// Reads a keyframe file. Errors (Input) name the file and the key at fault.
Result<PathSpec, ConvertError> loadCameraPath(const std::string& path);

// A looping orbit around `bounds` (8 keys, 16 s): radius 1.5 × the bounding radius, 30° above
// the centre, always looking at the centre. Degenerate bounds give a unit orbit at the origin.
PathSpec defaultCameraPath(const Aabb& bounds);

// Unit quaternion (xyzw) of a camera at `eye` looking at `target` with +Y up (the camera looks
// down its local -Z). Falls back to +Z up when the view is vertical.
Vec4 lookAtRotation(Vec3 eye, Vec3 target);

} // namespace pnb::converter
