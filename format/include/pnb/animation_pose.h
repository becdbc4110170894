// pnb/animation_pose.h — what a container's animation puts where at time t: clips sampled into
// node poses and morph weights (FORMAT.md "ANIM"), skins' joint matrices ("SKIN"), and the CPU
// deformation of a mesh ("MRPH", "SKIN"), in double where matrices compose.
//
// A property of the container, as node_transform.h is: the player (which deforms on the GPU),
// the ray-traced reference (which deforms here) and the tests must pose every frame identically,
// or the truth would judge another frame than the one drawn.
//
// Does NOT do: validation (readScene applies FORMAT.md's rules before any of this runs), GPU work.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "pnb/node_transform.h"
#include "pnb/scene.h"

namespace pnb {

// A clip's length: its latest key time (0 for a clip whose channels hold one key each).
double clipDuration(const Animation& clip);

// The time within a clip of length `duration` that the clock time `t` plays: looped (t mod
// duration) when `loop`, else clamped to [0, duration]. A zero-length clip plays t = 0.
double clipTime(double duration, double t, bool loop = true);

// The node graph and morph weights at one instant.
struct Pose {
    NodeGraph graph;                         // the container's nodes with animated TRS applied
    std::vector<std::vector<float>> weights; // per node: its mesh's morph weights (empty if none)
};

// Every node at its rest TRS, every morphed node at its mesh's default weights.
Pose restPose(const Scene& scene);

// Overrides the properties `clip` animates with their values at clip time `t` (glTF's sampling:
// step holds the key before t, linear interpolates with rotations slerped along the shorter arc,
// cubic spline is the Hermite curve of the keys' tangents; before the first key the first value,
// after the last the last). A rotation comes out normalised; a value that float cannot hold (an
// extreme cubic tangent) takes the nearer key's value, so no pose is ever non-finite.
void applyClip(const Scene& scene, const Animation& clip, double t, Pose& pose);

// restPose, then `clip` (if any) at clock time `t`, looped.
Pose poseAt(const Scene& scene, std::optional<uint32_t> clip, double t);

// Where a skinned node's deformed vertices are expressed: the translation of its world matrix
// alone. glTF ignores a skinned node's own transform (the joints place the mesh); keeping the
// translation lets renderers stay camera-relative with small coordinates.
Matrix4d skinnedPlacement(const Matrix4d& nodeWorld);

// The skin's joint matrices for skinned node `node`: inverse(placement) * world(joint) *
// inverseBind, column-major float (what the GPU reads), composed in double.
std::vector<std::array<float, 16>> jointMatrices(const Skin& skin, const std::vector<Matrix4d>& world,
                                                 uint32_t node);

// The skin deforming node `node`, if any.
const Skin* skinOf(const Scene& scene, uint32_t node);
// The morph targets of mesh `mesh`, if any.
const MorphTargets* morphTargetsOf(const Scene& scene, uint32_t mesh);

// Whether node `node` draws a deformed mesh (a skin or morph targets).
bool isDeformed(const Scene& scene, uint32_t node);

// The vertices of mesh `mesh` as node `node` draws them in `pose`: morph targets applied at the
// node's weights, then the skin (each vertex at sum_i w_i J[j_i] v with its weights divided by
// their sum; weights summing to 0 leave the vertex where the morph put it), normals and tangents
// by the joints' 3x3 and renormalised; a position that float cannot hold after all that (extreme
// but finite joint matrices or deltas) is the stored one. Positions are in the node's drawing space: its world
// matrix, or skinnedPlacement of it for a skinned node. Reads F32 streams (FORMAT.md requires
// them of deformed meshes); `normals`/`tangents` stay empty without those streams.
struct DeformedVertices {
    std::vector<Vec3> positions, normals;
    std::vector<Vec4> tangents;
};
DeformedVertices deformVertices(const Scene& scene, uint32_t node, const Pose& pose,
                                const std::vector<Matrix4d>& world);

// The matrix that places node `node`'s drawn vertices in the world in `pose`.
Matrix4d drawingMatrix(const Scene& scene, uint32_t node, const std::vector<Matrix4d>& world);

// Conservative bounds of a deformed mesh, cheap per frame: each joint's box of the vertices it
// influences (grown by the morph targets' largest displacement at the current weights),
// transformed by its joint matrix; their union holds every skinned vertex (each is a convex
// combination of its joints' transforms of it).
struct DeformBounds {
    std::vector<Aabb> jointBoxes;       // per joint (empty box: influences nothing); or one box
                                        // without a skin
    std::vector<float> targetReach;     // per morph target: its longest position delta
    Aabb unskinned; // vertices whose weights sum to 0: the skin leaves them where they are
};
DeformBounds deformBounds(const Scene& scene, uint32_t node);
Aabb deformedBounds(const DeformBounds& bounds, const std::vector<std::array<float, 16>>& joints,
                    const std::vector<float>& weights);

} // namespace pnb
