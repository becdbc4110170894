// player/math/lod_levels.h — which submeshes of a mesh are levels of detail of which (pure CPU).
//
// The MESH chunk lists level-0 submeshes and their simplified versions side by side (Submesh::lod,
// docs/FORMAT.md "MESH"). The pairing rule, which the converter's output follows (levels appended
// by level, then in level-0 submesh order): for a material m with k level-0 submeshes, level L of
// m is complete when it has exactly k submeshes with material m, and then the j-th of them (in
// chunk order) is level L of the j-th level-0 submesh of m. A level that is missing or incomplete
// for m ends every chain of m there (even when a later level is complete), so a level never
// leaves a hole where a submesh was.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "pnb/chunks.h"

namespace pnb::player {

// One level-0 submesh and its simplified versions.
struct SubmeshChain {
    uint32_t material = kNone;
    std::vector<uint32_t> levels; // Submesh indices: levels[0] the level-0 one, then level 1, ...
};

// Every level-0 submesh with a material (kNone ones are not drawn), in chunk order, with its
// chain. Submeshes that belong to no complete level are ignored.
std::vector<SubmeshChain> buildLevelChains(std::span<const Submesh> submeshes);

} // namespace pnb::player
