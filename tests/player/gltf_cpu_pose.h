// gltf_cpu_pose.h — a glTF's vertices at time t, computed on the CPU straight from the glTF's
// accessors (tinygltf), for the posed-frame conformance test. Deliberately independent of
// pnb/animation_pose.h and of the converter's import: it reads node matrices or TRS, samples
// the animation's channels (step, linear with quaternion slerp, cubic spline), morphs with the
// node's or the mesh's weights, and skins with world(joint) * inverseBind as the glTF
// specification states, so the test compares two implementations, not one with itself.
//
// Does NOT do: sparse accessors, KHR_mesh_quantization's integer positions, Draco (the
// conformance models use none; the loader says so when it meets one).
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace pnb::player::test {

// Every triangle vertex of every mesh instance in the default scene, in world space, with
// animation `animation` (-1: none) at time `t` (seconds, clamped to the clip's keys). Empty
// and `*error` set when the file cannot be read or uses what this reader does not.
std::vector<glm::dvec3> gltfPosedPositions(const std::string& path, int animation, double t, std::string* error);

} // namespace pnb::player::test
