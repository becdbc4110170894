// pnb_reference/frame_pose.h — which instant of a container's animation the truth traces: every
// tracer (ShadowTracer, IndirectTracer, SkyTracer, FrameTracer, placeLocalLight) builds its
// geometry and places its lights at one FramePose, the one the judged frame was drawn at
// (frame.json's "anim", docs/REFERENCE.md "Moving frames").
//
// The default is the container as stored: nodes at their rest TRS, meshes as their streams hold
// them, no deformation. That is the player's anim.enabled = false, and the truth of every frame
// dumped before issue 42 (a frame.json without "anim").
#pragma once

#include <cstdint>
#include <optional>

#include "pnb/scene.h"

namespace pnb::reference {

struct FramePose {
    // false: the container as stored (the fields below are ignored). true: posed by
    // pnb/animation_pose.h: `clip` sampled at `clipTime`, skins and morph targets deforming their
    // meshes (with no clip: every node at rest, morph weights at their defaults, skins at the
    // rest pose of their joints, which need not be the bind pose the streams hold).
    bool animated = false;
    std::optional<uint32_t> clip; // an index into the container's clips (ANIM), or none
    double clipTime = 0;          // seconds into the clip, as sampled: already looped or clamped

    bool operator==(const FramePose&) const = default;
};

// The same instant in its simplest form, so that equal geometry compares equal (a judge rebuilds
// its tracer only when this changes, and keys cached truths by it): the container as stored
// where the rest pose is (no clip, and no skin or morph target to deform), clip time 0 without a
// clip. Tracing either gives the same result (a clip index past the scene's is kept: an error).
FramePose effectivePose(const Scene& scene, const FramePose& at);

} // namespace pnb::reference
