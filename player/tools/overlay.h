// overlay.h — the Dear ImGui overlay of pnb-play (--ui): frame timings per pass, draw counts,
// GPU memory, and every render setting as a control generated from the settings table.
#pragma once

#include <string>
#include <vector>

#include "pnb_player/renderer.h"

struct GLFWwindow;

namespace pnb::player {

class Overlay {
public:
    explicit Overlay(GLFWwindow* window);
    ~Overlay();
    Overlay(const Overlay&) = delete;
    Overlay& operator=(const Overlay&) = delete;

    // Draws the overlay into the default framebuffer; returns true if a setting changed
    // (`settings` then holds the new values). `status` lines (camera speed and field of view,
    // recording state, the last message) are shown above the timings.
    // With `animation` (a scene that plays clips), a playback section first: play/pause (which
    // holds the pose where it is: anim.time takes the current time), a time slider over the
    // clip's length (scrubbing pauses), and the clip.
    bool draw(const Renderer& renderer, const FrameGpuTimes* lastTimes, RenderSettings& settings,
              const std::vector<std::string>& status = {}, const SceneAnimation* animation = nullptr);
    bool wantsInput() const;
};

} // namespace pnb::player
