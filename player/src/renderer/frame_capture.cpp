// Reading the frame's buffers back exactly (for screenshots, dumps and tests).
#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/renderer_impl.h"
#include "pnb_player/renderer.h"

namespace pnb::player {

namespace {

std::vector<float> readFloats(GLuint texture, GLenum format, uint32_t channels, uint32_t w, uint32_t h) {
    std::vector<float> data(size_t(w) * h * channels);
    glGetTextureImage(texture, 0, format, GL_FLOAT, GLsizei(data.size() * sizeof(float)), data.data());
    return data;
}

// Same mapping as shaders/include/octahedral.glsl.
glm::vec3 octDecode(glm::vec2 e) {
    glm::vec3 v(e, 1.0f - std::abs(e.x) - std::abs(e.y));
    if (v.z < 0) {
        glm::vec2 s(v.x >= 0 ? 1.0f : -1.0f, v.y >= 0 ? 1.0f : -1.0f);
        glm::vec2 xy = (1.0f - glm::abs(glm::vec2(v.y, v.x))) * s;
        v.x = xy.x;
        v.y = xy.y;
    }
    return glm::normalize(v);
}

} // namespace

size_t nonFinitePixels(const CapturedImage& image) {
    if (image.channels == 0 || image.f32.empty()) return 0;
    size_t count = 0;
    for (size_t i = 0; i + image.channels <= image.f32.size(); i += image.channels) {
        bool finite = true;
        for (uint32_t c = 0; c < image.channels; ++c) finite &= std::isfinite(image.f32[i + c]);
        count += !finite;
    }
    return count;
}

PlayResult<CapturedImage> Renderer::capture(CaptureBuffer buffer) {
    const FrameTargets& t = mImpl->targets;
    if (t.width == 0) return PlayError{PlayErrorKind::Usage, "capture before the first frame"};
    CapturedImage img;
    img.width = t.width;
    img.height = t.height;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    switch (buffer) {
    case CaptureBuffer::Color:
        img.channels = 4;
        img.u8.resize(size_t(t.width) * t.height * 4);
        glGetTextureImage(t.output.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(img.u8.size()), img.u8.data());
        break;
    case CaptureBuffer::Hdr:
        img.channels = 4;
        img.f32 = readFloats(t.hdr.id(), GL_RGBA, 4, t.width, t.height);
        break;
    case CaptureBuffer::Depth:
    case CaptureBuffer::LinearDepth:
        img.channels = 1;
        img.f32 = readFloats(t.depth.id(), GL_DEPTH_COMPONENT, 1, t.width, t.height);
        if (buffer == CaptureBuffer::LinearDepth) {
            for (float& d : img.f32) d = float(viewDepthFromBuffer(mView, d));
        }
        break;
    case CaptureBuffer::Position: {
        img.channels = 3;
        std::vector<float> depth = readFloats(t.depth.id(), GL_DEPTH_COMPONENT, 1, t.width, t.height);
        img.f32.resize(depth.size() * 3);
        glm::dmat4 inverse(mView.inverseViewProjection);
        for (uint32_t y = 0; y < t.height; ++y) {
            for (uint32_t x = 0; x < t.width; ++x) {
                size_t i = size_t(y) * t.width + x;
                glm::dvec3 p(std::numeric_limits<double>::quiet_NaN());
                if (depth[i] > 0) {
                    glm::dvec4 ndc{(x + 0.5) / t.width * 2 - 1, (y + 0.5) / t.height * 2 - 1, depth[i], 1};
                    glm::dvec4 h = inverse * ndc;
                    p = glm::dvec3(h) / h.w;
                }
                for (int k = 0; k < 3; ++k) img.f32[i * 3 + size_t(k)] = float(p[k]);
            }
        }
        break;
    }
    case CaptureBuffer::Shadow:
    case CaptureBuffer::ShadowColor:
    case CaptureBuffer::Indirect:
    case CaptureBuffer::Sky: {
        // Lighting writes visibility, cascade and texel ratio (or indirect irradiance) instead
        // of radiance for one frame of the same view; then the frame is rendered again so the
        // output is the image again.
        img.channels = 4;
        Impl& impl = *mImpl;
        FrameStats stats = mStats;
        bool& mode = buffer == CaptureBuffer::Shadow        ? impl.shadows.capture
                     : buffer == CaptureBuffer::ShadowColor ? impl.shadows.captureColor
                     : buffer == CaptureBuffer::Indirect    ? impl.gi.capture
                                                            : impl.ibl.capture;
        impl.capturing = mode = true;
        auto r = render(impl.lastCamera, t.width, t.height);
        if (r) img.f32 = readFloats(t.hdr.id(), GL_RGBA, 4, t.width, t.height);
        if ((buffer == CaptureBuffer::Indirect && !impl.gi.frame.active) ||
            (buffer == CaptureBuffer::Sky && !impl.ibl.active))
            std::fill(img.f32.begin(), img.f32.end(), 0.0f);
        mode = false;
        if (r) r = render(impl.lastCamera, t.width, t.height);
        impl.capturing = false;
        impl.frame -= 2;
        mStats = stats;
        if (!r) return r.error();
        break;
    }
    case CaptureBuffer::GiVolume: {
        const GiResources& gi = mImpl->gi.resources;
        img.channels = 12;
        img.width = img.height = 0;
        if (!mImpl->gi.frame.active) break;
        img.width = gi.cells;
        img.height = gi.cells * gi.cells * gi.cascades;
        size_t count = size_t(img.width) * img.height;
        img.f32.resize(count * 12);
        for (size_t ch = 0; ch < 3; ++ch) {
            std::vector<float> v = readFloats(gi.sum[ch].id(), GL_RGBA, 4, img.width, img.height);
            for (size_t i = 0; i < count; ++i)
                for (size_t k = 0; k < 4; ++k) img.f32[i * 12 + ch * 4 + k] = v[i * 4 + k];
        }
        break;
    }
    case CaptureBuffer::Normal: {
        img.channels = 3;
        img.f32.assign(size_t(t.width) * t.height * 3, 0.0f);
        if (!t.gbuffer[0]) break;
        std::vector<float> base = readFloats(t.gbuffer[0].id(), GL_RGBA, 4, t.width, t.height);
        std::vector<float> nm = readFloats(t.gbuffer[1].id(), GL_RGBA, 4, t.width, t.height);
        for (size_t i = 0; i < size_t(t.width) * t.height; ++i) {
            if (base[i * 4 + 3] <= 0) continue;
            glm::vec3 n = octDecode(glm::vec2(nm[i * 4], nm[i * 4 + 1]) * 2.0f - 1.0f);
            img.f32[i * 3] = n.x;
            img.f32[i * 3 + 1] = n.y;
            img.f32[i * 3 + 2] = n.z;
        }
        break;
    }
    }
    ++mStats.gpuReadbacks;
    return img;
}

} // namespace pnb::player
