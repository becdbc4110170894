// Global illumination: the whole pipeline on the box room converted with GI (flux independent of
// the RSM's resolution, sub-cell camera motion, GI off = today's image, extremes, accuracy against
// the one-bounce truth). The propagation shader alone, on hand-made volumes, is
// gi_propagation_test.cpp.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numeric>
#include <optional>
#include <tuple>

#include <gtest/gtest.h>

#include "lpv_math.h"
#include "pnb/atomic_file.h"
#include "pnb_assets/procedural_scenes.h"
#include "pnb_assets/scene_transform.h"
#include "pnb/reader.h"
#include "pnb_reference/indirect_metrics.h"
#include "pnb_reference/indirect_tracer.h"
#include "pnb_reference/shadow_metrics.h"
#include "pnb_converter/convert.h"
#include "pnb_player/gpu_scene.h"
#include "pnb_player/renderer.h"
#include "render_fixture.h"

namespace pnb::player::test {
namespace {

namespace fs = std::filesystem;

// --- the pipeline on the box room ------------------------------------------------------------

// This binary's scratch directory, removed when the process ends.
const fs::path& scratchDir() {
    struct Dir {
        fs::path path = fs::temp_directory_path() / ("pnb_gi_test_" + std::to_string(::getpid()));
        Dir() { fs::create_directories(path); }
        ~Dir() {
            std::error_code ec;
            fs::remove_all(path, ec);
        }
    };
    static const Dir dir;
    return dir.path;
}

// `input` (a .glb) converted with GI into the scratch directory as NAME.pnb, with the material
// overrides `sidecarJson` if not empty.
std::string convertWithGi(const std::string& input, const std::string& name, const std::string& sidecarJson = "") {
    converter::ConvertSettings s;
    s.input = input;
    s.output = (scratchDir() / (name + ".pnb")).string();
    s.jobs = 1;
    s.validateShaders = false;
    s.noSidecar = sidecarJson.empty();
    if (!sidecarJson.empty()) {
        s.sidecar = (scratchDir() / (name + ".sidecar.json")).string();
        std::ofstream(s.sidecar) << sidecarJson;
    }
    s.renderSettings = {{"gi.enabled", "true"}};
    auto r = converter::convertScene(s);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return s.output;
}

// The box room's pane letting all light through (casts_shadows false): these tests hold GI
// without glass to its behaviour before issue 43, and the one-bounce truth they compare with
// traces no glass. Light through the pane: gi_glass_test.cpp.
const char* const kPaneLetsAllThrough = R"({"materials": {"tinted-glass": {"casts_shadows": false}}})";

// The box room as converted by default (its pane casts, tinted: issue 43), with GI.
std::string giBoxRoomGlass() {
    static const std::string path = convertWithGi(std::string(PNB_SCENE_DIR) + "/box-room.glb", "box-room-glass");
    return path;
}

std::string giBoxRoom() {
    static const std::string path =
        convertWithGi(std::string(PNB_SCENE_DIR) + "/box-room.glb", "box-room", kPaneLetsAllThrough);
    return path;
}

struct GiFrameResult {
    CapturedImage color, hdr, indirect, volume, position, normal;
    TargetMemory memory;
};

GiFrameResult renderGi(const std::string& path, const CameraState& camera, RenderSettings s,
                       uint32_t w = 160, uint32_t h = 120) {
    GiFrameResult out;
    auto scene = loadScene(path);
    EXPECT_TRUE(scene.ok());
    if (!scene) return out;
    auto renderer = Renderer::create(**scene, s);
    EXPECT_TRUE(renderer.ok());
    if (!renderer) return out;
    EXPECT_TRUE((*renderer)->render(camera, w, h).ok());
    out.color = std::move(*(*renderer)->capture(CaptureBuffer::Color));
    out.hdr = std::move(*(*renderer)->capture(CaptureBuffer::Hdr));
    out.indirect = std::move(*(*renderer)->capture(CaptureBuffer::Indirect));
    out.volume = std::move(*(*renderer)->capture(CaptureBuffer::GiVolume));
    out.position = std::move(*(*renderer)->capture(CaptureBuffer::Position));
    out.normal = std::move(*(*renderer)->capture(CaptureBuffer::Normal));
    out.memory = (*renderer)->targetMemory();
    return out;
}

RenderSettings giSettings() {
    RenderSettings s;
    s.giEnabled = true;
    s.shadowResolution = 512;
    return s;
}

// Total band-0 of the red channel over every cell.
double volumeFlux(const CapturedImage& v) {
    double s = 0;
    for (size_t i = 0; i < v.f32.size(); i += 12) s += v.f32[i];
    return s;
}

// Outside the room, looking in through its open side (as the container camera does, nearer).
const CameraState kView = lookAt({0, 4, 8}, {0, 1.5, 0});

TEST(GiPipeline, InjectedFluxDoesNotDependOnTheRsmResolution) {
    RenderSettings s = giSettings();
    s.giCascades = 1;
    s.giIterations = 0; // the sum is the injection
    std::vector<double> fluxes;
    for (uint32_t res : {128u, 256u, 512u, 1024u}) {
        s.giRsmResolution = res;
        GiFrameResult r = renderGi(giBoxRoom(), kView, s, 64, 48);
        ASSERT_FALSE(r.volume.f32.empty());
        fluxes.push_back(volumeFlux(r.volume));
    }
    for (size_t i = 0; i < fluxes.size(); ++i)
        EXPECT_NEAR(fluxes[i] / fluxes.back(), 1.0, 0.05) << "RSM " << (128u << i);
}

TEST(GiPipeline, CameraMotionWithinACellLeavesIndirectLightUnchanged) {
    RenderSettings s = giSettings();
    s.giCascades = 2; // the inner cascade follows the camera
    // Blocking surfels from the camera's G-buffer are resampled as the view moves (up to 10 %
    // of the largest value here): what stays put is everything built in the cascades' frame.
    s.giCameraOcclusion = false;
    GiFrameResult a = renderGi(giBoxRoom(), kView, s);
    // Where do the cascades sit? Move the camera by a tenth of the finest cell in a direction
    // that keeps every snapped origin (checked with the same placement the player uses).
    auto scene = loadScene(giBoxRoom());
    ASSERT_TRUE(scene.ok());
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (const DrawItem& item : (*scene)->items) {
        lo = glm::min(lo, item.boundsMin);
        hi = glm::max(hi, item.boundsMax);
    }
    glm::dvec3 forward = glm::dvec3(glm::mat3_cast(glm::quat(kView.rotation)) * glm::vec3(0, 0, -1));
    auto before = placeCascades(2, s.giCells, 0, lo, hi, kView.position, forward);
    CameraState moved = kView;
    bool found = false;
    for (glm::dvec3 step : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0)}) {
        moved.position = kView.position + step * (0.1 * before[0].cellSize);
        auto after = placeCascades(2, s.giCells, 0, lo, hi, moved.position, forward);
        if (after[0].origin == before[0].origin) {
            found = true;
            break;
        }
    }
    ASSERT_TRUE(found);
    GiFrameResult b = renderGi(giBoxRoom(), moved, s);
    ASSERT_EQ(a.volume.f32.size(), b.volume.f32.size());
    ASSERT_FALSE(a.volume.f32.empty());
    float largest = 0, diff = 0;
    for (size_t i = 0; i < a.volume.f32.size(); ++i) {
        largest = std::max(largest, std::abs(a.volume.f32[i]));
        diff = std::max(diff, std::abs(a.volume.f32[i] - b.volume.f32[i]));
    }
    EXPECT_GT(largest, 0.0f);
    EXPECT_LE(diff, 2e-3f * largest); // fp16 rounding of camera-relative positions at most
}

TEST(GiPipeline, GiOffIsTodaysImageAndAllocatesNothing) {
    RenderSettings off = giSettings();
    off.giEnabled = false;
    GiFrameResult withoutGiPrograms = renderGi(std::string(PNB_SCENE_DIR) + "/box-room.pnb", kView, off);
    GiFrameResult giSwitchedOff = renderGi(giBoxRoomGlass(), kView, off); // both: the pane casts
    ImageDiff d = compareRgba8(withoutGiPrograms.color, giSwitchedOff.color);
    EXPECT_EQ(d.maxAbs, 0);
    EXPECT_EQ(giSwitchedOff.memory.giBytes, 0u);
    EXPECT_TRUE(giSwitchedOff.volume.f32.empty());
    // A container without GI programs ignores gi.enabled (the player says so once).
    GiFrameResult asked = renderGi(std::string(PNB_SCENE_DIR) + "/box-room.pnb", kView, giSettings());
    EXPECT_EQ(compareRgba8(withoutGiPrograms.color, asked.color).maxAbs, 0);
    EXPECT_EQ(asked.memory.giBytes, 0u);
}

TEST(GiPipeline, LightsWhatTheSunDoesNotReach) {
    GiFrameResult on = renderGi(giBoxRoom(), kView, giSettings());
    ASSERT_FALSE(on.indirect.f32.empty());
    ASSERT_TRUE(allFinite(on.indirect));
    size_t lit = 0;
    for (size_t i = 0; i < on.indirect.f32.size(); i += 4)
        lit += on.indirect.f32[i] + on.indirect.f32[i + 1] + on.indirect.f32[i + 2] > 0;
    EXPECT_GT(lit, on.indirect.f32.size() / 4 / 2); // most pixels receive indirect light
    // (Colour: the sun lights no red or green wall here, so the one-bounce truth's left and right
    // halves differ in red/green by 1 %; the channel balance against the truth is checked by
    // GiAccuracy below.)
}

TEST(GiPipeline, ExtremesStayFinite) {
    RenderSettings s = giSettings();
    s.giIntensity = 0; // zero flux
    GiFrameResult zero = renderGi(giBoxRoom(), kView, s);
    ASSERT_FALSE(zero.indirect.f32.empty());
    for (size_t i = 0; i < zero.indirect.f32.size(); i += 4)
        for (size_t c = 0; c < 3; ++c) ASSERT_EQ(zero.indirect.f32[i + c], 0.0f) << i;
    s = giSettings();
    s.giIntensity = 1000; // the most indirect light the setting allows
    s.giCells = 8;
    s.giRsmResolution = 2048; // many texels per cell: the fixed-point scale's other end
    GiFrameResult big = renderGi(giBoxRoom(), kView, s, 64, 48);
    EXPECT_TRUE(allFinite(big.volume));
    EXPECT_GT(volumeFlux(big.volume), 0.0);
    // A finest cell far smaller than the scene (the scene is ~1000x the outer cascade).
    s = giSettings();
    s.giCellSize = 1e-3f;
    GiFrameResult tiny = renderGi(giBoxRoom(), kView, s, 64, 48);
    EXPECT_TRUE(allFinite(tiny.volume));
    EXPECT_TRUE(allFinite(tiny.indirect));
}

} // namespace
} // namespace pnb::player::test

namespace pnb::player::test {
namespace {

double meanColor(const CapturedImage& c) {
    double s = 0;
    for (size_t i = 0; i < c.u8.size(); i += 4) s += c.u8[i] + c.u8[i + 1] + c.u8[i + 2];
    return s / double(c.u8.size() / 4 * 3);
}

TEST(GiPipeline, DebugViewsShowTheRsmTheVolumeAndIndirectLightAndNothingWithoutGi) {
    for (DebugView view : {DebugView::GiIndirect, DebugView::GiRsm, DebugView::GiVolume}) {
        RenderSettings s = giSettings();
        s.giCascades = 1;
        s.debugView = view;
        s.debugGiSlice = 2; // just above the floor of the scene's grid
        GiFrameResult on = renderGi(giBoxRoom(), kView, s, 96, 72);
        s.giEnabled = false;
        GiFrameResult off = renderGi(giBoxRoom(), kView, s, 96, 72);
        EXPECT_GT(meanColor(on.color), 2.0) << toString(view);
        if (view != DebugView::GiIndirect) {
            EXPECT_EQ(meanColor(off.color), 0.0) << toString(view);
        }
    }
}

} // namespace
} // namespace pnb::player::test

namespace pnb::player::test {
namespace {

// The box room (pnb_assets' generator), changed by `edit`, converted with GI.
std::string giVariant(const std::string& name, const std::function<void(gltf::Document&)>& edit) {
    gltf::Document doc = assets::buildBoxRoomGltf();
    edit(doc);
    std::string glb = (scratchDir() / (name + ".glb")).string();
    EXPECT_TRUE(isOk(pnb::writeFileAtomic(glb, assets::gltf::encodeGlb(doc))));
    return convertWithGi(glb, name, kPaneLetsAllThrough);
}

double meanIndirect(const CapturedImage& c) {
    double s = 0;
    size_t n = 0;
    for (size_t i = 0; i < c.f32.size(); i += 4) {
        if (!std::isfinite(c.f32[i])) continue;
        s += reference::luminance({c.f32[i], c.f32[i + 1], c.f32[i + 2]});
        ++n;
    }
    return n ? s / double(n) : 0.0;
}

// The box room with its sun shining up from below the floor (the truth: no light inside).
const std::string& sunBelowBoxRoom() {
    static const std::string path = giVariant("sun-below", [](gltf::Document& doc) {
        for (gltf::Node& n : doc.nodes)
            if (n.name == "sun") n.rotation = {0.70710678f, 0, 0, 0.70710678f}; // shines along +Y
    });
    return path;
}

TEST(GiPipeline, ASunBelowTheHorizonLightsNothingInsideTheRoom) {
    const std::string& below = sunBelowBoxRoom();
    RenderSettings s = giSettings();
    GiFrameResult up = renderGi(giBoxRoom(), kView, s), down = renderGi(below, kView, s);
    ASSERT_TRUE(allFinite(down.indirect));
    ASSERT_TRUE(allFinite(down.volume));
    EXPECT_GT(meanIndirect(up.indirect), 0.0);
    // The truth is 0: the floor stops the sun and its underside reflects downwards. The volume's
    // diffusion carries some of that light sideways, up outside the walls and in through the
    // open side: measured 8.4 % of the sunlit room's indirect light (5.7 % while the captures
    // showed the glass pane's light instead of the boxes' behind it; 7.5 % before the geometry
    // lobe was scaled to block a full face).
    EXPECT_LT(meanIndirect(down.indirect), 0.11 * meanIndirect(up.indirect));
}

TEST(GiPipeline, AMillionUnitsFromTheOriginGivesTheSameIndirectLight) {
    std::string far = giVariant("far", [](gltf::Document& doc) {
        assets::SceneTransform t;
        t.origin = {1e6f, 0, -1e6f};
        EXPECT_EQ(assets::applySceneTransform(doc, t), "");
    });
    RenderSettings s = giSettings();
    s.giCascades = 1; // fitted to the scene: the same cells relative to it in both
    CameraState away = kView;
    away.position += glm::dvec3(1e6, 0, -1e6);
    GiFrameResult near = renderGi(giBoxRoom(), kView, s), distant = renderGi(far, away, s);
    ASSERT_TRUE(allFinite(distant.indirect));
    double a = meanIndirect(near.indirect), b = meanIndirect(distant.indirect);
    EXPECT_GT(a, 0.0);
    EXPECT_NEAR(b / a, 1.0, 0.02);
}

} // namespace
} // namespace pnb::player::test

namespace pnb::player::test {
namespace {

TEST(GiPipeline, CascadesBlendWithoutASeam) {
    // Two cascades following the camera (0.4 and 0.8 m cells) against the coarse one alone
    // (0.8 m cells: the same placement and data as the coarse cascade of the pair). The atrium:
    // no forward surfaces, so every pixel's look-up point is the deferred surface's.
    RenderSettings pair = giSettings();
    pair.giCascades = 2;
    pair.giCells = 16;
    pair.giCellSize = 0.4f;
    RenderSettings coarse = pair;
    coarse.giCascades = 1;
    coarse.giCellSize = 0.8f;
    const CameraState view = lookAt({-6, 6, 6}, {2, 1, -2});
    static const std::string atrium = convertWithGi(std::string(PNB_SCENE_DIR) + "/atrium.glb", "atrium");
    GiFrameResult c = renderGi(atrium, view, pair, 128, 96), k = renderGi(atrium, view, coarse, 128, 96);
    ASSERT_EQ(c.indirect.f32.size(), k.indirect.f32.size());
    auto fine = placeCascades(1, 16, 0.4, glm::dvec3(0), glm::dvec3(1), view.position,
                              glm::dvec3(glm::mat3_cast(glm::quat(view.rotation)) * glm::vec3(0, 0, -1)))[0];
    const uint32_t w = c.indirect.width, h = c.indirect.height;
    // How far inside the fine cascade each pixel's look-up point is (cells; <= 0.5: not used).
    std::vector<double> inside(size_t(w) * h, -1.0);
    double largest = 0;
    for (size_t i = 0; i < inside.size(); ++i) {
        glm::dvec3 p(c.position.f32[i * 3], c.position.f32[i * 3 + 1], c.position.f32[i * 3 + 2]);
        glm::dvec3 n(c.normal.f32[i * 3], c.normal.f32[i * 3 + 1], c.normal.f32[i * 3 + 2]);
        if (!std::isfinite(p.x) || glm::length(n) < 0.5) continue; // deferred surfaces only
        glm::dvec3 q = (p + view.position - fine.origin) / fine.cellSize + 0.5 * n;
        inside[i] = std::min({q.x, q.y, q.z, 16 - q.x, 16 - q.y, 16 - q.z});
        if (std::abs(inside[i] - 0.5) < 1e-3) inside[i] = -1.0; // float rounding decides: skip
        largest = std::max(largest, double(c.indirect.f32[i * 4]));
    }
    ASSERT_GT(largest, 0.0);
    size_t outsidePixels = 0, boundaryPairs = 0;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            size_t i = size_t(y) * w + x;
            if (inside[i] < 0 || inside[i] > 0.5) continue;
            // Outside the fine cascade the pair shows the coarse cascade: exactly but for rounding
            // (the injection's fixed-point unit follows the finest cell, so the pair's coarse
            // cascade rounds its light differently: measured 1 fp16 step, 3e-5 at 0.046).
            ++outsidePixels;
            ASSERT_NEAR(c.indirect.f32[i * 4], k.indirect.f32[i * 4], 2e-4 * largest)
                << x << "," << y;
            // Across its border the blend starts at 0: a neighbour just inside (weight <= 1/8)
            // differs from this pixel by at most the coarse image's own step plus 1/8 of the range.
            for (size_t j : {i + 1, i + w}) {
                if (j >= inside.size() || inside[j] <= 0.5 || inside[j] > 0.75) continue;
                ++boundaryPairs;
                double step = std::abs(c.indirect.f32[j * 4] - c.indirect.f32[i * 4]);
                double coarseStep = std::abs(k.indirect.f32[j * 4] - k.indirect.f32[i * 4]);
                EXPECT_LE(step, coarseStep + 0.125 * largest) << x << "," << y;
            }
        }
    EXPECT_GT(outsidePixels, 100u);
    EXPECT_GT(boundaryPairs, 10u);
}

TEST(GiPipeline, AMillionTimesBrighterSunGivesTheSameVolume) {
    std::string bright = giVariant("bright-sun", [](gltf::Document& doc) {
        for (gltf::Light& l : doc.lights)
            if (l.type == gltf::LightType::Directional) l.intensity *= 1e6f;
    });
    RenderSettings s = giSettings();
    GiFrameResult normal = renderGi(giBoxRoom(), kView, s, 64, 48), strong = renderGi(bright, kView, s, 64, 48);
    // The volumes hold radiance over the sun's irradiance: no fp16 overflow, the same numbers.
    ASSERT_EQ(normal.volume.f32.size(), strong.volume.f32.size());
    ASSERT_TRUE(allFinite(strong.volume));
    EXPECT_EQ(normal.volume.f32, strong.volume.f32);
    // The image has no NaN (the RGBA16F HDR target itself saturates at 65504, direct light
    // first: a limit of the frame's format, not of GI).
    for (float v : strong.hdr.f32) ASSERT_FALSE(std::isnan(v));
    for (float v : strong.indirect.f32) ASSERT_FALSE(std::isnan(v));
}

} // namespace
} // namespace pnb::player::test

namespace pnb::player::test {
namespace {

// The player's indirect light against the one-bounce truth (sun only: what the LPV models) at
// the exact pixels it drew, default settings.
reference::IndirectErrorMetrics accuracy(const std::string& path, const CameraState& view,
                                         const RenderSettings& settings = giSettings()) {
    GiFrameResult r = renderGi(path, view, settings, 96, 72);
    auto container = Container::open(path);
    EXPECT_TRUE(container.ok());
    auto scene = readScene(*container);
    EXPECT_TRUE(scene.ok());
    auto tracer = reference::IndirectTracer::build(*scene, view.position);
    EXPECT_TRUE(tracer.ok());
    if (!tracer) return {};
    const size_t pixels = size_t(r.position.width) * r.position.height;
    std::vector<glm::vec3> points(pixels), player(pixels), normals;
    for (size_t i = 0; i < pixels; ++i) {
        points[i] = {r.position.f32[i * 3], r.position.f32[i * 3 + 1], r.position.f32[i * 3 + 2]};
        player[i] = std::isfinite(points[i].x)
                        ? glm::vec3(r.indirect.f32[i * 4], r.indirect.f32[i * 4 + 1], r.indirect.f32[i * 4 + 2])
                        : glm::vec3(NAN);
    }
    normals = reference::normalsFromPositions(points, int(r.position.width), int(r.position.height));
    for (size_t i = 0; i < pixels; ++i) {
        glm::vec3 n(r.normal.f32[i * 3], r.normal.f32[i * 3 + 1], r.normal.f32[i * 3 + 2]);
        if (glm::length(n) > 0.5f) normals[i] = n;
    }
    reference::IndirectSettings s;
    s.samples = 128;
    s.lights = reference::IndirectLights::Sun;
    std::vector<glm::vec3> truth(pixels), error(pixels);
    (*tracer)->irradiance(points, normals, s, truth, error);
    reference::IndirectErrorMetrics m = reference::compareIndirect(player, truth, error);
    std::printf("  rmse %.1f %% (truth noise %.1f %%), energy %.3f, leak %.2f %%, rmse / best constant %.3f, "
                "correlation %.3f\n",
                m.relativeRmsePercent, m.referenceNoisePercent, m.energyRatio, m.leakPercent, m.rmseOverBestConstant,
                m.correlation);
    return m;
}

// The issue's targets for the default LPV (docs/PLAYER.md, Global illumination): closer to the
// truth than the best constant ambient by a quarter, the right pattern (correlation), the right
// total light and its colour, and little light where the truth has none.
void expectLpvTargets(const reference::IndirectErrorMetrics& m) {
    EXPECT_GT(m.pixels, 3000u);
    EXPECT_LT(m.rmseOverBestConstant, 0.75);
    EXPECT_GT(m.correlation, 0.8);
    EXPECT_GT(m.energyRatio, 0.8);
    EXPECT_LT(m.energyRatio, 1.25);
    for (double c : m.channelRatio)
        EXPECT_NEAR(c / m.energyRatio, 1.0, 0.1);
}

TEST(GiAccuracy, AtriumAgainstTheOneBounceTruth) {
    static const std::string atrium = convertWithGi(std::string(PNB_SCENE_DIR) + "/atrium.glb", "atrium");
    reference::IndirectErrorMetrics m = accuracy(atrium, lookAt({-9.5, 7.2, 9.5}, {2, 1, -2}));
    // Measured (96x72, 128 rays): RMSE over the best constant's 0.478, correlation 0.909, energy
    // 1.159, leak 0.59 % (Kaplanyan-Dachsbacher propagation, before: 0.752, 0.732, 0.847).
    expectLpvTargets(m);
    EXPECT_LT(m.leakPercent, 2.0);
}

TEST(GiAccuracy, BoxRoomAgainstTheOneBounceTruth) {
    reference::IndirectErrorMetrics m = accuracy(giBoxRoom(), lookAt({0, 5, 14}, {0, 4, 0}));
    // Measured: 0.574, correlation 0.838, energy 0.990, leak 2.95 % (before: 1.076, 0.577,
    // 0.554: the light of one floor patch has to climb the walls, and diffusion kept it low).
    expectLpvTargets(m);
    EXPECT_LT(m.leakPercent, 6.0);
}

// The box room as it is converted by default: its blue pane casts, so the sun that enters through
// the open front reaches the floor tinted (issue 43), in the player's RSM and in the truth, which
// attenuates by the pane's transmittance on its way as well (docs/REFERENCE.md).
TEST(GiAccuracy, BoxRoomThroughItsPaneAgainstTheGlassTruth) {
    const std::string glassRoom = giBoxRoomGlass();
    const CameraState view = lookAt({0, 5, 14}, {0, 4, 0});
    // Measured at 96x72, 128 rays: LPV rmse / best constant 0.565, correlation 0.844, energy 0.98
    // (without the pane casting: 0.574, 0.838, 0.99); probes 0.424, 0.909, energy 1.06.
    reference::IndirectErrorMetrics lpv = accuracy(glassRoom, view);
    expectLpvTargets(lpv);
    RenderSettings probes = giSettings();
    probes.giTechnique = GiTechnique::Probes;
    reference::IndirectErrorMetrics p = accuracy(glassRoom, view, probes);
    EXPECT_LT(p.rmseOverBestConstant, 0.6);
    EXPECT_GT(p.correlation, 0.85);
    EXPECT_GT(p.energyRatio, 0.7);
    EXPECT_LT(p.energyRatio, 1.25);
}

// gi.technique = probes: a grid of probes gathering the RSM's clustered lights through the
// scene's occupancy grid. Measured against the same truth in the same pixels as the LPV
// (docs/PLAYER.md, Global illumination).
RenderSettings probeSettings() {
    RenderSettings s = giSettings();
    s.giTechnique = GiTechnique::Probes;
    return s;
}

void expectProbesBeatTheConstant(const std::string& path, const CameraState& view) {
    for (ProbeVisibility visibility : {ProbeVisibility::Depth, ProbeVisibility::Exact}) {
        SCOPED_TRACE(visibility == ProbeVisibility::Depth ? "gi.probe_visibility=depth" : "gi.probe_visibility=exact");
        RenderSettings settings = probeSettings();
        settings.giProbeVisibility = visibility;
        reference::IndirectErrorMetrics probes = accuracy(path, view, settings);
        EXPECT_GT(probes.pixels, 3000u);
        // Measured at 96x72, 128 rays (box room / atrium), depth maps: RMSE over the best constant's
        // 0.444 / 0.532, correlation 0.897 / 0.891, energy 0.948 / 0.795, leak 1.7 / 0.4 %; the
        // exact walk: 0.453 / 0.536, 0.892 / 0.891, 1.016 / 0.793, 1.4 / 0.4 % (LPV 0.574 / 0.478).
        // (16^3 probes, each blocked by the surfaces beside it: 0.537 / 0.608, energy 0.970 / 0.749.)
        EXPECT_LT(probes.rmseOverBestConstant, 0.6);
        EXPECT_GT(probes.correlation, 0.85);
        EXPECT_GT(probes.energyRatio, 0.7);
        EXPECT_LT(probes.energyRatio, 1.25);
        EXPECT_LT(probes.leakPercent, 2.5);
    }
}

TEST(GiProbes, BoxRoomCloserToTheTruthThanTheBestConstant) {
    expectProbesBeatTheConstant(giBoxRoom(), lookAt({0, 5, 14}, {0, 4, 0}));
}

TEST(GiProbes, AtriumCloserToTheTruthThanTheBestConstant) {
    static const std::string atrium = convertWithGi(std::string(PNB_SCENE_DIR) + "/atrium.glb", "atrium");
    expectProbesBeatTheConstant(atrium, lookAt({-9.5, 7.2, 9.5}, {2, 1, -2}));
}

TEST(GiProbes, AllocateOnlyTheirOwnAndSwitchBackToLpv) {
    RenderSettings probes = probeSettings();
    // GI's own: the probes' sky-visibility volume (probes^3 x 8 bytes, which ibl.visibility=auto
    // adds with the box room's environment) is the sky's.
    probes.iblVisibility = SkyVisibility::None;
    GiFrameResult p = renderGi(giBoxRoom(), kView, probes, 64, 48);
    GiFrameResult l = renderGi(giBoxRoom(), kView, giSettings(), 64, 48);
    ASSERT_TRUE(allFinite(p.indirect));
    EXPECT_GT(meanIndirect(p.indirect), 0.0);
    // The volume lighting reads: gi.probe_cells^3 probes, one grid (LPV: gi.cells^3 x cascades).
    EXPECT_EQ(p.volume.width, probes.giProbeCells);
    EXPECT_EQ(p.volume.height, probes.giProbeCells * probes.giProbeCells);
    // RSM 256^2 (1 MiB), 20^3 probes, their 16x16 fp16 depth maps with a border and needed flags,
    // 64^3 voxels, 32^2 VPLs: no propagation volumes, geometry volume or atomic buffers; with the
    // exact walk, no depth maps.
    const uint64_t probeCount = 20ull * 20 * 20;
    const uint64_t exact = 256ull * 256 * 16 + probeCount * 3 * 8 + 64ull * 64 * 64 + 32ull * 32 * 48;
    EXPECT_EQ(p.memory.giBytes, exact + probeCount * (18 * 18 * 2 + 4));
    RenderSettings walk = probes;
    walk.giProbeVisibility = ProbeVisibility::Exact;
    EXPECT_EQ(renderGi(giBoxRoom(), kView, walk, 64, 48).memory.giBytes, exact);
    // One renderer switching technique frees the other's objects and gives the same images.
    auto scene = loadScene(giBoxRoom());
    ASSERT_TRUE(scene.ok());
    auto renderer = Renderer::create(**scene, probes);
    ASSERT_TRUE(renderer.ok());
    ASSERT_TRUE((*renderer)->render(kView, 64, 48).ok());
    (*renderer)->setSettings(giSettings());
    ASSERT_TRUE((*renderer)->render(kView, 64, 48).ok());
    EXPECT_EQ((*renderer)->targetMemory().giBytes, l.memory.giBytes);
    auto back = (*renderer)->capture(CaptureBuffer::Indirect);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(back->f32, l.indirect.f32);
}

TEST(GiProbes, TheFloorHidesASunBelowTheHorizon) {
    const std::string& below = sunBelowBoxRoom();
    RenderSettings s = probeSettings();
    GiFrameResult up = renderGi(giBoxRoom(), kView, s), down = renderGi(below, kView, s);
    ASSERT_TRUE(allFinite(down.indirect));
    EXPECT_GT(meanIndirect(up.indirect), 0.0);
    // The truth is 0: the floor's underside reflects downwards and the occupancy grid holds the
    // floor between that light and every probe in the room. What remains is the look-up's
    // trilinear blend with the probes under the floor, near its edges: measured 5.1 % of the
    // sunlit room's indirect light (LPV: 8.4 %).
    EXPECT_LT(meanIndirect(down.indirect), 0.07 * meanIndirect(up.indirect));
}

TEST(GiProbes, AGridFollowingTheCameraMovesByACellWithoutChangingItsLight) {
    // gi.cell_size > 0 (or a scene larger than gi.probe_max_spacing allows): the grid follows the
    // camera in whole cells, so the probes it keeps stand where they stood and should hold the
    // same light; what changes is the RSM's and the occupancy grid's extent (they cover the grid)
    // and the probes at the edges. A pop here would show as the camera crosses a cell boundary.
    RenderSettings s = probeSettings();
    s.giCellSize = 0.6f;
    s.giProbeCells = 16;
    const double cell = s.giCellSize;
    glm::dvec3 forward = glm::dvec3(glm::mat3_cast(glm::quat(kView.rotation)) * glm::vec3(0, 0, -1));
    auto before = placeCascades(1, s.giProbeCells, cell, glm::dvec3(0), glm::dvec3(1), kView.position, forward);
    // Step along x to just past the next cell boundary: the grid moves by exactly one cell.
    CameraState moved = kView;
    const double centreX = kView.position.x + forward.x * 0.25 * cell * s.giProbeCells - 0.5 * cell * s.giProbeCells;
    moved.position.x += (std::floor(centreX / cell) + 1.0) * cell - centreX + 1e-3 * cell;
    auto after = placeCascades(1, s.giProbeCells, cell, glm::dvec3(0), glm::dvec3(1), moved.position, forward);
    ASSERT_NEAR(after[0].origin.x - before[0].origin.x, cell, 1e-9);
    ASSERT_EQ(after[0].origin.y, before[0].origin.y);
    ASSERT_EQ(after[0].origin.z, before[0].origin.z);
    GiFrameResult a = renderGi(giBoxRoom(), kView, s, 64, 48), b = renderGi(giBoxRoom(), moved, s, 64, 48);
    const size_t n = s.giProbeCells;
    ASSERT_EQ(a.volume.f32.size(), n * n * n * 12);
    ASSERT_EQ(b.volume.f32.size(), a.volume.f32.size());
    // The probes both grids hold, away from their edges (an edge probe's rays and lights end at
    // the grid): before's x + 1 is after's x.
    double changed = 0, total = 0;
    for (size_t z = 2; z + 2 < n; ++z)
        for (size_t y = 2; y + 2 < n; ++y)
            for (size_t x = 3; x + 2 < n; ++x) {
                const size_t i = x + n * (y + n * z), j = (x - 1) + n * (y + n * z);
                for (int ch = 0; ch < 3; ++ch) {
                    changed += std::abs(double(b.volume.f32[j * 12 + ch * 4]) - a.volume.f32[i * 12 + ch * 4]);
                    total += std::abs(double(a.volume.f32[i * 12 + ch * 4]));
                }
            }
    ASSERT_GT(total, 0.0);
    std::printf("[ figure ] probes' grid moved a cell: their light changed by %.2f %% (band 0, inner probes)\n",
                100.0 * changed / total);
    EXPECT_LT(changed / total, 0.05);
}

TEST(GiProbes, ExtremesStayFinite) {
    RenderSettings s = probeSettings();
    for (auto [cells, voxels, vpls] : {std::tuple{4u, 16u, 4u}, std::tuple{64u, 16u, 4u}, std::tuple{4u, 256u, 128u}}) {
        s.giProbeCells = cells;
        s.giVoxels = voxels;
        s.giVpls = vpls;
        GiFrameResult r = renderGi(giBoxRoom(), kView, s, 32, 24);
        EXPECT_TRUE(allFinite(r.indirect)) << cells << " " << voxels << " " << vpls;
        EXPECT_GT(meanIndirect(r.indirect), 0.0) << cells << " " << voxels << " " << vpls;
    }
}

// The GI box room read and uploaded with its Scene kept beside the container it points into, so
// that a test can edit materials and push them with updateMaterials. Empty `gpu` on failure.
struct EditableBoxRoom {
    std::optional<Container> container;
    std::optional<Scene> scene;
    std::unique_ptr<GpuScene> gpu;
};

EditableBoxRoom editableBoxRoom() {
    EditableBoxRoom r;
    auto container = Container::open(giBoxRoom());
    EXPECT_TRUE(container.ok());
    if (!container) return r;
    r.container.emplace(std::move(*container));
    auto scene = readScene(*r.container);
    EXPECT_TRUE(scene.ok());
    if (!scene) return r;
    r.scene.emplace(std::move(*scene));
    auto gpu = uploadScene(*r.scene);
    EXPECT_TRUE(gpu.ok());
    if (gpu) r.gpu = std::move(*gpu);
    return r;
}

TEST(GiProbes, TheCacheGivesTheSameLightAndFollowsMaterialEdits) {
    EditableBoxRoom room = editableBoxRoom();
    ASSERT_TRUE(room.gpu);
    Scene& scene = *room.scene;
    GpuScene& gpu = *room.gpu;
    RenderSettings cached = probeSettings(), fresh = probeSettings();
    fresh.giProbeCache = false;
    auto a = Renderer::create(gpu, cached), b = Renderer::create(gpu, fresh);
    ASSERT_TRUE(a.ok() && b.ok());
    auto indirect = [](Renderer& r, const CameraState& view) {
        EXPECT_TRUE(r.render(view, 64, 48).ok());
        auto c = r.capture(CaptureBuffer::Indirect);
        EXPECT_TRUE(c.ok());
        return c ? c->f32 : std::vector<float>{};
    };
    const CameraState elsewhere = lookAt({3, 2, 6}, {0, 1, 0});
    std::vector<float> first = indirect(**a, kView);
    indirect(**a, elsewhere); // a camera move alone keeps the probes
    std::vector<float> again = indirect(**a, kView), everyFrame = indirect(**b, kView);
    EXPECT_EQ(again, first);
    ASSERT_EQ(everyFrame.size(), first.size());
    double worst = 0, total = 0;
    for (size_t i = 0; i < first.size(); ++i)
        if (std::isfinite(first[i])) worst = std::max(worst, double(std::fabs(first[i] - everyFrame[i]))), total += first[i];
    EXPECT_LT(worst, 1e-3 * total / double(first.size()) + 1e-6); // the RSM drawn from another origin
    // A material edit is a new input: the sunlit floor turned red bleeds red (the red wall is
    // edge-on to this sun and bleeds nothing either way).
    auto redOf = [](const std::vector<float>& v) {
        double r = 0, g = 0;
        for (size_t i = 0; i < v.size(); i += 4)
            if (std::isfinite(v[i])) r += v[i], g += v[i + 1];
        return r / g;
    };
    for (auto& m : scene.materials)
        if (scene.str(m.name) == "checker-floor") m.baseColorFactor = {1.0f, 0.1f, 0.1f, 1.0f};
    ASSERT_TRUE(updateMaterials(gpu, scene).ok());
    std::vector<float> edited = indirect(**a, kView);
    EXPECT_GT(redOf(edited), 1.5 * redOf(first));
    std::vector<float> editedEveryFrame = indirect(**b, kView);
    EXPECT_NEAR(redOf(edited), redOf(editedEveryFrame), 1e-3 * redOf(edited));
}

TEST(GiPipeline, ASceneOfMetalAloneRunsNoGiPassAndAllocatesNothing) {
    // Diffuse light bounces off diffuse albedo, base colour x (1 - metallic): with every material
    // metal, the bounce is zero everywhere, so neither technique runs a pass or holds memory;
    // one material made dielectric again brings GI back (a material edit, as pnb-edit makes).
    EditableBoxRoom room = editableBoxRoom();
    ASSERT_TRUE(room.gpu);
    Scene& scene = *room.scene;
    GpuScene& gpu = *room.gpu;
    for (auto& m : scene.materials) {
        m.metallicFactor = 1.0f;
        m.textures[size_t(TextureSlotKind::MetallicRoughness)].texture = kNone;
    }
    ASSERT_TRUE(updateMaterials(gpu, scene).ok());
    for (RenderSettings s : {giSettings(), probeSettings()}) {
        auto r = Renderer::create(gpu, s);
        ASSERT_TRUE(r.ok());
        ASSERT_TRUE((*r)->render(kView, 64, 48).ok());
        EXPECT_EQ((*r)->targetMemory().giBytes, 0u) << int(s.giTechnique);
        scene.materials.front().metallicFactor = 0.0f;
        ASSERT_TRUE(updateMaterials(gpu, scene).ok());
        ASSERT_TRUE((*r)->render(kView, 64, 48).ok());
        EXPECT_GT((*r)->targetMemory().giBytes, 0u) << int(s.giTechnique);
        scene.materials.front().metallicFactor = 1.0f;
        ASSERT_TRUE(updateMaterials(gpu, scene).ok());
    }
}

// lighting.sun_turn_deg on a static view: the indirect light's luminance per frame while the sun
// turns by `step` degrees a frame (both techniques: a fresh RSM, volume or gather every frame).
std::vector<std::vector<double>> indirectWhileTheSunTurns(RenderSettings s, int frames, float step) {
    std::vector<std::vector<double>> out;
    auto scene = loadScene(giBoxRoom());
    EXPECT_TRUE(scene.ok());
    if (!scene) return out;
    auto renderer = Renderer::create(**scene, s);
    EXPECT_TRUE(renderer.ok());
    if (!renderer) return out;
    for (int f = 0; f < frames; ++f) {
        s.sunTurnDeg = step * float(f);
        (*renderer)->setSettings(s);
        EXPECT_TRUE((*renderer)->render(kView, 96, 72).ok());
        auto c = (*renderer)->capture(CaptureBuffer::Indirect);
        EXPECT_TRUE(c.ok());
        if (!c) return out;
        std::vector<double> l;
        for (size_t i = 0; i + 3 < c->f32.size(); i += 4)
            if (std::isfinite(c->f32[i])) l.push_back(reference::luminance({c->f32[i], c->f32[i + 1], c->f32[i + 2]}));
        out.push_back(std::move(l));
    }
    return out;
}

// Frame-to-frame change: sum |L_i - L_i-1| / sum L_i-1, per step.
std::vector<double> frameChanges(const std::vector<std::vector<double>>& frames) {
    std::vector<double> changes;
    for (size_t f = 1; f < frames.size(); ++f) {
        double changed = 0, total = 0;
        for (size_t i = 0; i < frames[f].size() && i < frames[f - 1].size(); ++i)
            changed += std::fabs(frames[f][i] - frames[f - 1][i]), total += frames[f - 1][i];
        changes.push_back(total > 0 ? changed / total : 0.0);
    }
    return changes;
}

TEST(GiTemporal, ASlowlyTurningSunChangesTheIndirectLightWithoutPopping) {
    // 0.25 degrees a frame, a hundred times faster than the real sun at 60 Hz. The light has to
    // follow smoothly: no step changes the image much more than a typical one, none by more
    // than a few percent. Measured (box room, 96x72, 15 steps): LPV median 1.5 %, worst 2.2 %;
    // probes 2.0 %, 3.0 % — 7.9 % before their RSM stopped snapping to whole texels (a snap
    // jump changed every VPL block's texels at once).
    for (RenderSettings s : {giSettings(), probeSettings()}) {
        std::vector<double> c = frameChanges(indirectWhileTheSunTurns(s, 16, 0.25f));
        ASSERT_EQ(c.size(), 15u);
        std::vector<double> sorted = c;
        std::sort(sorted.begin(), sorted.end());
        const double median = sorted[sorted.size() / 2], worst = sorted.back();
        std::printf("[ figure ] %s, sun turning 0.25 deg/frame: frame-to-frame change median %.2f %%, worst %.2f %%\n",
                    s.giTechnique == GiTechnique::Probes ? "probes" : "lpv", 100 * median, 100 * worst);
        EXPECT_GT(median, 0.0) << "the light follows the sun";
        EXPECT_LT(worst, 0.05);
        EXPECT_LT(worst, 2.5 * median + 0.002) << "a step that pops";
    }
}

TEST(GiTemporal, TheSunTurnedHalfwayRoundLeavesTheRoomInItsOwnShadow) {
    // The sun enters through the open side; turned 180 degrees about +Y it falls on the back
    // wall's outside, and the room gets (next to) no bounce.
    for (RenderSettings s : {giSettings(), probeSettings()}) {
        std::vector<std::vector<double>> f = indirectWhileTheSunTurns(s, 2, 180.0f);
        ASSERT_EQ(f.size(), 2u);
        const double lit = std::accumulate(f[0].begin(), f[0].end(), 0.0);
        const double turned = std::accumulate(f[1].begin(), f[1].end(), 0.0);
        std::printf("[ figure ] %s: indirect light with the sun turned 180 deg: %.3f of the sunlit room's\n",
                    s.giTechnique == GiTechnique::Probes ? "probes" : "lpv", turned / lit);
        EXPECT_GT(lit, 0.0);
        EXPECT_LT(turned, 0.25 * lit) << int(s.giTechnique);
    }
}

} // namespace
} // namespace pnb::player::test
