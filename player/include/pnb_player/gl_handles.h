// pnb_player/gl_handles.h — move-only owners of GL object names, so every early return and
// failed load releases what it created.
#pragma once

#include <epoxy/gl.h>

#include <utility>

namespace pnb::player {

enum class GlKind { Buffer, Texture, Framebuffer, VertexArray, Program, Shader, Query };

class GlHandle {
public:
    GlHandle() = default;
    GlHandle(GlKind kind, GLuint id) : mKind(kind), mId(id) {}
    GlHandle(GlHandle&& o) noexcept : mKind(o.mKind), mId(std::exchange(o.mId, 0)) {}
    GlHandle& operator=(GlHandle&& o) noexcept {
        if (this != &o) {
            reset();
            mKind = o.mKind;
            mId = std::exchange(o.mId, 0);
        }
        return *this;
    }
    GlHandle(const GlHandle&) = delete;
    GlHandle& operator=(const GlHandle&) = delete;
    ~GlHandle() { reset(); }

    GLuint id() const { return mId; }
    explicit operator bool() const { return mId != 0; }
    void reset();

private:
    GlKind mKind = GlKind::Buffer;
    GLuint mId = 0;
};

// Creators (DSA: the objects exist immediately, no bind needed).
GlHandle createBuffer();
GlHandle createTexture(GLenum target);
GlHandle createFramebuffer();
GlHandle createVertexArray();

inline void GlHandle::reset() {
    if (!mId) return;
    switch (mKind) {
    case GlKind::Buffer: glDeleteBuffers(1, &mId); break;
    case GlKind::Texture: glDeleteTextures(1, &mId); break;
    case GlKind::Framebuffer: glDeleteFramebuffers(1, &mId); break;
    case GlKind::VertexArray: glDeleteVertexArrays(1, &mId); break;
    case GlKind::Program: glDeleteProgram(mId); break;
    case GlKind::Shader: glDeleteShader(mId); break;
    case GlKind::Query: glDeleteQueries(1, &mId); break;
    }
    mId = 0;
}

inline GlHandle createBuffer() {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    return {GlKind::Buffer, id};
}
inline GlHandle createTexture(GLenum target) {
    GLuint id = 0;
    glCreateTextures(target, 1, &id);
    return {GlKind::Texture, id};
}
inline GlHandle createFramebuffer() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    return {GlKind::Framebuffer, id};
}
inline GlHandle createVertexArray() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    return {GlKind::VertexArray, id};
}

} // namespace pnb::player
