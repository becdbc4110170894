// pnb_player/camera_path.h — evaluating a container's camera path at a time.
//
// Positions and field of view: cubic Hermite through the keys with Catmull-Rom tangents taken
// from the key *times* (non-uniform spacing stays smooth, C1). Rotations: the same Hermite on
// quaternion components (hemisphere-aligned to the previous key) then normalised — smooth where
// per-segment slerp would kink at every key. Linear paths use lerp and slerp. Looping paths wrap
// time and tangents. Deterministic: the same path and time give the same camera.
#pragma once

#include "pnb/chunks.h"
#include "pnb_player/camera.h"

namespace pnb::player {

// Time span of the path (0 for fewer than two keys; loops include the closing segment, which
// takes the mean key spacing).
double pathDuration(const CameraPath& path);

// Precondition: path.keys is non-empty. Times outside the path clamp (or wrap, if looping).
// Sets position, rotation and yfov of `camera`; near/far are left as they are.
void evaluatePath(const CameraPath& path, double timeSeconds, CameraState& camera);

} // namespace pnb::player
