// posed_frame.h — the posed-frame test as a helper any container can go through: the
// player poses a frame at a time, and every deformed node's posed buffer (read back from the GPU)
// is compared with pnb::deformVertices, the CPU pose every consumer shares; the draw items'
// world bounds must hold every posed vertex. The tests call it on the animated scene they build
// (animation_test.cpp) and on the Khronos targets where present.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace pnb::player::test {

struct PosedFrameCheck {
    std::string error;       // what stopped the check ("" when it ran)
    size_t deformedNodes = 0, vertices = 0;
    // Largest differences, GPU against CPU: positions relative to the node's posed extent
    // (the diagonal of its CPU-posed box), normals and tangents as unit vectors.
    double positionError = 0, normalError = 0, tangentError = 0;
    size_t outsideBounds = 0; // posed vertices outside their items' world bounds
    // Every deformed node's posed vertices as the GPU wrote them, placed in the world by the
    // node's draw item (what the frame drew), for comparisons with an independent pose.
    std::vector<glm::dvec3> worldPositions;
};

// Loads `pnbPath`, renders one 64x64 frame with the pose held at `time` seconds of clip `clip`
// (anim.clip: an index, a name or "none"), and compares. The container's clip is sampled at
// clip `clip` index for the CPU side: pass the index (or "none").
PosedFrameCheck checkPosedFrame(const std::string& pnbPath, double time, const std::string& clip = "0");

} // namespace pnb::player::test
