// Headless context through EGL (see ../shared/design/HEADLESS.md for the facts this relies on).
#include <epoxy/gl.h> // before epoxy/egl.h: the Khronos typedefs clash otherwise
#include <epoxy/egl.h>

#include <string>

#include "gl/gl_debug.h"
#include "pnb_player/gl_context.h"

namespace pnb::player {

namespace {

PlayError eglError(const std::string& what) {
    char code[32];
    std::snprintf(code, sizeof code, "0x%04X", eglGetError());
    return PlayError{PlayErrorKind::Gl, "EGL: " + what + " failed (error " + code + ")"};
}

// The one place that chooses how to reach a GPU without a display.
EGLDisplay eglPlatform() {
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                                nullptr);
        if (d != EGL_NO_DISPLAY) return d;
    }
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration")) {
        EGLDeviceEXT devices[8];
        EGLint count = 0;
        if (eglQueryDevicesEXT(8, devices, &count) && count > 0)
            return eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr);
    }
    return EGL_NO_DISPLAY;
}

class EglContext final : public GlContext {
public:
    EglContext(EGLDisplay display, EGLContext context) : mDisplay(display), mContext(context) {}
    ~EglContext() override {
        eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(mDisplay, mContext);
        // No eglTerminate: Mesa then unloads its driver, whose one-time allocations LeakSanitizer
        // reports as leaks from an unknown module. The display is a per-process singleton that
        // the next eglInitialize reuses, so nothing accumulates.
    }
    bool isWindow() const override { return false; }
    void framebufferSize(int& width, int& height) const override { width = height = 0; }

private:
    EGLDisplay mDisplay;
    EGLContext mContext;
};

} // namespace

PlayResult<std::unique_ptr<GlContext>> createHeadlessContext(bool debug) {
    EGLDisplay display = eglPlatform();
    if (display == EGL_NO_DISPLAY)
        return PlayError{PlayErrorKind::Gl,
                     "EGL: no surfaceless or device platform (install libegl-dev and "
                     "libgl1-mesa-dri, or a GPU driver with EGL)"};
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) return eglError("eglInitialize");
    if (!eglBindAPI(EGL_OPENGL_API)) return eglError("eglBindAPI(EGL_OPENGL_API)");
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_CONTEXT_OPENGL_DEBUG,
                                 debug ? EGL_TRUE : EGL_FALSE, EGL_NONE};
    EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context == EGL_NO_CONTEXT) {
        PlayError e = eglError("eglCreateContext (OpenGL 4.5 core)");
        eglTerminate(display);
        return e;
    }
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        PlayError e = eglError("eglMakeCurrent (surfaceless)");
        eglDestroyContext(display, context);
        eglTerminate(display);
        return e;
    }
    std::unique_ptr<GlContext> result = std::make_unique<EglContext>(display, context);
    installGlDebugOutput(debug);
    return result;
}

} // namespace pnb::player
