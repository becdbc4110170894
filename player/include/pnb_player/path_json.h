// pnb_player/path_json.h — camera paths as the keyframe JSON that `pnb-convert --path FILE` reads
// (converter/include/pnb_converter/camera_path.h has the schema), so `pnb-play --path FILE` can
// replay a file without converting, and a path recorded in the window can be packed into a
// container unchanged.
//
//   { "name": "flythrough", "interpolation": "catmull-rom" | "linear", "loop": false,
//     "keys": [ { "time": 0.0, "position": [x, y, z],
//                 "target": [x, y, z]  (or "rotation": [x, y, z, w]),
//                 "yfov_degrees": 50 }, ... ] }
//
// Reading applies the converter's rules (at least two keys, strictly increasing finite times,
// yfov_degrees in (1, 179), default 45.8) and the converter's look-at convention for "target".
// Writing stores "rotation" (exact, no look-at round trip) and full double precision.
//
// Does NOT do: reading or writing containers; any schema field beyond the above.
#pragma once

#include <string>

#include "pnb_player/gpu_scene.h"
#include "pnb_player/play_error.h"

namespace pnb::player {

// Reads a keyframe file. Errors (Input) name the file and the key at fault.
PlayResult<ScenePath> readPathJson(const std::string& file);

// The JSON text of `path` (name, interpolation, loop, keys with time, position, rotation,
// yfov_degrees), newline-terminated.
std::string pathJsonText(const ScenePath& path);

// Writes pathJsonText atomically (pnb/atomic_file.h). Errors are Io.
PlayResult<Done> writePathJson(const std::string& file, const ScenePath& path);

} // namespace pnb::player
