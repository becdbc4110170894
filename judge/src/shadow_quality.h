// shadow_quality.h — pnb-play's --shadow-metrics: each measured frame's sun visibility (or, with
// shadows.judged_light, a point or spot light's) compared with the ray-traced truth
// (pnb_reference, Embree) for the exact pixels the player drew.
//
// Per measured frame: % of pixels whose lit/shadow classification differs (and which way), mean
// absolute shadow-factor error, screen-pixel-to-shadow-texel ratio per cascade (median, p95);
// on the frame after it, temporal flicker: pixels whose classification changed between the two
// frames while the truth's did not (a static scene under a moving camera should have none).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "pnb_player/renderer.h"
#include "pnb_reference/frame_pose.h"

namespace pnb::player {

class ShadowQuality {
public:
    // Loads the container's geometry into the tracer (origin: `origin`, near the camera path).
    // `judgedLight` >= 0: the container's light of that index (a point or spot light) is judged
    // instead of the sun: traced to its position, over the pixels it reaches, weighted by its
    // irradiance (pnb_reference/local_light.h); an index that names no such light is an error.
    static PlayResult<std::unique_ptr<ShadowQuality>> create(const std::string& containerPath,
                                                             glm::dvec3 origin, int judgedLight = -1);
    ~ShadowQuality();

    // Captures position, normal and shadow buffers of the renderer's last frame and measures.
    // With followUp, the frame is the one displayed right after the previous measurement: only
    // flicker against it is reported. `at`: the instant the frame was drawn at (judgedPose): the
    // truth is traced there, its geometry and the judged light posed (a tracer is rebuilt only
    // when the effective instant changes).
    PlayResult<std::vector<std::pair<std::string, double>>> measure(Renderer& renderer, glm::vec3 towardLight,
                                                                     bool followUp,
                                                                     const reference::FramePose& at = {});

    // The last measured frame (not a follow-up) exactly as compared: per pixel the player's
    // shadow factor and the truth's visibility (NaN where the player left the pixel out), rows
    // bottom-up as captured. Classify with reference::classifyShadow, as the metric does. Empty
    // (0 x 0) before the first measurement; valid until the next one. With translucent casters
    // in the scene the metric compares colours (playerColor, truthColor, classified with
    // reference::classifyShadowColor; player and truth are then their means); else those are empty.
    struct Frame {
        uint32_t width = 0, height = 0;
        std::span<const float> player, truth;
        std::span<const glm::vec3> playerColor, truthColor;
    };
    Frame lastFrame() const;

private:
    ShadowQuality() = default;
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

} // namespace pnb::player
