// pnb/mesh_levels.h — which submeshes of a mesh are levels of detail of which: the pairing rule
// of docs/FORMAT.md "MESH", for every reader and writer (the player's draw items, the
// converter's proxies for MDET).
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
#include "pnb/scene_builder.h"

namespace pnb {

// One level-0 submesh and its simplified versions.
struct SubmeshChain {
    uint32_t material = kNone;
    std::vector<uint32_t> levels; // Submesh indices: levels[0] the level-0 one, then level 1, ...
};

// Every level-0 submesh with a material (kNone ones are not drawn), in chunk order, with its
// chain. Submeshes that belong to no complete level are ignored.
std::vector<SubmeshChain> buildLevelChains(std::span<const Submesh> submeshes);

// Whether `mesh` has levels of detail a reader would use (some chain longer than one level).
bool hasLevelChains(const Mesh& mesh);

// The coarse proxy of a mesh with levels (docs/FORMAT.md "MDET"): one level-0 submesh per chain,
// holding the chain's coarsest level's triangles but level 0's bounds (so culling and the draw
// item's bounds do not change when the detail arrives), over only the vertices those triangles
// use (in first-use order), in the mesh's own stream encodings (same dequantisation). Its bytes
// are kept by `builder`. lodError of each proxy submesh is 0: it is the only level it has.
Mesh buildCoarseProxy(const Mesh& mesh, SceneBuilder& builder);

} // namespace pnb
