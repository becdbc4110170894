// pnb_player/frame_animation.h — the animation state a benchmark frame is drawn at, as the dumps'
// frame.json records it ("anim", written by bench_report.cpp; docs/REFERENCE.md "Moving frames")
// for the ray-traced truth to pose the same instant.
//
// The player's clock (issue 42): frame i of a fixed-step run is at clock time anim.time +
// anim.speed x i x step when anim.play, else anim.time; the clip plays it looped
// (pnb::clipTime). anim.enabled = false draws the container as stored.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pnb::player {

// The anim.* settings (docs/PLAYER.md), with their defaults.
struct AnimationClock {
    bool enabled = true;
    std::string clip = "0"; // an index, a clip's name, or "none"
    bool play = true;
    double time = 0, speed = 1;
};

// The anim.* keys of `entries` ("key", "value"; later wins, as RSET then --set), others ignored;
// a value that does not parse keeps the default.
AnimationClock animationClock(const std::vector<std::pair<std::string, std::string>>& entries);

// A container's clip, as the clock needs it.
struct ClipInfo {
    std::string name;
    double duration = 0; // pnb::clipDuration
};

// The clips of the container at `path` (its ANIM chunks, in order); empty when it has none or
// cannot be read.
std::vector<ClipInfo> containerClips(const std::string& path);

struct FrameAnimation {
    bool enabled = true;
    std::optional<uint32_t> clip; // none: the rest pose (anim.clip none, a clip that does not
                                  // exist, or a container without clips)
    std::string clipName;
    double time = 0;              // the clip time sampled (after looping)
};

// Frame `frame` of a run whose clock advances by `step` seconds a frame.
FrameAnimation frameAnimation(const AnimationClock& clock, const std::vector<ClipInfo>& clips, uint32_t frame,
                              double step);

} // namespace pnb::player
