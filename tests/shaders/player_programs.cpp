// The player's programs, mirrored from their call sites (player_programs.h says why a table).

#include "player_programs.h"

namespace pnb::test {

namespace {

PlayerProgram graphics(const std::string& vert, const std::string& frag) {
    // compileEmbeddedProgram labels a program by its fragment file.
    return {frag + " (built in)", {{vert}, {frag}}, {}};
}

PlayerProgram compute(const std::string& file, std::vector<std::string> defines) {
    // compileEmbeddedCompute's label: the file, then each define.
    std::string label = file;
    for (const std::string& d : defines) label += " " + d;
    return {label + " (built in)", {{file}}, std::move(defines)};
}

} // namespace

std::vector<PlayerProgram> playerPrograms() {
    std::vector<PlayerProgram> out;
    // renderer.cpp, Renderer::setSettings: the built-in passes a setting switches on.
    for (const char* frag : {"fxaa.frag", "background.frag", "shadow_debug.frag", "debug_view.frag"})
        out.push_back(graphics("fullscreen.vert", frag));
    for (const char* frag : {"depth_only.frag", "flat.frag"}) out.push_back(graphics("flat.vert", frag));
    // gi_resources.cpp: the probe technique's voxelisation.
    out.push_back(graphics("flat.vert", "gi_voxelize.frag"));
    // pass_light_clusters.cpp.
    out.push_back(compute("light_clusters.comp", {}));
    // shadow_resources.cpp: one SDSM program per stage define.
    for (const char* stage : {"SDSM_REDUCE", "SDSM_PARTITION", "SDSM_BOUNDS", "SDSM_FINALIZE", "SDSM_CULL"})
        out.push_back(compute("sdsm.comp", {stage}));
    // gi_resources.cpp, compileStages: FLOAT_ATOMICS (gi.atomics = float) comes first, then the
    // stage's own define.
    const std::pair<const char*, const char*> lpv[] = {
        {"lpv_inject.comp", "SOURCE_RSM"},          {"lpv_inject.comp", "SOURCE_CAMERA"},
        {"lpv_resolve.comp", "RESOLVE_LIGHT"},      {"lpv_resolve.comp", "RESOLVE_GEOMETRY"},
        {"lpv_resolve.comp", "RESOLVE_TRANSMITTANCE"}, {"lpv_propagate.comp", "PLAIN"},
        {"lpv_propagate.comp", "OCCLUSION"}};
    for (bool floatAtomics : {false, true})
        for (const auto& [file, stage] : lpv) {
            std::vector<std::string> defines;
            if (floatAtomics) defines.push_back("FLOAT_ATOMICS");
            defines.push_back(stage);
            out.push_back(compute(file, defines));
        }
    // gi_resources.cpp: the probes' gather (depth-map or exact visibility), their depth maps,
    // sky visibility, and the VPL clustering.
    out.push_back(compute("gi_probe_gather.comp", {}));
    for (const char* define : {"EXACT_VISIBILITY", "PROBE_DEPTH", "SKY_VISIBILITY"})
        out.push_back(compute("gi_probe_gather.comp", {define}));
    out.push_back(compute("gi_vpls.comp", {}));
    // gi_resources.cpp, with translucent casters (issue 43): every probe variant with
    // TRANSMITTANCE after its own define, and the panes' program for the RSM and the grid.
    for (const char* define : {"", "EXACT_VISIBILITY", "PROBE_DEPTH", "SKY_VISIBILITY"}) {
        std::vector<std::string> defines;
        if (*define) defines.push_back(define);
        defines.push_back("TRANSMITTANCE");
        out.push_back(compute("gi_probe_gather.comp", defines));
    }
    out.push_back(graphics("gi_transmit.vert", "gi_transmit.frag"));
    PlayerProgram voxelize = graphics("gi_transmit.vert", "gi_transmit.frag");
    voxelize.defines = {"VOXELIZE"};
    out.push_back(voxelize);
    // pass_gi_bounce.cpp (gi.bounces > 1): the voxelisation with albedo, and the bounce gather
    // with either visibility, with and without glass.
    PlayerProgram albedo = graphics("gi_voxelize.vert", "gi_voxelize.frag");
    albedo.defines = {"ALBEDO"};
    out.push_back(albedo);
    for (bool exact : {false, true})
        for (bool glass : {false, true}) {
            std::vector<std::string> defines = {"BOUNCE"};
            if (exact) defines.push_back("EXACT_VISIBILITY");
            if (glass) defines.push_back("TRANSMITTANCE");
            out.push_back(compute("gi_probe_gather.comp", defines));
        }
    return out;
}

PlayerProgram geometryLayerProgram(const std::string& shadowLabel,
                                   const std::vector<std::string>& shadowDefines) {
    PlayerProgram p;
    p.label = shadowLabel + " + shadow_layers.geom";
    p.stages = {{"shadow.vert", ShaderOrigin::Scene},
                {"shadow_layers.geom", ShaderOrigin::Player},
                {"shadow.frag", ShaderOrigin::Scene}};
    p.defines = shadowDefines;
    p.defines.push_back("LAYER_FROM_GEOMETRY");
    return p;
}

} // namespace pnb::test
