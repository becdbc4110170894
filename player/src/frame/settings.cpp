// The render-setting table: one row per key; parsing and printing are derived from the row.
#include "pnb_player/settings.h"

#include <algorithm>
#include <charconv>
#include <span>
#include <type_traits>
#include <cmath>
#include <cstdio>
#include <variant>

namespace pnb::player {

namespace {

struct FloatField {
    float RenderSettings::*member;
    float min, max;
};
struct UIntField {
    uint32_t RenderSettings::*member;
    uint32_t min, max;
};
struct IntField {
    int32_t RenderSettings::*member;
    int32_t min, max;
};
struct BoolField {
    bool RenderSettings::*member;
};
// One of a list of names, stored as an enum.
struct EnumField {
    std::span<const std::string_view> names;
    int (*get)(const RenderSettings&);
    void (*set)(RenderSettings&, int);
};
// Free text, checked by the consumer (anim.clip: an index or a name the scene decides on).
struct StringField {
    std::string RenderSettings::*member;
};
using Field = std::variant<FloatField, UIntField, IntField, BoolField, EnumField, StringField>;

template <auto Member>
EnumField enumField(std::span<const std::string_view> names) {
    return {names, [](const RenderSettings& s) { return int(s.*Member); },
            [](RenderSettings& s, int v) {
                s.*Member = std::remove_reference_t<decltype(s.*Member)>(v);
            }};
}

struct Row {
    SettingInfo info;
    Field field;
};

constexpr std::string_view kDebugViewNames[] = {"none", "basecolor", "alpha", "normal",
                                                "roughness", "metallic", "occlusion", "emissive",
                                                "depth", "layer", "overdraw", "cascades",
                                                "shadowmap", "histogram", "gi_indirect", "gi_rsm",
                                                "gi_volume", "lod", "light_clusters"};
static_assert(std::size(kDebugViewNames) == size_t(DebugView::Count));
constexpr std::string_view kTechniqueNames[] = {"off", "single", "lispsm", "pssm", "sdsm"};
constexpr std::string_view kFitNames[] = {"sphere", "tight"};
constexpr std::string_view kRenderNames[] = {"layered", "multipass"};
constexpr std::string_view kLayerSourceNames[] = {"auto", "vertex", "geometry"};
constexpr std::string_view kFilterNames[] = {"hardware", "poisson", "pcss"};
constexpr std::string_view kTranslucentDivisorNames[] = {"1", "2", "4", "8"}; // 2^index
constexpr std::string_view kSelectNames[] = {"depth", "bounds"};
constexpr std::string_view kPartitionNames[] = {"log", "quantile"};
constexpr std::string_view kAtomicsNames[] = {"fixed", "float"};
constexpr std::string_view kGiTechniqueNames[] = {"lpv", "probes"};
constexpr std::string_view kProbeVisibilityNames[] = {"depth", "exact"};
constexpr std::string_view kLightCullingNames[] = {"auto", "clusters", "off"};
constexpr std::string_view kSkyVisibilityNames[] = {"none", "screen", "height", "volume", "probes", "auto"};

using S = RenderSettings;

// Every setting, once: its key, its range as text, its help, and the field it sets with its
// bounds: parsing (--set, a container's settings) and listing (--list-settings) read it.
const Row kRows[] = {
    {{"lighting.exposure", "float 1e-6..1e6", "HDR scale applied before tone mapping"},
     FloatField{&S::exposure, 1e-6f, 1e6f}},
    {{"lighting.ambient", "float 0..1e6",
      "uniform ambient radiance, multiplied by base colour and occlusion"},
     FloatField{&S::ambient, 0.0f, 1e6f}},
    {{"lighting.sun_turn_deg", "float -360..360",
      "directional lights turned about +Y (seen from above: counter-clockwise), their shadows "
      "and GI with them: a moving sun without reconverting; the environment stays "
      "(ibl.rotation_deg), and the ray-traced truths keep the container's sun, so the "
      "metrics refuse a turned one"},
     FloatField{&S::sunTurnDeg, -360.0f, 360.0f}},
    {{"post.fxaa", "bool", "FXAA edge anti-aliasing after tone mapping"},
     BoolField{&S::fxaa}},
    {{"cull.frustum", "bool", "skip draws whose world bounds are outside the view frustum"},
     BoolField{&S::frustumCulling}},
    {{"camera.near", "float 0..1e9", "near plane in scene units; 0 = the container camera's"},
     FloatField{&S::nearPlane, 0.0f, 1e9f}},
    {{"camera.far", "float >= -1",
      "far plane in scene units; 0 = infinite (reversed-Z), -1 = the container camera's"},
     FloatField{&S::farPlane, -1.0f, 1e30f}},
    {{"lights.culling", "auto|clusters|off",
      "which lights each pixel shades: those of its cluster (a screen tile x a depth slice; "
      "the cluster pass runs each frame), every light (off), or auto: clusters from "
      "lights.cluster_min point and spot lights on. The image is the same either way"},
     enumField<&S::lightCulling>(kLightCullingNames)},
    {{"lights.cluster_min", "int 1..65536",
      "lights.culling=auto: the number of point and spot lights from which clusters pay "
      "(measured: docs/PLAYER.md \"Many lights\")"},
     UIntField{&S::lightClusterMin, 1, 65536}},
    {{"lights.tile_px", "int 8..256", "cluster tile side in pixels"},
     UIntField{&S::lightTilePx, 8, 256}},
    {{"lights.slices", "int 1..64",
      "cluster depth slices, exponential from the near plane to the farthest light's reach"},
     UIntField{&S::lightSlices, 1, 64}},
    {{"shadows.technique", "off|single|lispsm|pssm|sdsm",
      "sun shadows: none, one map over the scene, LiSPSM, practical-split cascades, or "
      "cascades fitted on the GPU to this frame's depth (SDSM)"},
     enumField<&S::shadowTechnique>(kTechniqueNames)},
    {{"shadows.cascades", "int 1..8", "cascade count (pssm, sdsm)"},
     UIntField{&S::shadowCascades, 1, 8}},
    {{"shadows.resolution", "int 64..8192", "width and height of each shadow map in texels"},
     UIntField{&S::shadowResolution, 64, 8192}},
    {{"shadows.lambda", "float 0..1",
      "pssm split scheme: 0 uniform, 1 logarithmic (C_i = l*n*(f/n)^(i/m) + (1-l)*(n+(f-n)*i/m))"},
     FloatField{&S::shadowLambda, 0.0f, 1.0f}},
    {{"shadows.distance", "float >= 0",
      "farthest view depth that gets shadows; 0 = the far side of the scene bounds"},
     FloatField{&S::shadowDistance, 0.0f, 1e30f}},
    {{"shadows.fit", "sphere|tight",
      "cascade extents: bounding sphere with texel snapping (stable) or tight rectangle (sharper, swims)"},
     enumField<&S::shadowFit>(kFitNames)},
    {{"shadows.render", "layered|multipass",
      "all cascades in one pass (gl_Layer from instancing) or one pass per cascade"},
     enumField<&S::shadowRender>(kRenderNames)},
    {{"shadows.layer_from", "auto|vertex|geometry",
      "layered pass: gl_Layer from the vertex shader (ARB_shader_viewport_layer_array) or "
      "from a geometry shader; auto = vertex where the extension exists"},
     enumField<&S::shadowLayerSource>(kLayerSourceNames)},
    {{"shadows.filter", "hardware|poisson|pcss",
      "2x2 hardware PCF, rotated Poisson-disk PCF, or PCSS (contact-hardening)"},
     enumField<&S::shadowFilter>(kFilterNames)},
    {{"shadows.taps", "int 1..64", "Poisson/PCSS filter taps"},
     UIntField{&S::shadowTaps, 1, 64}},
    {{"shadows.radius", "float 0..64", "Poisson filter radius in texels"},
     FloatField{&S::shadowRadius, 0.0f, 64.0f}},
    {{"shadows.light_size", "float 0..20",
      "PCSS: angular diameter of the light in degrees (the sun: 0.53)"},
     FloatField{&S::shadowLightSize, 0.0f, 20.0f}},
    {{"shadows.select", "depth|bounds",
      "cascade selection: by view depth, or the first cascade whose map contains the point"},
     enumField<&S::shadowSelect>(kSelectNames)},
    {{"shadows.blend", "float 0..0.5",
      "band at the end of each cascade, as a fraction of its range, blended with the next"},
     FloatField{&S::shadowBlend, 0.0f, 0.5f}},
    {{"shadows.normal_offset", "float 0..16",
      "receiver offset along the normal, in texels of the cascade read"},
     FloatField{&S::shadowNormalOffset, 0.0f, 16.0f}},
    {{"shadows.slope_bias", "float 0..16",
      "receiver offset toward the light, in texels times tan(angle to the light), capped at 10"},
     FloatField{&S::shadowSlopeBias, 0.0f, 16.0f}},
    {{"shadows.sdsm_partition", "log|quantile",
      "sdsm: logarithmic splits over the tight depth range, or equal sample counts per cascade "
      "(seed 000's histogram variant, weighted by the pssm scheme)"},
     enumField<&S::sdsmPartition>(kPartitionNames)},
    {{"shadows.local", "bool",
      "point and spot light shadows: a depth atlas with a tile per spot light and six per point "
      "light (casts_shadows lights in view), read with the sun's filter and offsets"},
     BoolField{&S::shadowLocal}},
    {{"shadows.local_lights", "int 0..64",
      "the most point and spot lights shadowed in a frame: the largest on screen"},
     UIntField{&S::shadowLocalLights, 0, 64}},
    {{"shadows.local_atlas", "int 256..8192",
      "side of the local-light shadow atlas in texels (its memory: side^2 x 4 bytes); tiles "
      "follow each light's size on screen and are halved together when they do not fit"},
     UIntField{&S::shadowLocalAtlas, 256, 8192}},
    {{"shadows.local_max_tile", "int 32..8192", "largest local-light shadow tile side, texels"},
     UIntField{&S::shadowLocalMaxTile, 32, 8192}},
    {{"shadows.local_cache", "bool",
      "draw a local-light tile again only when its light, its place in the atlas or the "
      "casters change (its depths do not depend on the camera); false: every frame"},
     BoolField{&S::shadowLocalCache}},
    {{"shadows.translucent", "bool",
      "blended (BLEND) materials that cast shadows let light through, tinted: T = base colour x "
      "(1 - alpha), into colour companions of the sun's maps and the local atlas; false: they "
      "cast nothing (no companions; for comparing the cost)"},
     BoolField{&S::shadowTranslucent}},
    {{"shadows.translucent_divisor", "1|2|4|8",
      "the colour companions' side is the map's divided by this: their memory and clearing "
      "fall with its square (x 1/16 at 4), their glass-shadow edges blur over as many texels"},
     enumField<&S::shadowTranslucentDivisorLog2>(kTranslucentDivisorNames)},
    {{"shadows.local_taps", "int 1..64",
      "local-light PCF taps over the shadows.radius disk (1: one 2x2 hardware-compared tap); "
      "a pixel may read many lights' tiles, so fewer than the sun's shadows.taps"},
     UIntField{&S::shadowLocalTaps, 1, 64}},
    {{"shadows.judged_light", "int -1..65535",
      "the light whose shadow --dump shadow and --shadow-metrics capture: -1 the sun, else an "
      "index into the container's lights (a point or spot light: its tiles' visibility)"},
     IntField{&S::shadowJudgedLight, -1, 65535}},
    {{"gi.enabled", "bool",
      "one-bounce indirect light from the sun: reflective shadow map, cascaded light "
      "propagation volumes (needs a container converted with GI: pnb-convert --gi)"},
     BoolField{&S::giEnabled}},
    {{"gi.technique", "lpv|probes",
      "lpv: light propagation volumes (cheap, diffuse, reaches a few cells); probes: a grid of "
      "irradiance probes gathering every clustered RSM light they see through an occupancy grid "
      "(gi.probe_cells, gi.voxels, gi.vpls; gi.cascades, cells, iterations, occlusion unused)"},
     enumField<&S::giTechnique>(kGiTechniqueNames)},
    {{"gi.cascades", "int 1..4", "nested propagation volumes, each twice the previous' cell"},
     UIntField{&S::giCascades, 1, 4}},
    {{"gi.cells", "int 8..128", "cells along each side of every cascade"},
     UIntField{&S::giCells, 8, 128}},
    {{"gi.cell_size", "float >= 0",
      "finest cascade's cell in scene units, all cascades following the camera; 0 = the outer "
      "cascade is the scene's bounding cube and the finer ones follow the camera"},
     FloatField{&S::giCellSize, 0.0f, 1e30f}},
    {{"gi.iterations", "int 0..64",
      "propagation steps (light travels one cell per step; with as many steps as cells it "
      "crosses a cascade)"},
     UIntField{&S::giIterations, 0, 64}},
    {{"gi.rsm_resolution", "int 16..2048",
      "reflective shadow map side: one virtual point light per texel, flux per texel area"},
     UIntField{&S::giRsmResolution, 16, 2048}},
    {{"gi.occlusion", "bool", "geometry volume blocks light during propagation"},
     BoolField{&S::giOcclusion}},
    {{"gi.camera_occlusion", "bool",
      "the geometry volume also holds what the camera's G-buffer sees (merged by max)"},
     BoolField{&S::giCameraOcclusion}},
    {{"gi.intensity", "float 0..1000", "scale of the indirect light (1 = physically based)"},
     FloatField{&S::giIntensity, 0.0f, 1000.0f}},
    {{"gi.atomics", "fixed|float",
      "injection accumulates in 32-bit fixed point (order-independent, deterministic) or with "
      "NV_shader_atomic_float float adds"},
     enumField<&S::giAtomics>(kAtomicsNames)},
    {{"gi.probe_cells", "int 4..64", "probes: probes along each side of the grid over the scene"},
     UIntField{&S::giProbeCells, 4, 64}},
    {{"gi.bounces", "int 1..16",
      "probes: diffuse bounces (1: the VPLs' light alone; N: N - 1 more gathers, each probe reading "
      "the previous irradiance where its rays hit, times the albedo there)"},
     UIntField{&S::giBounces, 1, 16}},
    {{"gi.probe_max_spacing", "float >= 0",
      "probes, with gi.cell_size 0: the grid spans the scene's bounding cube unless that spaces "
      "the probes wider than this (scene units; glTF: metres), then it follows the camera at "
      "this spacing; 0 = always the cube"},
     FloatField{&S::giProbeMaxSpacing, 0.0f, 1e30f}},
    {{"gi.voxels", "int 16..256",
      "probes: occupancy voxels along each side of the grid (the visibility's resolution)"},
     UIntField{&S::giVoxels, 16, 256}},
    {{"gi.vpls", "int 4..128",
      "probes: virtual point lights along each side of the RSM (its texels clustered in blocks)"},
     UIntField{&S::giVpls, 4, 128}},
    {{"gi.probe_cache", "bool",
      "probes: the RSM, VPLs and gather run again only when the sun, geometry, textures or the "
      "probe grid change (false: every frame, which is what a turning sun costs)"},
     BoolField{&S::giProbeCache}},
    {{"gi.probe_visibility", "depth|exact",
      "probes: whether a VPL is seen, from each probe's 16x16 depth map traced once per grid (a "
      "fetch per pair) or by a walk through the voxels per probe-VPL pair (exact, slower)"},
     enumField<&S::giProbeVisibility>(kProbeVisibilityNames)},
    {{"ibl.enabled", "bool",
      "light from the container's environment (pnb-convert --sky or --environment): diffuse "
      "from its irradiance SH, reflections from its prefiltered cube, and the background; "
      "off = the uniform lighting.ambient, exactly as without an environment"},
     BoolField{&S::iblEnabled}},
    {{"ibl.intensity", "float 0..1000", "scale of the environment's radiance (1 = as stored, nits)"},
     FloatField{&S::iblIntensity, 0.0f, 1000.0f}},
    {{"ibl.rotation_deg", "float -360..360",
      "environment turned about +Y (seen from above: counter-clockwise), lighting and background"},
     FloatField{&S::iblRotationDeg, -360.0f, 360.0f}},
    {{"ibl.specular", "bool", "reflections of the environment (prefiltered cube + split-sum table)"},
     BoolField{&S::iblSpecular}},
    {{"ibl.background", "bool", "draw the environment where no surface is"},
     BoolField{&S::iblBackground}},
    {{"ibl.visibility", "none|screen|height|volume|probes|auto",
      "sky visibility of deferred materials: none (every surface sees the whole sky), screen "
      "(rays marched through the depth buffer), height (through a height map of the scene "
      "seen from above, drawn once), out to ibl.visibility_radius; volume (through the "
      "GI's geometry: the light propagation volumes' face transmittances; needs gi.enabled "
      "and gi.occlusion); or probes (each GI probe traces rays through the occupancy grid "
      "when the geometry changes, looked up per pixel; needs gi.enabled and "
      "gi.technique=probes); auto (the default): probes where the GI probes run, else none — "
      "probes beat a constant on the street canyon and the box room, every other mode loses "
      "to it on one (height: 0.51 outdoors, 1.9 indoors)"},
     enumField<&S::iblVisibility>(kSkyVisibilityNames)},
    {{"ibl.visibility_radius", "float >= 0",
      "screen and height visibility: how far occluders are searched, scene units; 0 = 1/8 of the scene "
      "bounds' diagonal"},
     FloatField{&S::iblVisibilityRadius, 0.0f, 1e30f}},
    {{"ibl.height_resolution", "int 64..4096",
      "height visibility: the side of the height map over the scene's ground plan, texels"},
     UIntField{&S::iblHeightResolution, 64, 4096}},
    {{"debug.view",
      "none|basecolor|alpha|normal|roughness|metallic|occlusion|emissive|depth|layer|overdraw|"
      "cascades|shadowmap|histogram|gi_indirect|gi_rsm|gi_volume|lod|light_clusters",
      "show one buffer instead of the lit image"},
     enumField<&S::debugView>(kDebugViewNames)},
    {{"lod.threshold_px", "float 0..1000",
      "largest simplification error a level of detail may show, in pixels at the current "
      "resolution and field of view (0 = full detail unless a level is exact)"},
     FloatField{&S::lodThresholdPx, 0.0f, 1000.0f}},
    {{"lod.hysteresis", "float 0..0.9",
      "a coarser level is taken only once its error is below threshold x (1 - hysteresis), a "
      "finer one as soon as the current exceeds the threshold: no flipping at the threshold"},
     FloatField{&S::lodHysteresis, 0.0f, 0.9f}},
    {{"lod.bias", "int -8..8", "levels added to the chosen level of detail (+ coarser, - finer)"},
     IntField{&S::lodBias, -8, 8}},
    {{"lod.force", "int -1..254",
      "-1: levels of detail by projected error; N: every object draws level N (or its "
      "coarsest, if it has fewer)"},
     IntField{&S::lodForce, -1, 254}},
    {{"stream.budget_mib", "int 0..1048576",
      "streaming: GPU storage budget in MiB for textures and level-of-detail meshes (0 = no "
      "limit); textures keep the mip levels the view needs, meshes their full detail where "
      "the LOD rule draws finer than their proxy; the least recently needed are given up "
      "when it is short"},
     UIntField{&S::streamBudgetMib, 0, 1048576}},
    {{"stream.upload_mib", "float 0.0625..4096",
      "streaming: texel bytes uploaded per frame through the staging ring, MiB (more: full "
      "quality sooner; fewer: steadier frame times)"},
     FloatField{&S::streamUploadMib, 0.0625f, 4096.0f}},
    {{"debug.shadow_layer", "int 0..7", "the shadow-map layer debug.view=shadowmap shows"},
     UIntField{&S::debugShadowLayer, 0, 7}},
    {{"debug.gi_slice", "int 0..511",
      "the z slice debug.view=gi_volume shows (cascades stacked: cascade c is slices "
      "c*cells .. (c+1)*cells-1)"},
     UIntField{&S::debugGiSlice, 0, 511}},
    {{"textures.anisotropy", "float 1..16",
      "largest anisotropic filtering ratio of mipmapped textures (1 = trilinear only)"},
     FloatField{&S::anisotropy, 1.0f, 16.0f}},
    {{"startup.warmup", "bool",
      "before the first frame, draw every program the scene uses once, off-screen, in its "
      "pass's real state, so the driver generates its code during load and no frame along a "
      "path pays for it (off: for measuring what it saves)"},
     BoolField{&S::warmUp}},
    {{"anim.enabled", "bool",
      "play the container's animation (clips, skins, morph targets); false = the container as "
      "stored: the bind pose, every node at rest, no deform pass (the frozen baseline)"},
     BoolField{&S::animEnabled}},
    {{"anim.clip", "index|name|none",
      "the clip played: its index (0 = the first), its name, or none (the rest pose; skins and "
      "morph targets still deform, at the rest pose and default weights)"},
     StringField{&S::animClip}},
    {{"anim.play", "bool",
      "advance the clock (headless and benchmark runs by the fixed frame step, the window by "
      "wall time); false = the pose held at anim.time"},
     BoolField{&S::animPlay}},
    {{"anim.time", "float -1e6..1e6", "seconds into the clip where playback starts (or holds); clips loop"},
     FloatField{&S::animTime, -1e6f, 1e6f}},
    {{"anim.speed", "float -100..100", "clip seconds per clock second (negative: backwards)"},
     FloatField{&S::animSpeed, -100.0f, 100.0f}},
};

std::span<const Row> rows() { return kRows; }

const Row* findRow(std::string_view key) {
    for (const Row& r : rows())
        if (r.info.key == key) return &r;
    return nullptr;
}

PlayError usage(std::string_view key, std::string_view value, std::string_view expected) {
    return {PlayErrorKind::Usage, "setting " + std::string(key) + ": '" + std::string(value) +
                                      "' is not " + std::string(expected)};
}

std::string formatFloat(float f) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", double(f));
    return buf;
}

} // namespace

const std::vector<SettingInfo>& settingInfos() {
    static const std::vector<SettingInfo> infos = [] {
        std::vector<SettingInfo> v;
        for (const Row& r : rows()) v.push_back(r.info);
        return v;
    }();
    return infos;
}

std::string_view toString(DebugView view) { return kDebugViewNames[size_t(view)]; }

PlayResult<Done> applySetting(RenderSettings& settings, std::string_view key,
                              std::string_view value) {
    const Row* row = findRow(key);
    if (!row) {
        std::string known;
        for (const Row& r : rows()) known += (known.empty() ? "" : ", ") + std::string(r.info.key);
        return PlayError{PlayErrorKind::Usage,
                         "unknown setting '" + std::string(key) + "' (known: " + known + ")"};
    }
    if (const auto* f = std::get_if<FloatField>(&row->field)) {
        float v = 0;
        auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
        if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(v) ||
            v < f->min || v > f->max)
            return usage(key, value, row->info.type);
        settings.*(f->member) = v;
    } else if (const auto* u = std::get_if<UIntField>(&row->field)) {
        uint32_t v = 0;
        auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
        if (ec != std::errc() || end != value.data() + value.size() || v < u->min || v > u->max)
            return usage(key, value, row->info.type);
        settings.*(u->member) = v;
    } else if (const auto* n = std::get_if<IntField>(&row->field)) {
        int32_t v = 0;
        auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
        if (ec != std::errc() || end != value.data() + value.size() || v < n->min || v > n->max)
            return usage(key, value, row->info.type);
        settings.*(n->member) = v;
    } else if (const auto* b = std::get_if<BoolField>(&row->field)) {
        if (value == "1" || value == "true" || value == "on") settings.*(b->member) = true;
        else if (value == "0" || value == "false" || value == "off") settings.*(b->member) = false;
        else return usage(key, value, "a bool (1/0, true/false, on/off)");
    } else if (const auto* t = std::get_if<StringField>(&row->field)) {
        if (value.empty()) return usage(key, value, row->info.type);
        settings.*(t->member) = std::string(value);
    } else {
        const auto& e = std::get<EnumField>(row->field);
        auto it = std::find(e.names.begin(), e.names.end(), value);
        if (it == e.names.end()) return usage(key, value, row->info.type);
        e.set(settings, int(it - e.names.begin()));
    }
    return Done{};
}

PlayResult<Done> applySetting(RenderSettings& settings, std::string_view assignment) {
    size_t eq = assignment.find('=');
    if (eq == std::string_view::npos || eq == 0)
        return PlayError{PlayErrorKind::Usage,
                         "--set expects key=value, got '" + std::string(assignment) + "'"};
    return applySetting(settings, assignment.substr(0, eq), assignment.substr(eq + 1));
}

std::string settingValue(const RenderSettings& settings, std::string_view key) {
    const Row* row = findRow(key);
    if (!row) return {};
    if (const auto* f = std::get_if<FloatField>(&row->field))
        return formatFloat(settings.*(f->member));
    if (const auto* u = std::get_if<UIntField>(&row->field))
        return std::to_string(settings.*(u->member));
    if (const auto* n = std::get_if<IntField>(&row->field))
        return std::to_string(settings.*(n->member));
    if (const auto* b = std::get_if<BoolField>(&row->field))
        return settings.*(b->member) ? "true" : "false";
    if (const auto* t = std::get_if<StringField>(&row->field)) return settings.*(t->member);
    const auto& e = std::get<EnumField>(row->field);
    return std::string(e.names[size_t(e.get(settings))]);
}

std::vector<std::string_view> settingChoices(std::string_view key) {
    const Row* row = findRow(key);
    const auto* e = row ? std::get_if<EnumField>(&row->field) : nullptr;
    if (!e) return {};
    return {e->names.begin(), e->names.end()};
}

std::vector<std::pair<std::string, std::string>> settingValues(const RenderSettings& settings) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const Row& r : rows())
        out.emplace_back(std::string(r.info.key), settingValue(settings, r.info.key));
    return out;
}

std::vector<std::pair<std::string, std::string>> driverDefaults(std::string_view glRenderer) {
    if (glRenderer.find("llvmpipe") != std::string_view::npos ||
        glRenderer.find("softpipe") != std::string_view::npos)
        return {{"textures.anisotropy", "1"}};
    return {};
}

std::string settingNote(std::string_view key, const RenderSettings& s) {
    auto in = [&](std::string_view section) { return key.substr(0, section.size()) == section; };
    if (in("gi.") && key != "gi.enabled" && !s.giEnabled) return "gi.enabled is false";
    if (in("shadows.") && key != "shadows.technique" && s.shadowTechnique == ShadowTechnique::Off)
        return "shadows.technique is off";
    if (key == "shadows.cascades" && (s.shadowTechnique == ShadowTechnique::Single ||
                                      s.shadowTechnique == ShadowTechnique::Lispsm))
        return std::string("shadows.technique ") + (s.shadowTechnique == ShadowTechnique::Single ? "single" : "lispsm") +
               " draws one map";
    if (in("ibl.") && key != "ibl.enabled" && !s.iblEnabled) return "ibl.enabled is false";
    if (key == "debug.gi_slice" && s.debugView != DebugView::GiVolume) return "debug.view is not gi_volume";
    if (in("anim.") && key != "anim.enabled" && !s.animEnabled) return "anim.enabled is false";
    if (key == "gi.bounces" && s.giTechnique != GiTechnique::Probes) return "gi.technique is not probes";
    return {};
}

PlayResult<RenderSettings> resolveSettings(
    const std::vector<std::pair<std::string, std::string>>& containerSettings,
    const std::vector<std::string>& commandLine, std::vector<std::string>* warnings) {
    RenderSettings s;
    for (const auto& [key, value] : containerSettings) {
        auto r = applySetting(s, key, value);
        if (!r && warnings) warnings->push_back("container setting ignored: " + r.error().message);
    }
    for (const std::string& assignment : commandLine)
        if (auto r = applySetting(s, assignment); !r) return r.error();
    return s;
}

} // namespace pnb::player
