// The colour companions of the shadow maps (shadow_maps.h, issue 43): what blended casters let
// through, and where the nearest of them is. Shared by the sun's cascade array and the local
// atlas, which attach them to their own framebuffers.
#include "shadows/shadow_maps.h"

namespace pnb::player {

namespace {

GlHandle companion(GLenum format, uint32_t width, uint32_t height, uint32_t layers, const std::string& label) {
    GlHandle t = createTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(t.id(), 1, format, GLsizei(width), GLsizei(height), GLsizei(layers));
    // Lighting reads single texels (texelFetch) and filters them itself, per depth comparison.
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glObjectLabel(GL_TEXTURE, t.id(), -1, label.c_str());
    return t;
}

} // namespace

void TranslucentMaps::create(uint32_t width, uint32_t height, uint32_t layers, const char* label) {
    // sRGB-encoded: blending and reads happen in linear, and 8 bits then resolve the dark end
    // where panes multiply (two panes of T 0.12: 0.0144, stored within 3 %; linear 8 bits: 9 %).
    transmittance = companion(GL_SRGB8_ALPHA8, width, height, layers, std::string(label) + " transmittance");
    nearestDepth = companion(GL_R32F, width, height, layers, std::string(label) + " nearest translucent depth");
    bytes = uint64_t(width) * height * layers * (4 + 4);
}

void attachTranslucentMaps(GLuint framebuffer, const TranslucentMaps& maps, int layer) {
    const GLuint textures[2] = {maps.transmittance.id(), maps.nearestDepth.id()};
    for (GLenum i = 0; i < 2; ++i) {
        if (!maps || layer < 0)
            glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0 + i, maps ? textures[i] : 0, 0);
        else
            glNamedFramebufferTextureLayer(framebuffer, GL_COLOR_ATTACHMENT0 + i, textures[i], 0, layer);
    }
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    if (maps) glNamedFramebufferDrawBuffers(framebuffer, 2, buffers);
    else glNamedFramebufferDrawBuffer(framebuffer, GL_NONE);
}

void clearTranslucentMaps(GLuint framebuffer) {
    const float one[4] = {1, 1, 1, 1};
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, one);
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, 1, one);
}

void beginTranslucentCasters() {
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_FALSE); // tested against the opaque casters, never hiding each other
    glEnable(GL_FRAMEBUFFER_SRGB); // the transmittance is stored sRGB-encoded, blended in linear
    glEnable(GL_BLEND);
    glBlendEquationi(0, GL_FUNC_ADD);
    glBlendFunci(0, GL_DST_COLOR, GL_ZERO); // panes along the way multiply
    glBlendEquationi(1, GL_MIN);            // the nearest pane's depth
    glBlendFunci(1, GL_ONE, GL_ONE);
}

void restoreOpaqueCasterState() {
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glBlendEquation(GL_FUNC_ADD);
    glDisable(GL_BLEND);
    glDisable(GL_FRAMEBUFFER_SRGB);
}

static const TranslucentMaps& neutralTranslucentMaps(TranslucentMaps& neutral) {
    if (!neutral) {
        neutral.create(1, 1, 1, "neutral");
        const float one[4] = {1, 1, 1, 1};
        glClearTexImage(neutral.transmittance.id(), 0, GL_RGBA, GL_FLOAT, one);
        glClearTexImage(neutral.nearestDepth.id(), 0, GL_RED, GL_FLOAT, one);
        neutral.bytes = 0;
    }
    return neutral;
}

void bindTranslucentMaps(const TranslucentMaps& maps, TranslucentMaps& neutral, GLuint firstUnit) {
    const TranslucentMaps& m = maps ? maps : neutralTranslucentMaps(neutral);
    glBindTextureUnit(firstUnit, m.transmittance.id());
    glBindTextureUnit(firstUnit + 1, m.nearestDepth.id());
}

} // namespace pnb::player
