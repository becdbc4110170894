// place_item.h — a draw item put somewhere: its world and normal matrices, world scale, winding
// and world-space box. At load for every item (scene_load.cpp), and again for the items an
// animation moves (anim/animate_scene.cpp).
#pragma once

#include <glm/glm.hpp>

#include "pnb/chunks.h"
#include "pnb_player/gpu_scene.h"

namespace pnb::player {

// The world box of `local` placed by `m` (its eight corners); an empty box is the point at the
// placement's origin.
void placeBox(const glm::dmat4& m, const Aabb& local, glm::dvec3& outMin, glm::dvec3& outMax);

// Places `item` at `world` with `local` (its mesh-space box) as its bounds.
void placeItem(DrawItem& item, const glm::dmat4& world, const Aabb& local);

} // namespace pnb::player
