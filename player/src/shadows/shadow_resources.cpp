// GPU objects of the shadow maps: the cascade array, its two views and framebuffers, the blended
// casters' colour companions (only while some are drawn), and the SDSM buffers and compute programs (only while SDSM is selected).
#include <bit>

#include "gl/program_compile.h"
#include "shadows/shadow_maps.h"
#include "gl/upload_heap.h"
#include "shared/sdsm_state.h" // SdsmState (GLSL and C++)

namespace pnb::player {

namespace {

constexpr size_t kIndirectCommandBytes = 20; // DrawElementsIndirectCommand

GlHandle buffer(size_t bytes, const char* label, uint64_t& counter) {
    GlHandle b = createBuffer();
    glNamedBufferStorage(b.id(), GLsizeiptr(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glObjectLabel(GL_BUFFER, b.id(), -1, label);
    counter += bytes;
    return b;
}

} // namespace

PlayResult<Done> ShadowResources::ensure(uint32_t res, uint32_t layerCount, bool sdsm, bool withTranslucent,
                                         uint32_t divisor,
                                         const std::vector<ShadowCaster>& casters,
                                         const GpuScene& scene) {
    const bool resized = res != resolution || layerCount != layers;
    if (resized) {
        resolution = res;
        layers = layerCount;
        depthArray = createTexture(GL_TEXTURE_2D_ARRAY);
        {
            // 16 MiB per 2048² cascade: in 2 MiB pages where the driver keeps it in process
            // memory (upload_heap.h), instead of a first frame paying 4 KiB faults for it.
            UploadHeap heap(uint64_t(res) * res * sizeof(float) * layerCount);
            glTextureStorage3D(depthArray.id(), 1, GL_DEPTH_COMPONENT32F, GLsizei(res),
                               GLsizei(res), GLsizei(layerCount));
        }
        glObjectLabel(GL_TEXTURE, depthArray.id(), -1, "shadow cascades");
        // Comparison with bilinear weights: hardware 2x2 PCF per lookup.
        glTextureParameteri(depthArray.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(depthArray.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(depthArray.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTextureParameteri(depthArray.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        // Outside the map is lit: lookups past the edge compare against the far plane.
        const float one[4] = {1, 1, 1, 1};
        glTextureParameteri(depthArray.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
        glTextureParameteri(depthArray.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
        glTextureParameterfv(depthArray.id(), GL_TEXTURE_BORDER_COLOR, one);
        GLuint view = 0;
        glGenTextures(1, &view);
        glTextureView(view, GL_TEXTURE_2D_ARRAY, depthArray.id(), GL_DEPTH_COMPONENT32F, 0, 1, 0,
                      layerCount);
        depthView = GlHandle(GlKind::Texture, view);
        glTextureParameteri(view, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(view, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTextureParameteri(view, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
        glTextureParameteri(view, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
        glTextureParameterfv(view, GL_TEXTURE_BORDER_COLOR, one);
        layeredFb = createFramebuffer();
        glNamedFramebufferTexture(layeredFb.id(), GL_DEPTH_ATTACHMENT, depthArray.id(), 0);
        glNamedFramebufferDrawBuffer(layeredFb.id(), GL_NONE);
        layerFbs.clear();
        for (uint32_t l = 0; l < layerCount; ++l) {
            GlHandle fb = createFramebuffer();
            glNamedFramebufferTextureLayer(fb.id(), GL_DEPTH_ATTACHMENT, depthArray.id(), 0, GLint(l));
            glNamedFramebufferDrawBuffer(fb.id(), GL_NONE);
            layerFbs.push_back(std::move(fb));
        }
        mapBytes = uint64_t(res) * res * layerCount * 4;
    }
    if (resized || withTranslucent != bool(translucent) || (withTranslucent && divisor != translucentDivisor)) {
        // At 1/divisor of the map's side: clearing them every frame costs their bytes, and at
        // full size they would outweigh the depths twice (docs/PLAYER.md "Light through glass").
        translucent = {};
        translucentDivisor = divisor;
        const uint32_t side = std::max(res / divisor, 1u);
        if (withTranslucent) translucent.create(side, side, layerCount, "shadow cascades");
        // Framebuffers of their own, colour only: the opaque round keeps its depth-only targets,
        // and the blended round tests the depths in its fragment shader (shadow.frag), since
        // attachments of different sizes cannot share a framebuffer.
        translucentLayeredFb = {};
        translucentLayerFbs.clear();
        if (withTranslucent) {
            translucentLayeredFb = createFramebuffer();
            attachTranslucentMaps(translucentLayeredFb.id(), translucent, -1);
            for (uint32_t l = 0; l < layerCount; ++l) {
                GlHandle fb = createFramebuffer();
                attachTranslucentMaps(fb.id(), translucent, int(l));
                translucentLayerFbs.push_back(std::move(fb));
            }
        }
    }
    if (!sdsm) {
        for (GlHandle* h : {&sdsmState, &sdsmBlock, &sdsmMasks, &sdsmCommands,
                            &sdsmReduce, &sdsmPartition, &sdsmBounds, &sdsmFinalize, &sdsmCull})
            h->reset();
        sdsmCasterCapacity = 0;
        bufferBytes = 0;
        return Done{};
    }
    if (!sdsmReduce) {
        struct Stage {
            GlHandle* program;
            std::string_view define;
        } stages[] = {{&sdsmReduce, "SDSM_REDUCE"},     {&sdsmPartition, "SDSM_PARTITION"},
                      {&sdsmBounds, "SDSM_BOUNDS"},     {&sdsmFinalize, "SDSM_FINALIZE"},
                      {&sdsmCull, "SDSM_CULL"}};
        for (Stage& st : stages) {
            auto p = compileEmbeddedCompute("sdsm.comp", std::span(&st.define, 1));
            if (!p) return p.error();
            *st.program = std::move(*p);
        }
    }
    uint32_t casterCount = uint32_t(std::max<size_t>(casters.size(), 1));
    if (!sdsmState || casterCount > sdsmCasterCapacity) {
        bufferBytes = 0;
        sdsmCasterCapacity = casterCount;
        sdsmState = buffer(sizeof(SdsmState), "sdsm state", bufferBytes);
        sdsmBlock = buffer(sizeof(ShadowBlock), "sdsm shadow block", bufferBytes);
        sdsmMasks = buffer(casterCount * 4, "sdsm caster masks", bufferBytes);
        sdsmCommands = buffer(size_t(casterCount) * (kMaxCascades + 1) * kIndirectCommandBytes,
                              "sdsm shadow draws", bufferBytes);
    }
    (void)scene;
    return Done{};
}

} // namespace pnb::player
