// pnb_player/settings.h — every render setting, addressable by a dotted key.
//
// One table (settings.cpp) names each setting, its type, default, range and meaning; the
// command line (`--set key=value`), the container's RSET chunk and the ImGui overlay all go
// through it. Precedence: defaults < container < command line. Unknown keys from the command
// line are errors; unknown keys in a container are reported as warnings (a newer converter may
// write settings for features this player does not have).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pnb_player/play_error.h"

namespace pnb::player {

enum class DebugView {
    None,      // the lit, tone-mapped image
    BaseColor, // G-buffer RT0 rgb of the last deferred layer
    Alpha,     // G-buffer RT0 a
    Normal,    // decoded world normal, 0.5 + 0.5 n
    Roughness,
    Metallic,
    Occlusion,
    Emissive,
    Depth,     // linearised view depth, log-scaled
    Layer,     // which deferred layer (or forward) last wrote each pixel
    Overdraw,  // fragments shaded per pixel across all geometry passes
    Cascades,  // lit image tinted by the shadow cascade each pixel reads (seed 000's colours)
    ShadowMap, // one layer of the shadow-map array (debug.shadow_layer), depth as grey
    Histogram, // SDSM's depth histogram with the split positions marked (sdsm only)
    GiIndirect, // the irradiance GI adds, tone mapped (lighting writes it instead of radiance)
    GiRsm,      // the reflective shadow map: diffuse albedo each texel reflects (flux / (E A_t))
    GiVolume,   // one z slice (debug.gi_slice) of the summed light volume: band 0 per colour, x4
    Lod,        // each object in the colour of the level of detail it draws (grey: has no LODs)
    LightClusters, // lights in each pixel's cluster as heat (red 8, yellow 16, white 32+)
    Count
};

// shadows.technique: how the sun's (first directional light's) shadow map is fitted.
enum class ShadowTechnique {
    Off,
    Single, // one orthographic map over the whole scene (the baseline)
    Lispsm, // one light-space perspective map over the view (Wimmer et al. 2004)
    Pssm,   // cascades at the practical split scheme's distances (Zhang et al. 2006)
    Sdsm,   // cascades fitted on the GPU to this frame's depth samples (Lauritzen et al. 2011)
};
enum class CascadeFit { Sphere, Tight };       // shadows.fit
enum class ShadowRender { Layered, MultiPass }; // shadows.render
enum class LayerSource { Auto, Vertex, Geometry }; // shadows.layer_from
enum class ShadowFilter { Hardware, Poisson, Pcss }; // shadows.filter
enum class CascadeSelect { Depth, Bounds };    // shadows.select
enum class SdsmPartition { Log, Quantile };    // shadows.sdsm_partition
enum class GiAtomics { Fixed, Float };         // gi.atomics
enum class GiTechnique { Lpv, Probes };        // gi.technique
enum class ProbeVisibility { Depth, Exact };   // gi.probe_visibility
enum class LightCulling { Auto, Clusters, Off };   // lights.culling
// ibl.visibility. Auto (the default) is Probes where the GI probes run, None elsewhere:
// resolvedSkyVisibility says which the frame gets.
enum class SkyVisibility { None, Screen, Height, Volume, Probes, Auto };

struct RenderSettings {
    float exposure = 1.0f;       // lighting.exposure: HDR scale before tone mapping
    float ambient = 0.03f;       // lighting.ambient: uniform ambient radiance (times base colour)
    float sunTurnDeg = 0.0f;     // lighting.sun_turn_deg: directional lights turned about +Y
    bool fxaa = false;           // post.fxaa: FXAA 3.11-style edge anti-aliasing after tone mapping
    bool frustumCulling = true;  // cull.frustum: skip draws whose world AABB is outside the view
    float nearPlane = 0.0f;      // camera.near: metres; 0 = the container camera's znear
    float farPlane = -1.0f;      // camera.far: metres; 0 = infinite; -1 = the container camera's
    DebugView debugView = DebugView::None; // debug.view
    uint32_t debugShadowLayer = 0;         // debug.shadow_layer
    uint32_t debugGiSlice = 0;             // debug.gi_slice
    float anisotropy = 8.0f;               // textures.anisotropy: max anisotropic filter ratio
    bool warmUp = true;                    // startup.warmup: Renderer::warmUp draws every program once

    // lod.*: level-of-detail selection by projected error (player/math/lod_select.h,
    // docs/PLAYER.md "Level of detail").
    float lodThresholdPx = 1.0f; // lod.threshold_px: largest projected simplification error, px
    float lodHysteresis = 0.2f;  // lod.hysteresis: coarser only once below threshold x (1 - h)
    int32_t lodBias = 0;         // lod.bias: levels added to the chosen one (+ coarser, - finer)
    int32_t lodForce = -1;       // lod.force: -1 = by error; N = level N (clamped to what exists)

    // stream.*: streaming playback (scene_stream.h, docs/PLAYER.md "Streaming").
    uint32_t streamBudgetMib = 0;  // stream.budget_mib: textures + LOD meshes' storage; 0 = no limit
    float streamUploadMib = 8.0f;  // stream.upload_mib: texel bytes uploaded per frame, MiB

    // lights.*: which lights each pixel shades (docs/PLAYER.md "Many lights").
    LightCulling lightCulling = LightCulling::Auto;
    uint32_t lightClusterMin = 32; // auto: clusters from this many point and spot lights on
    uint32_t lightTilePx = 32;     // cluster tile side, pixels
    uint32_t lightSlices = 24;     // exponential depth slices between the near plane and the
                                   // farthest light's reach

    // shadows.*: see settings.cpp for each key's meaning.
    ShadowTechnique shadowTechnique = ShadowTechnique::Pssm;
    uint32_t shadowCascades = 4;
    uint32_t shadowResolution = 2048;
    float shadowLambda = 0.75f;
    float shadowDistance = 0.0f; // 0 = to the far side of the scene bounds
    CascadeFit shadowFit = CascadeFit::Sphere;
    ShadowRender shadowRender = ShadowRender::Layered;
    LayerSource shadowLayerSource = LayerSource::Auto;
    ShadowFilter shadowFilter = ShadowFilter::Poisson;
    uint32_t shadowTaps = 16;
    float shadowRadius = 1.5f;     // filter radius in texels
    float shadowLightSize = 0.53f; // PCSS: the light's angular diameter in degrees (the sun: 0.53)
    CascadeSelect shadowSelect = CascadeSelect::Depth;
    float shadowBlend = 0.1f;      // blend band: fraction of each cascade's depth range
    float shadowNormalOffset = 1.0f; // texels
    float shadowSlopeBias = 1.0f;    // texels per unit of tan(angle to the light)
    SdsmPartition sdsmPartition = SdsmPartition::Log;
    // Point and spot light shadows (docs/PLAYER.md "Local-light shadows").
    bool shadowLocal = true;            // shadows.local
    uint32_t shadowLocalLights = 16;    // shadows.local_lights: the largest on screen get tiles
    uint32_t shadowLocalAtlas = 2048;   // shadows.local_atlas: the atlas side (the memory budget)
    uint32_t shadowLocalMaxTile = 1024; // shadows.local_max_tile: largest tile side
    bool shadowLocalCache = true;       // shadows.local_cache: redraw only tiles that changed
    bool shadowTranslucent = true;      // shadows.translucent: blended casters tint the light
    uint32_t shadowTranslucentDivisorLog2 = 2; // shadows.translucent_divisor (1, 2, 4, 8): log2
    uint32_t shadowLocalTaps = 4;       // shadows.local_taps: PCF taps per local-light lookup
    int32_t shadowJudgedLight = -1;     // shadows.judged_light: the light captures describe

    // gi.*: one-bounce diffuse indirect light from the sun through cascaded Light Propagation
    // Volumes (seed 004; see settings.cpp and docs/PLAYER.md "Global illumination").
    bool giEnabled = false;
    // lpv: the cheap one (RSM -> propagation volumes); probes: a grid of irradiance probes that
    // gather the RSM's lights directly with voxel visibility (docs/PLAYER.md "Global illumination").
    GiTechnique giTechnique = GiTechnique::Lpv;
    uint32_t giCascades = 3;
    uint32_t giCells = 16;
    float giCellSize = 0.0f;      // finest cell in scene units; 0 = outer cascade fits the scene
    uint32_t giIterations = 16; // = giCells: light crosses the outer cascade once
    uint32_t giRsmResolution = 256;
    bool giOcclusion = true;      // geometry-volume blocking during propagation
    bool giCameraOcclusion = true; // blocking geometry also from the camera's G-buffer
    float giIntensity = 1.0f;
    GiAtomics giAtomics = GiAtomics::Fixed;
    uint32_t giProbeCells = 20;   // probes: probes along each side of the grid over the scene
    // probes: the grid over the scene's bounding cube, unless that spaces the probes wider than
    // this (scene units; glTF's are metres): then it follows the camera at this spacing. 0: never.
    float giProbeMaxSpacing = 8.0f;
    uint32_t giVoxels = 64;       // probes: occupancy voxels along each side (visibility)
    uint32_t giVpls = 32;         // probes: virtual point lights along each side of the RSM
    bool giProbeCache = true;     // probes: gathered again only when what they see changed
    // probes: VPL-to-probe visibility from each probe's depth map (a fetch) or a walk through
    // the occupancy grid per pair (exact at the grid's resolution, 5.5x the gather's time here)
    ProbeVisibility giProbeVisibility = ProbeVisibility::Depth;
    // probes: diffuse bounces the probes hold. 1: the VPLs' one bounce; N > 1: N - 1 more
    // gathers, each probe reading the last one's irradiance where its depth rays hit
    // (pass_gi_bounce.cpp); nothing of it exists at 1.
    uint32_t giBounces = 1;

    // ibl.*: light from the container's environment (ENVM; docs/PLAYER.md "Sky and image-based
    // lighting"). Without an environment none of these has an effect.
    bool iblEnabled = true;         // ibl.enabled: off = exactly the image without an environment
    float iblIntensity = 1.0f;      // ibl.intensity: scale of the environment's radiance
    float iblRotationDeg = 0.0f;    // ibl.rotation_deg: environment turned about +Y
    bool iblSpecular = true;        // ibl.specular: the prefiltered reflection term
    bool iblBackground = true;      // ibl.background: the environment behind the scene
    // ibl.visibility: auto by default — the only mode that beats a constant on every bundled
    // scene is probes (docs/PLAYER.md "Sky visibility, the scorecard"), which needs GI probes.
    SkyVisibility iblVisibility = SkyVisibility::Auto;
    float iblVisibilityRadius = 0.0f; // ibl.visibility_radius: scene units; 0 = 1/8 of the
                                      // scene bounds' diagonal
    uint32_t iblHeightResolution = 1024; // ibl.height_resolution: the height map's side, texels

    // anim.*: playback of the container's clips, skins and morph targets (docs/PLAYER.md
    // "Animation"). The pose's time is anim.time + anim.speed x the clock while anim.play.
    bool animEnabled = true;     // anim.enabled: false = the container as stored (bind pose,
                                 // nodes at rest, no deform pass): the frozen baseline
    std::string animClip = "0";  // anim.clip: a clip's index or name; "none" = the rest pose
    bool animPlay = true;        // anim.play: false = the pose held at anim.time
    float animTime = 0.0f;       // anim.time: seconds, where playback starts (or holds)
    float animSpeed = 1.0f;      // anim.speed: clock seconds to clip seconds
};

// The sky-visibility mode the settings ask for, Auto resolved: Probes when GI runs with the
// probes (gi.enabled, gi.technique = probes), None otherwise (without the probes every mode
// loses to a constant on one bundled scene). Whether the frame's inputs allow it is the
// frame's business (planIbl).
inline SkyVisibility resolvedSkyVisibility(const RenderSettings& s) {
    if (s.iblVisibility != SkyVisibility::Auto) return s.iblVisibility;
    return s.giEnabled && s.giTechnique == GiTechnique::Probes ? SkyVisibility::Probes : SkyVisibility::None;
}

struct SettingInfo {
    std::string_view key, type, description;
};

// Every key, in a stable order (for --list-settings, the JSON summary and the overlay).
const std::vector<SettingInfo>& settingInfos();

// The accepted values of a key that takes one of a list of names (empty for other keys).
std::vector<std::string_view> settingChoices(std::string_view key);

// Parses `value` into the setting `key`. Errors (Usage) name the key and what is accepted.
PlayResult<Done> applySetting(RenderSettings& settings, std::string_view key,
                              std::string_view value);
// "key=value"
PlayResult<Done> applySetting(RenderSettings& settings, std::string_view assignment);

// The current value of `key` in the same syntax applySetting accepts ("" for an unknown key).
std::string settingValue(const RenderSettings& settings, std::string_view key);

// Every key with its current value, in settingInfos() order.
std::vector<std::pair<std::string, std::string>> settingValues(const RenderSettings& settings);

std::string_view toString(DebugView view);

// Defaults that depend on the driver (GL_RENDERER), as "key=value" pairs to apply before the
// container's: Mesa's software rasterisers get textures.anisotropy = 1, because llvmpipe
// (Mesa 22.3) takes up to tens of seconds per frame for anisotropic lookups at grazing angles.
std::vector<std::pair<std::string, std::string>> driverDefaults(std::string_view glRenderer);

// Why the setting `key`, as `settings` stand, changes nothing ("" when it does): a gi.* setting
// while gi.enabled is false, a shadows.* one while shadows.technique is off, shadows.cascades with
// a one-map technique, ibl.* while ibl.enabled is false, debug.gi_slice outside the gi_volume
// view. Scene-dependent reasons (no environment, no GI programs) are the renderer's notes.
std::string settingNote(std::string_view key, const RenderSettings& settings);

// Defaults, then the container's RSET entries, then command-line assignments ("key=value"):
// later wins. A container entry that does not apply is skipped with a line in `warnings`; a
// command-line one is an error.
PlayResult<RenderSettings> resolveSettings(
    const std::vector<std::pair<std::string, std::string>>& containerSettings,
    const std::vector<std::string>& commandLine, std::vector<std::string>* warnings = nullptr);

} // namespace pnb::player
