#include "gl/gl_debug.h"

#include <atomic>
#include <cstdio>

#include <epoxy/gl.h>

#include "pnb_player/gl_context.h"

namespace pnb::player {

namespace {

std::atomic<uint64_t> gErrors{0};

void GLAPIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity,
                               GLsizei /*length*/, const GLchar* message, const void* user) {
    bool verbose = user != nullptr;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    // Compile errors are reported with file names by program_compile.cpp.
    if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
    if (type == GL_DEBUG_TYPE_ERROR) ++gErrors;
    if (!verbose && type != GL_DEBUG_TYPE_ERROR) return;
    std::fprintf(stderr, "pnb-play: GL %s %u: %s\n", type == GL_DEBUG_TYPE_ERROR ? "error" : "note",
                 id, message);
}

} // namespace

uint64_t glErrorsReported() { return gErrors.load(); }

void installGlDebugOutput(bool verbose) {
    if (!epoxy_has_gl_extension("GL_KHR_debug") && epoxy_gl_version() < 43) return;
    glEnable(GL_DEBUG_OUTPUT);
    glDebugMessageCallback(onDebugMessage, verbose ? reinterpret_cast<const void*>(1) : nullptr);
}

GlInfo GlContext::info() const {
    auto str = [](GLenum name) {
        const GLubyte* s = glGetString(name);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    return {str(GL_VENDOR), str(GL_RENDERER), str(GL_VERSION), str(GL_SHADING_LANGUAGE_VERSION)};
}

} // namespace pnb::player
