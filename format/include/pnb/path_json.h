// pnb/path_json.h — the camera-path keyframe file: the JSON a user writes for `pnb-convert --path`,
// `pnb-play --path FILE` replays and the player's path recorder saves. One reader and one writer,
// shared by converter and player, so the two can never disagree about a file.
//
//   { "name": "flythrough", "interpolation": "catmull-rom" | "linear", "loop": false,
//     "keys": [ { "time": 0.0, "position": [x, y, z],
//                 "target": [x, y, z]            (or "rotation": [x, y, z, w]),
//                 "yfov_degrees": 50 }, ... ] }
// Times in seconds, finite and strictly increasing; at least two keys; positions in scene units;
// yfov_degrees in (1, 179), default 45.8; "target" uses lookAtRotation's convention.
//
// A separate library (pnb_path_json) from pnb_format: JSON is not part of the container.
// Does NOT do: reading or writing containers (the PATH chunk is pnb/chunks.h's CameraPath).
#pragma once

#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/error.h"

namespace pnb {

struct CameraPathFile {
    std::string name = "path";
    Interpolation interpolation = Interpolation::CatmullRom;
    bool loop = false;
    std::vector<CameraKey> keys;
};

// Reads a keyframe file. Errors: IoError (cannot open), BadPayload (the first problem, naming the
// file and the key at fault: "FILE: keys[3].time does not increase").
Result<CameraPathFile> readCameraPathJson(const std::string& file);

// The file's JSON text, one key per line, newline-terminated. Keys are written with "rotation"
// (exact, no look-at round trip) and the shortest decimals that read back as the same floats
// (rotations are renormalised on reading: equal within 1e-7).
std::string cameraPathJsonText(const CameraPathFile& path);

// Unit quaternion (xyzw) of a camera at `eye` looking at `target` with +Y up (the camera looks
// down its local -Z). Falls back to +Z up when the view is vertical.
Vec4 lookAtRotation(Vec3 eye, Vec3 target);

} // namespace pnb
