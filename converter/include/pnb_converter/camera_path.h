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

// A looping orbit around `bounds` (8 keys, 16 s): radius 1.5 × the bounding radius, 30° above
// the centre, always looking at the centre. Degenerate bounds give a unit orbit at the origin.
PathSpec defaultCameraPath(const Aabb& bounds);

} // namespace pnb::converter
