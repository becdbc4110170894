// Interactive context: a GLFW window (X11 or Wayland; Xvfb works for smoke tests).
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <string>

#include "gl/gl_debug.h"
#include "pnb_player/gl_context.h"

namespace pnb::player {

namespace {

std::string lastGlfwError() {
    const char* description = nullptr;
    glfwGetError(&description);
    return description ? description : "unknown error";
}

class GlfwContext final : public GlContext {
public:
    explicit GlfwContext(GLFWwindow* window) : mWindow(window) {}
    ~GlfwContext() override {
        glfwDestroyWindow(mWindow);
        // No glfwTerminate: it unloads the GL driver, whose one-time allocations LeakSanitizer
        // then reports from an unknown module (as with eglTerminate in gl_context_egl.cpp).
    }
    bool isWindow() const override { return true; }
    bool shouldClose() const override { return glfwWindowShouldClose(mWindow); }
    void swapBuffers() override { glfwSwapBuffers(mWindow); }
    void pollEvents() override { glfwPollEvents(); }
    void waitEvents(double timeoutSeconds) override {
        if (timeoutSeconds < 0) glfwWaitEvents();
        else glfwWaitEventsTimeout(timeoutSeconds);
    }
    void framebufferSize(int& width, int& height) const override {
        glfwGetFramebufferSize(mWindow, &width, &height);
    }
    GLFWwindow* glfwWindow() const override { return mWindow; }

private:
    GLFWwindow* mWindow;
};

} // namespace

PlayResult<std::unique_ptr<GlContext>> createWindowContext(const WindowOptions& options) {
    if (!glfwInit())
        return PlayError{PlayErrorKind::Gl,
                     "GLFW: cannot initialise (" + lastGlfwError() +
                         "); is there a display? Use --headless without one"};
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, options.debug ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_TRUE);
    GLFWwindow* window =
        glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
    if (!window) {
        std::string why = lastGlfwError();
        glfwTerminate();
        return PlayError{PlayErrorKind::Gl, "GLFW: cannot create a 4.5 core window: " + why};
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(options.vsync ? 1 : 0);
    std::unique_ptr<GlContext> result = std::make_unique<GlfwContext>(window);
    installGlDebugOutput(options.debug);
    return result;
}

} // namespace pnb::player
