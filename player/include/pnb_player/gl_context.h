// pnb_player/gl_context.h — an OpenGL 4.5 core context: headless (EGL, no display needed) or a
// GLFW window. The renderer draws into its own framebuffers either way; a window only adds the
// final blit and buffer swap.
//
// Headless picks the EGL platform in one place (eglPlatform()): Mesa's surfaceless platform
// (llvmpipe on the development machine and CI), else EGL device enumeration (NVIDIA).
//
// Does NOT do: multiple contexts, context sharing, vsync control beyond on/off.
#pragma once

#include <memory>
#include <string>

#include "pnb_player/play_error.h"

struct GLFWwindow;

namespace pnb::player {

struct GlInfo {
    std::string vendor, renderer, version, glsl;
};

class GlContext {
public:
    virtual ~GlContext() = default;
    virtual bool isWindow() const = 0;
    // Window only: false once the user closed it.
    virtual bool shouldClose() const { return false; }
    virtual void swapBuffers() {}
    virtual void pollEvents() {}
    // Window only: sleeps until an event arrives (or `timeoutSeconds` pass, if >= 0), then
    // handles it. What a minimised window does instead of rendering.
    virtual void waitEvents(double timeoutSeconds = -1) { (void)timeoutSeconds; }
    // Drawable size in pixels (window) or the size asked for (headless).
    virtual void framebufferSize(int& width, int& height) const = 0;
    virtual GLFWwindow* glfwWindow() const { return nullptr; }
    GlInfo info() const;
};

// A 4.5 core context with no surface; GL debug output is routed to stderr (errors only unless
// `debug`). Errors name the failing EGL call.
PlayResult<std::unique_ptr<GlContext>> createHeadlessContext(bool debug = false);

struct WindowOptions {
    int width = 1280, height = 720;
    std::string title = "pnb-play";
    bool vsync = true;
    bool debug = false;
};
// A 4.5 core GLFW window (needs a display, e.g. Xvfb). Errors carry GLFW's description.
PlayResult<std::unique_ptr<GlContext>> createWindowContext(const WindowOptions& options);

} // namespace pnb::player
