#include "frame/frame_targets.h"

#include <string>

namespace pnb::player {

namespace {

GlHandle texture2d(GLenum format, uint32_t w, uint32_t h, const char* label, uint64_t bytesPerPixel,
                   uint64_t& counter) {
    GlHandle t = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), 1, format, GLsizei(w), GLsizei(h));
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glObjectLabel(GL_TEXTURE, t.id(), -1, label);
    counter += bytesPerPixel * w * h;
    return t;
}

GlHandle framebuffer(std::initializer_list<GLuint> colors, GLuint depth) {
    GlHandle fb = createFramebuffer();
    GLenum buffers[4];
    GLsizei n = 0;
    for (GLuint c : colors) {
        glNamedFramebufferTexture(fb.id(), GL_COLOR_ATTACHMENT0 + GLenum(n), c, 0);
        buffers[n] = GL_COLOR_ATTACHMENT0 + GLenum(n);
        ++n;
    }
    glNamedFramebufferDrawBuffers(fb.id(), n, buffers);
    if (depth) glNamedFramebufferTexture(fb.id(), GL_DEPTH_ATTACHMENT, depth, 0);
    return fb;
}

} // namespace

void FrameTargets::ensure(uint32_t w, uint32_t h, bool needGbuffer, bool needFxaa, bool needDebug) {
    bool resized = w != width || h != height;
    if (resized) {
        width = w;
        height = h;
        uint64_t streaming = memory.streamingBytes;
        memory = {};
        memory.streamingBytes = streaming;
        depth = texture2d(GL_DEPTH_COMPONENT32F, w, h, "depth (shared)", 4, memory.depthBytes);
        hdr = texture2d(GL_RGBA16F, w, h, "hdr", 8, memory.hdrBytes);
        output = texture2d(GL_SRGB8_ALPHA8, w, h, "output", 4, memory.outputBytes);
        hdrFb = framebuffer({hdr.id()}, depth.id());
        composeFb = framebuffer({hdr.id()}, 0); // no depth: compose samples it
        outputFb = framebuffer({output.id()}, 0);
        for (GlHandle& g : gbuffer) g = {};
        fxaaInput = {};
        debugColor = {};
    }
    if (needGbuffer && !gbuffer[0]) {
        memory.gbufferBytes = 0;
        gbuffer[0] = texture2d(GL_SRGB8_ALPHA8, w, h, "gbuffer base+alpha", 4, memory.gbufferBytes);
        gbuffer[1] = texture2d(GL_RGBA16, w, h, "gbuffer normal+material", 8, memory.gbufferBytes);
        gbuffer[2] = texture2d(GL_R11F_G11F_B10F, w, h, "gbuffer emissive", 4, memory.gbufferBytes);
        gbufferFb = framebuffer({gbuffer[0].id(), gbuffer[1].id(), gbuffer[2].id()}, depth.id());
    } else if (!needGbuffer && gbuffer[0]) {
        for (GlHandle& g : gbuffer) g = {};
        gbufferFb = {};
        memory.gbufferBytes = 0;
    }
    if (needFxaa && !fxaaInput) {
        uint64_t bytes = 0;
        fxaaInput = texture2d(GL_SRGB8_ALPHA8, w, h, "fxaa input", 4, bytes);
        glTextureParameteri(fxaaInput.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(fxaaInput.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        fxaaInputFb = framebuffer({fxaaInput.id()}, 0);
    } else if (!needFxaa && fxaaInput) {
        fxaaInput = {};
        fxaaInputFb = {};
    }
    memory.outputBytes = uint64_t(4) * w * h * (fxaaInput ? 2 : 1);
    if (needDebug && !debugColor) {
        memory.debugBytes = 0;
        debugColor = texture2d(GL_RGBA16F, w, h, "debug accumulation", 8, memory.debugBytes);
        debugDepth = texture2d(GL_DEPTH_COMPONENT32F, w, h, "debug depth", 4, memory.debugBytes);
        debugFb = framebuffer({debugColor.id()}, debugDepth.id());
    } else if (!needDebug && debugColor) {
        debugColor = {};
        debugDepth = {};
        debugFb = {};
        memory.debugBytes = 0;
    }
}

} // namespace pnb::player
