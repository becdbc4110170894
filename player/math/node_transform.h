// player/math/node_transform.h — a container node's local transform (pure CPU, no GL).
//
// The player (draw items, lights, cameras) and the ray-traced reference (reference/) must place
// every node identically, or the reference would judge shadows of geometry the player put
// elsewhere; both take the matrix from here.
#pragma once

#include <glm/glm.hpp>

#include "pnb/scene.h"

namespace pnb::player {

// T * R(normalised quaternion) * S, in double so scenes far from the origin compose exactly.
glm::dmat4 nodeLocalMatrix(const Node& node);

} // namespace pnb::player
