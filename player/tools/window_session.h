// window_session.h — pnb-play's interactive window: GLFW callbacks (and --script-input events)
// feed InputMapper (input_actions.h); its actions quit, record camera paths (path_recorder.h),
// save screenshots, open dropped files (a .pnb directly, glTF/OBJ through a child pnb-convert:
// child_convert.h) and steer the fly camera. A minimised window (or a zero-sized framebuffer)
// sleeps in glfwWaitEvents instead of rendering.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "input_actions.h"
#include "pnb_player/benchmark.h"
#include "pnb_player/gl_context.h"
#include "pnb_player/renderer.h"
#include "pnb_player/scene_stream.h"

namespace pnb::player {

struct WindowRunOptions {
    std::string sceneFile;          // shown in the title; replaced by a dropped file
    std::string glRenderer;         // for driverDefaults when a dropped scene is loaded
    std::vector<std::string> sets;  // --set, applied to dropped scenes too
    bool verifyChecksums = true;
    bool quiet = false;
    bool ui = false;                // the ImGui overlay
    uint32_t frames = 0;            // quit after this many rendered frames (0: run until quit)
    uint32_t width = 0, height = 0; // render size (0: the framebuffer's)
    double fixedDt = 0;             // > 0: every frame advances the camera by this (else wall clock)
    std::vector<CaptureRequest> captures; // --screenshot FILE --frame K
    std::string screenshotDir = "."; // F12
    std::string recordPath = "recorded_path.json";
    double recordEvery = 0;          // > 0: a key every this many seconds while recording
    bool scripted = false;           // --script-input given: real keyboard/mouse input is ignored
    std::vector<ScriptedEvent> script;
};

// Runs until Esc, the window's close button, a scripted close or `frames`. Returns the exit code
// (0 on a normal quit; a recording in progress is saved first).
// `stream` (may be null) fills `scene` while frames are drawn; a dropped file is streamed too
// when it is set.
int runWindow(GlContext& context, std::unique_ptr<GpuScene> scene, std::unique_ptr<SceneStream> stream,
              std::unique_ptr<Renderer> renderer, RenderSettings settings, const CameraState& first,
              const WindowRunOptions& options);

} // namespace pnb::player
