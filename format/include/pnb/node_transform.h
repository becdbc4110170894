// pnb/node_transform.h — where a container puts each node: local and world matrices of the node
// graph (FORMAT.md, NODE chunk), in double.
//
// A property of the container, not of a renderer: the player (draw items, lights, cameras), the
// ray-traced reference and the editor must place every node identically, or the reference would
// judge shadows of geometry the player put elsewhere. Matrices are column-major (element
// [column * 4 + row]), as GL and GLM store them; glm::make_mat4(m.data()) reads one.
//
// Does NOT do: validation (readScene checks that every parent precedes its child), bounds.
#pragma once

#include <array>
#include <vector>

#include "pnb/chunks.h"

namespace pnb {

using Matrix4d = std::array<double, 16>; // column-major

// T * R * S of one node: translation, rotation (the quaternion normalised first; a zero
// quaternion is the identity), scale. In double, so a scene 10^7 from the origin composes exactly
// to the precision its float fields hold.
Matrix4d nodeLocalMatrix(const Node& node);

// a * b (column-major).
Matrix4d multiply(const Matrix4d& a, const Matrix4d& b);

// The world matrix of every node: parent world * local, parents first. Precondition: every
// parent index is below its node's (what readScene guarantees); a node whose parent is not is
// treated as a root.
std::vector<Matrix4d> nodeWorldMatrices(const NodeGraph& graph);

// One drawn copy of a node's mesh and where it is.
struct MeshInstance {
    uint32_t node = 0;
    Matrix4d world{};
};

// Every drawn copy of every mesh, in node order: one per node with a mesh, or, for a node with
// NODE version 2 instances (EXT_mesh_gpu_instancing), one per instance at world(node) * TRS_k.
// `world` is nodeWorldMatrices(graph). The player, the reference and the converter's bounds
// all place copies with this, so they agree on what exists.
std::vector<MeshInstance> meshInstances(const NodeGraph& graph, const std::vector<Matrix4d>& world);

} // namespace pnb
