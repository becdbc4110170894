// gi.technique = probes with gi.bounces > 1 (gi.h): light after more than one diffuse bounce, as
// irradiance-field methods (DDGI) gather it: the probes read their own previous irradiance where
// their rays hit. After the gather of the VPLs' one bounce (V_1 = G), each further pass computes
// V_k+1 = G + B(V_k): the gather G kept in `gathered`, plus, per probe, 8 x 8 directions walked
// through the occupancy grid to the first solid voxel, the previous volume's irradiance on the
// face entered, times the voxel's albedo over pi, projected onto the probe's L1 SH
// (gi_probe_gather.comp, BOUNCE).
// gi.bounces = N runs N - 1 such passes in the frame the probes are gathered in; with
// gi.probe_cache nothing runs again until an input changes (gi.bounces is one of them).
// Why this design: it reuses what the probes already have (occupancy grid, volume format,
// look-up), adds one albedo volume (R32UI sums, 4 texels a voxel) and six small ones, and costs
// a walk of 64 rays per probe per bounce only when the probes are updated.
#include <array>
#include <string_view>
#include <vector>

#include "frame/frame_context.h"
#include "gi/gi.h"
#include "gl/program_compile.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

PlayResult<uint64_t> ensureGiBounce(GiResources& r, const RenderSettings& s) {
    if (s.giBounces <= 1 || r.technique != GiTechnique::Probes) {
        if (r.albedoVoxels) r.voxelVersion = ~0ull; // the grid is drawn again without albedo
        r.albedoVoxels = {};
        r.voxelizeAlbedo = {};
        r.bounceGather = {};
        for (GlHandle& v : r.previous) v = {};
        for (GlHandle& v : r.gathered) v = {};
        r.albedoSide = r.previousCells = 0;
        return uint64_t(0);
    }
    if (!r.voxelizeAlbedo) {
        const std::string_view define = "ALBEDO";
        auto p = compileEmbeddedProgram("gi_voxelize.vert", "gi_voxelize.frag", std::span(&define, 1));
        if (!p) return p.error();
        r.voxelizeAlbedo = std::move(*p);
    }
    if (!r.bounceGather || r.bounceVisibility != s.giProbeVisibility || r.bounceGlass != r.glass) {
        std::vector<std::string_view> defines = {"BOUNCE"};
        if (s.giProbeVisibility == ProbeVisibility::Exact) defines.push_back("EXACT_VISIBILITY");
        if (r.glass) defines.push_back("TRANSMITTANCE");
        auto p = compileEmbeddedCompute("gi_probe_gather.comp", defines);
        if (!p) return p.error();
        r.bounceGather = std::move(*p);
        r.bounceVisibility = s.giProbeVisibility;
        r.bounceGlass = r.glass;
    }
    if (r.albedoSide != r.voxelSide) {
        r.albedoSide = r.voxelSide;
        r.albedoVoxels = createTexture(GL_TEXTURE_3D);
        const GLsizei side = GLsizei(r.voxelSide);
        // Per voxel four R32UI texels along x: the fixed-point sums of r, g, b and the fragments'
        // count (gi_voxelize.frag, ALBEDO).
        glTextureStorage3D(r.albedoVoxels.id(), 1, GL_R32UI, 4 * side, side, side);
        glTextureParameteri(r.albedoVoxels.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(r.albedoVoxels.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glObjectLabel(GL_TEXTURE, r.albedoVoxels.id(), -1, "gi probe albedo voxels");
        r.voxelVersion = ~0ull; // drawn with the occupancy grid
    }
    if (r.previousCells != r.cells) {
        r.previousCells = r.cells;
        const char* names[2][3] = {{"gi probe previous r", "gi probe previous g", "gi probe previous b"},
                                   {"gi probe gathered r", "gi probe gathered g", "gi probe gathered b"}};
        for (size_t ch = 0; ch < 3; ++ch) {
            r.previous[ch] = giVolume(r.cells, r.cells, names[0][ch]);
            r.gathered[ch] = giVolume(r.cells, r.cells, names[1][ch]);
        }
    }
    const uint64_t side = r.voxelSide, cells = r.cells;
    return side * side * side * 16 + cells * cells * cells * 6 * 8;
}

void runGiProbeBounces(FrameContext& ctx, GiContext& gi, const glm::vec3& origin, float spacing) {
    GiResources& r = gi.resources;
    const uint32_t bounces = ctx.settings.giBounces;
    if (!r.bounceGather || bounces <= 1) return;
    const GLuint p = r.bounceGather.id();
    bindProbeGatherInputs(r, p, origin, spacing);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_GI_VPLS, r.vpls.id());
    glBindTextureUnit(7, r.albedoVoxels.id());
    const GLsizei n = GLsizei(r.cells);
    auto copy = [n](const GlHandle& from, const GlHandle& to) {
        glCopyImageSubData(from.id(), GL_TEXTURE_3D, 0, 0, 0, 0, to.id(), GL_TEXTURE_3D, 0, 0, 0, 0, n, n, n);
    };
    for (size_t ch = 0; ch < 3; ++ch) {
        copy(r.sum[ch], r.gathered[ch]); // the VPLs' one bounce: every pass adds to it
        glBindTextureUnit(GLuint(8 + ch), r.gathered[ch].id());
    }
    glUseProgram(p);
    for (uint32_t pass = 1; pass < bounces; ++pass) {
        // The volume lighting reads becomes the previous one; the pass writes the next into it.
        for (size_t ch = 0; ch < 3; ++ch) copy(r.sum[ch], r.previous[ch]);
        for (GLuint ch = 0; ch < 3; ++ch) {
            glBindTextureUnit(4 + ch, r.previous[ch].id());
            glBindImageTexture(ch, r.sum[ch].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        }
        glDispatchCompute((r.cells + 7) / 8, r.cells, r.cells); // as the gather: 8 probes a group
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                        GL_TEXTURE_UPDATE_BARRIER_BIT);
    }
    for (GLuint unit = 4; unit < 11; ++unit) glBindTextureUnit(unit, 0);
    glUseProgram(0);
}

} // namespace pnb::player
