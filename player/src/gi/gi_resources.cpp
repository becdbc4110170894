// GI's GPU objects, created for the current gi.* sizes and dropped with GI (gi.h).
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "gi/gi.h"
#include "gl/program_compile.h"

namespace pnb::player {

GlHandle giVolume(uint32_t side, uint32_t depth, const char* label, GLenum format) {
    GlHandle t = createTexture(GL_TEXTURE_3D);
    glTextureStorage3D(t.id(), 1, format, GLsizei(side), GLsizei(side), GLsizei(depth));
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glTextureParameteri(t.id(), wrap, GL_CLAMP_TO_EDGE);
    glObjectLabel(GL_TEXTURE, t.id(), -1, label);
    return t;
}

namespace {

GlHandle texture2d(GLenum format, uint32_t size, const char* label) {
    GlHandle t = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), 1, format, GLsizei(size), GLsizei(size));
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glObjectLabel(GL_TEXTURE, t.id(), -1, label);
    return t;
}



// The probes' depth maps: a (16 + 2)^2 tile per probe, probes (x, y) side by side in layer z.
GlHandle depthAtlas(uint32_t probes, GLenum format = GL_R16F, const char* label = "gi probe depth maps") {
    GlHandle t = createTexture(GL_TEXTURE_2D_ARRAY);
    const GLsizei side = GLsizei(probes * 18);
    glTextureStorage3D(t.id(), 1, format, side, side, GLsizei(probes));
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T}) glTextureParameteri(t.id(), wrap, GL_CLAMP_TO_EDGE);
    glObjectLabel(GL_TEXTURE, t.id(), -1, label);
    return t;
}

GlHandle storage(uint64_t bytes, const char* label) {
    GlHandle b = createBuffer();
    glNamedBufferStorage(b.id(), GLsizeiptr(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glObjectLabel(GL_BUFFER, b.id(), -1, label);
    return b;
}

GlHandle voxelGrid(uint32_t side) {
    GlHandle t = createTexture(GL_TEXTURE_3D);
    glTextureStorage3D(t.id(), 1, GL_R8UI, GLsizei(side), GLsizei(side), GLsizei(side));
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glObjectLabel(GL_TEXTURE, t.id(), -1, "gi probe voxels");
    return t;
}

PlayResult<Done> compileStages(std::span<const std::pair<GlHandle*, std::pair<const char*, std::string_view>>> stages,
                               bool floatAtomics) {
    for (const auto& [program, what] : stages) {
        std::vector<std::string_view> defines;
        if (floatAtomics) defines.push_back("FLOAT_ATOMICS");
        if (!what.second.empty()) defines.push_back(what.second);
        auto p = compileEmbeddedCompute(what.first, defines);
        if (!p) return p.error();
        *program = std::move(*p);
    }
    return Done{};
}

// A gi_probe_gather.comp variant: `define` ("" for the gather itself), and TRANSMITTANCE with
// glass (the panes' transmittance grid along its rays).
PlayResult<GlHandle> compileProbeProgram(std::string_view define, bool glass) {
    std::vector<std::string_view> defines;
    if (!define.empty()) defines.push_back(define);
    if (glass) defines.push_back("TRANSMITTANCE");
    return compileEmbeddedCompute("gi_probe_gather.comp", defines);
}

// LPV's glass cells (one RGBA8 volume like the LPV's, its attachment-less framebuffer) and the
// propagation variants reading them, or none of it without glass. Returns their bytes.
PlayResult<uint64_t> ensureLpvGlass(GiResources& r, bool lpv) {
    if (!lpv) {
        r.lpvGlass = {};
        r.lpvGlassFb = {};
        r.propagateGlass = {};
        r.propagateOccludedGlass = {};
        return uint64_t(0);
    }
    if (!r.propagateGlass) {
        const std::pair<GlHandle*, std::string_view> variants[] = {{&r.propagateGlass, "PLAIN"},
                                                                   {&r.propagateOccludedGlass, "OCCLUSION"}};
        for (const auto& [program, define] : variants) {
            const std::string_view defines[] = {define, "GLASS"};
            auto p = compileEmbeddedCompute("lpv_propagate.comp", defines);
            if (!p) return p.error();
            *program = std::move(*p);
        }
    }
    if (!r.lpvGlass) {
        r.lpvGlass = giVolume(r.cells, r.cells * r.cascades, "lpv glass cells", GL_RGBA8);
        r.lpvGlassFb = createFramebuffer();
        glNamedFramebufferDrawBuffer(r.lpvGlassFb.id(), GL_NONE);
        r.lpvGlassVersion = ~0ull;
    }
    return uint64_t(r.cells) * r.cells * r.cells * r.cascades * 4;
}

// The translucent casters' objects (issue 43), or none while no BLEND material casts shadows:
// the RSM's multiplying program always; probes: the transmittance grid and its voxelisation, and
// with depth maps each probe's transmittance map; LPV: the cascades' glass cells and their
// voxelisation. Runs after the sizes are set (a size change dropped the grids). Returns their
// bytes.
PlayResult<uint64_t> ensureGlass(GiResources& r, const RenderSettings& s) {
    const bool probes = r.glass && r.technique == GiTechnique::Probes;
    const bool lpv = r.glass && r.technique == GiTechnique::Lpv;
    const bool depthMaps = probes && s.giProbeVisibility == ProbeVisibility::Depth;
    if (!r.glass) r.transmitRsm = {};
    if (!probes) r.transmitVoxels = {};
    if (!probes && !lpv) r.transmitVoxelize = {};
    auto lpvBytes = ensureLpvGlass(r, lpv);
    if (!lpvBytes) return lpvBytes.error();
    if (!depthMaps) r.probeTransmit = {};
    if (!r.glass) return uint64_t(0);
    if (!r.transmitRsm) {
        auto p = compileEmbeddedProgram("gi_transmit.vert", "gi_transmit.frag");
        if (!p) return p.error();
        r.transmitRsm = std::move(*p);
    }
    if ((probes || lpv) && !r.transmitVoxelize) {
        std::string_view define = "VOXELIZE";
        auto p = compileEmbeddedProgram("gi_transmit.vert", "gi_transmit.frag", std::span(&define, 1));
        if (!p) return p.error();
        r.transmitVoxelize = std::move(*p);
    }
    const uint64_t side = r.voxelSide, probeCount = uint64_t(r.cells) * r.cells * r.cells;
    if (probes && !r.transmitVoxels) {
        r.transmitVoxels = createTexture(GL_TEXTURE_3D);
        glTextureStorage3D(r.transmitVoxels.id(), 1, GL_RGBA8, GLsizei(side), GLsizei(side), GLsizei(side));
        glTextureParameteri(r.transmitVoxels.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(r.transmitVoxels.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glObjectLabel(GL_TEXTURE, r.transmitVoxels.id(), -1, "gi probe transmittance voxels");
        r.voxelVersion = ~0ull;
    }
    if (depthMaps && !r.probeTransmit) {
        r.probeTransmit = depthAtlas(r.cells, GL_RGBA8, "gi probe transmittance maps");
        r.depthCurrent = false;
    }
    return (probes ? side * side * side * 4 : 0) + (depthMaps ? probeCount * 18 * 18 * 4 : 0) + *lpvBytes;
}

} // namespace

PlayResult<Done> GiResources::ensure(const RenderSettings& s, uint32_t cascadeCount, bool glassWanted) {
    const GiTechnique want = s.giTechnique;
    const uint32_t cellCount = want == GiTechnique::Probes ? s.giProbeCells : s.giCells;
    const bool useFloatAtomics = want == GiTechnique::Lpv && s.giAtomics == GiAtomics::Float;
    if (want != technique) {
        *this = GiResources{}; // the other technique's objects go
        technique = want;
    }
    if (glassWanted != glass) {
        // The grids and what was traced through them are drawn again with (or without) glass;
        // the sky visibility changes layout (one SH or one per colour).
        glass = glassWanted;
        voxelVersion = ~0ull;
        skyVisibility = {};
        gatherProbes = {}; // these three are compiled again with(out) TRANSMITTANCE
        traceDepth = {};
        traceSky = {};
    }
    const uint32_t rsm = s.giRsmResolution;
    if (want == GiTechnique::Lpv && (useFloatAtomics != floatAtomics || !injectRsm)) {
        floatAtomics = useFloatAtomics;
        const std::pair<GlHandle*, std::pair<const char*, std::string_view>> stages[] = {
            {&injectRsm, {"lpv_inject.comp", "SOURCE_RSM"}},
            {&injectCamera, {"lpv_inject.comp", "SOURCE_CAMERA"}},
            {&resolveLight, {"lpv_resolve.comp", "RESOLVE_LIGHT"}},
            {&resolveGeometry, {"lpv_resolve.comp", "RESOLVE_GEOMETRY"}},
            {&resolveTransmittance, {"lpv_resolve.comp", "RESOLVE_TRANSMITTANCE"}},
            {&propagate, {"lpv_propagate.comp", "PLAIN"}},
            {&propagateOccluded, {"lpv_propagate.comp", "OCCLUSION"}}};
        if (auto ok = compileStages(stages, floatAtomics); !ok) return ok.error();
    }
    const bool depthMaps = want == GiTechnique::Probes && s.giProbeVisibility == ProbeVisibility::Depth;
    if (want == GiTechnique::Probes && (!gatherProbes || gatherVisibility != s.giProbeVisibility)) {
        gatherVisibility = s.giProbeVisibility;
        auto p = compileProbeProgram(depthMaps ? "" : "EXACT_VISIBILITY", glass);
        if (!p) return p.error();
        gatherProbes = std::move(*p);
    }
    if (!depthMaps) {
        probeDepth = {};
        probeNeeded = {};
        traceDepth = {};
    } else if (!traceDepth) {
        auto p = compileProbeProgram("PROBE_DEPTH", glass);
        if (!p) return p.error();
        traceDepth = std::move(*p);
        depthCurrent = false;
    }
    if (want == GiTechnique::Probes && !clusterVpls) {
        const std::pair<GlHandle*, std::pair<const char*, std::string_view>> stages[] = {
            {&clusterVpls, {"gi_vpls.comp", ""}}};
        if (auto ok = compileStages(stages, false); !ok) return ok.error();
        auto v = compileEmbeddedProgram("flat.vert", "gi_voxelize.frag");
        if (!v) return v.error();
        voxelize = std::move(*v);
        voxelFb = createFramebuffer();
        glNamedFramebufferDrawBuffer(voxelFb.id(), GL_NONE);
    }
    // The probes' sky visibility exists only while ibl.visibility asks for it.
    const bool sky = want == GiTechnique::Probes && resolvedSkyVisibility(s) == SkyVisibility::Probes;
    if (!sky) {
        skyVisibility = {};
        traceSky = {};
    } else if (!traceSky) {
        auto p = compileProbeProgram("SKY_VISIBILITY", glass);
        if (!p) return p.error();
        traceSky = std::move(*p);
    }
    if (rsm != rsmResolution) {
        rsmResolution = rsm;
        rsmColor = texture2d(GL_SRGB8_ALPHA8, rsm, "rsm base colour");
        rsmNormal = texture2d(GL_RGBA16, rsm, "rsm normal+material");
        rsmDepth = texture2d(GL_DEPTH_COMPONENT32F, rsm, "rsm depth");
        rsmFb = createFramebuffer();
        glNamedFramebufferTexture(rsmFb.id(), GL_COLOR_ATTACHMENT0, rsmColor.id(), 0);
        glNamedFramebufferTexture(rsmFb.id(), GL_COLOR_ATTACHMENT1, rsmNormal.id(), 0);
        glNamedFramebufferTexture(rsmFb.id(), GL_DEPTH_ATTACHMENT, rsmDepth.id(), 0);
        // gbuffer.frag's third output (emissive) has no attachment: discarded.
        const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_NONE};
        glNamedFramebufferDrawBuffers(rsmFb.id(), 3, buffers);
    }
    if (cellCount != cells || cascadeCount != cascades) {
        cells = cellCount;
        cascades = cascadeCount;
        const uint32_t depth = cells * cascades, corners = cells + 1;
        const char* names[3][3] = {{"lpv source r", "lpv source g", "lpv source b"},
                                   {"lpv next r", "lpv next g", "lpv next b"},
                                   {"gi sum r", "gi sum g", "gi sum b"}};
        for (int ch = 0; ch < 3; ++ch) sum[size_t(ch)] = giVolume(cells, depth, names[2][ch]);
        skyVisibility = {};
        probeDepth = {};
        probeNeeded = {};
        probeTransmit = {};
        if (want == GiTechnique::Lpv) {
            for (int ch = 0; ch < 3; ++ch) {
                source[size_t(ch)] = giVolume(cells, depth, names[0][ch]);
                next[size_t(ch)] = giVolume(cells, depth, names[1][ch]);
            }
            geometry = giVolume(corners, corners * cascades, "lpv geometry");
            transmittance[0] = giVolume(cells, depth, "lpv transmittance -x +x -y +y", GL_RGBA8);
            transmittance[1] = giVolume(cells, depth, "lpv transmittance -z +z", GL_RGBA8);
            lpvGlass = {}; // ensureGlass makes it again at the new size, with glass
            uint64_t cellsTotal = uint64_t(cells) * cells * depth;
            uint64_t cornersTotal = uint64_t(corners) * corners * corners * cascades;
            lightAccumulation = storage(cellsTotal * 12 * 4, "lpv light accumulation");
            geometryAccumulation = storage(cornersTotal * 2 * 4 * 4, "lpv geometry accumulation");
        }
    }
    const uint64_t cellsTotal = uint64_t(cells) * cells * cells * cascades;
    const uint64_t rsmBytes = uint64_t(rsmResolution) * rsmResolution * (4 + 8 + 4);
    if (want == GiTechnique::Probes) {
        if (s.giVoxels != voxelSide) {
            voxelSide = s.giVoxels;
            voxels = voxelGrid(voxelSide);
            transmitVoxels = {};
            voxelVersion = ~0ull;
        }
        if (s.giVpls != vplSide) {
            vplSide = s.giVpls;
            vpls = storage(uint64_t(vplSide) * vplSide * 48, "gi probe vpls");
        }
        if (sky && !skyVisibility) {
            // With glass, one L1 SH per colour (red, green, blue stacked along z): what a probe
            // sees of the sky through panes is tinted. sky_visibility.glsl tells by the depth.
            skyVisibility = giVolume(cells, glass ? 3 * cells : cells, "gi probe sky visibility");
            skyCurrent = false;
        }
        if (depthMaps && !probeDepth) {
            probeDepth = depthAtlas(cells);
            probeNeeded = storage(cellsTotal * 4, "gi probes needed");
            depthCurrent = false;
        }
        auto glassBytes = ensureGlass(*this, s);
        if (!glassBytes) return glassBytes.error();
        auto bounceBytes = ensureGiBounce(*this, s);
        if (!bounceBytes) return bounceBytes.error();
        const uint64_t skyVolumes = sky ? (glass ? 3 : 1) : 0;
        bytes = rsmBytes + cellsTotal * (3 + skyVolumes) * 8 + (depthMaps ? cellsTotal * (18 * 18 * 2 + 4) : 0) +
                uint64_t(voxelSide) * voxelSide * voxelSide + uint64_t(vplSide) * vplSide * 48 + *glassBytes +
                *bounceBytes;
        return Done{};
    }
    auto glassBytes = ensureGlass(*this, s);
    if (!glassBytes) return glassBytes.error();
    const uint64_t cornersTotal = uint64_t(cells + 1) * (cells + 1) * (cells + 1) * cascades;
    bytes = rsmBytes + cellsTotal * (9 * 8 + 2 * 4) + cornersTotal * 8 + cellsTotal * 12 * 4 +
            cornersTotal * 2 * 4 * 4 + *glassBytes;
    return Done{};
}

} // namespace pnb::player
