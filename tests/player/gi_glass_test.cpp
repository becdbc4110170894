// GI and sky light through glass (issue 43): a closed box whose roof is a red pane (colour
// (1, 0, 0), alpha 0.5: T = (0.5, 0, 0)) under a sun from straight above. The pane casting
// (casts_shadows true) against the same pane letting everything through (false, as before issue
// 43): the indirect light on a wall is the bounce off the floor the sun lights through the roof,
// so it is red and half as bright, for both GI techniques; the sky a probe sees through the roof
// is tinted and dimmed alike (ibl.visibility = probes). Without casting glass nothing of it is
// allocated. And a room divided by a vertical red pane, the sun on the floor of one half: the
// LPV's bounce across the pane to the other half's far wall is tinted red (lpv_propagate.comp,
// GLASS).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <glm/glm.hpp>

#include "pnb/atomic_file.h"
#include "pnb_converter/convert.h"
#include "render_fixture.h"

namespace pnb::player::test {
namespace {

// The room: a floor slab, four wall slabs 0.2 thick around a 4 x 3 x 4 inside, and the roof pane
// above them all (wider than the walls, so the sun reaches no wall top but through it).
gltf::Document glassRoofRoom() {
    gltf::Document doc;
    gltf::Material white;
    white.name = "white";
    white.baseColorFactor = {0.8f, 0.8f, 0.8f, 1};
    gltf::Material pane;
    pane.name = "pane";
    pane.baseColorFactor = {1, 0, 0, 0.5f};
    pane.alphaMode = gltf::AlphaMode::Blend;
    pane.doubleSided = true;
    doc.materials = {white, pane};
    addObject(doc, "floor", box(4.4f, 0.2f, 4.4f, 0), {0, -0.1f, 0});
    addObject(doc, "wall-left", box(0.2f, 3.0f, 4.4f, 0), {-2.1f, 1.5f, 0});
    addObject(doc, "wall-right", box(0.2f, 3.0f, 4.4f, 0), {2.1f, 1.5f, 0});
    addObject(doc, "wall-back", box(4.4f, 3.0f, 0.2f, 0), {0, 1.5f, -2.1f});
    addObject(doc, "wall-front", box(4.4f, 3.0f, 0.2f, 0), {0, 1.5f, 2.1f});
    addObject(doc, "roof", quad(4.8f, 4.8f, 1), {0, 3.05f, 0}, {0.70710678f, 0, 0, 0.70710678f});
    addSun(doc, 3.0f, gltf::lookRotation({0.05f, -1.0f, 0.03f}));
    return doc;
}

// The same room cut in two by a vertical pane at x = 0.05 (the same red, 6 x 6: it reaches past
// the walls, floor and roof, so no cell path goes round it), an opaque black roof (black: it
// injects no light of its own) but for an opening over the left half, where the sun lights the
// floor. The right half's far wall (x = 2) receives only the bounce across the pane.
gltf::Document paneDividedRoom() {
    gltf::Document doc = glassRoofRoom();
    gltf::Material black;
    black.name = "black";
    black.baseColorFactor = {0, 0, 0, 1};
    doc.materials.push_back(black);
    doc.nodes.pop_back(); // the sun, added again last
    doc.lights.clear();
    doc.meshes[5] = {"pane", {quad(6.0f, 6.0f, 1)}};
    doc.nodes[5].translation = {0.05f, 1.5f, 0};
    doc.nodes[5].rotation = {0, 0.70710678f, 0, 0.70710678f}; // facing +x
    addObject(doc, "roof-right", box(2.45f, 0.2f, 4.4f, 2), {0.975f, 3.1f, 0});
    addObject(doc, "roof-left-rim", box(0.3f, 0.2f, 4.4f, 2), {-2.05f, 3.1f, 0});
    addSun(doc, 3.0f, gltf::lookRotation({-0.05f, -1.0f, 0.03f}));
    return doc;
}

// A room converted with GI and the analytic sky, the pane casting or not (through the sidecar).
std::string convertRoom(const gltf::Document& room, const std::string& prefix, bool paneCasts) {
    // This binary's scratch directory, removed when the process ends.
    struct Dir {
        std::filesystem::path path =
            std::filesystem::temp_directory_path() / ("pnb_gi_glass_" + std::to_string(::getpid()));
        Dir() { std::filesystem::create_directories(path); }
        ~Dir() {
            std::error_code ec;
            std::filesystem::remove_all(path, ec);
        }
    };
    static const Dir scratch;
    const std::string dir = scratch.path.string();
    const std::string name = prefix + (paneCasts ? "glass-casts" : "glass-passes");
    const std::string glb = dir + "/" + name + ".glb";
    EXPECT_TRUE(isOk(pnb::writeFileAtomic(glb, gltf::encodeGlb(room))));
    converter::ConvertSettings s;
    s.sidecar = dir + "/" + name + ".sidecar.json";
    std::ofstream(s.sidecar) << R"({"materials": {"pane": {"casts_shadows": )" << (paneCasts ? "true" : "false")
                             << "}}}";
    s.input = glb;
    s.output = dir + "/" + name + ".pnb";
    s.jobs = 1;
    s.validateShaders = false;
    s.renderSettings = {{"gi.enabled", "true"}};
    s.environment.sky = true;
    auto r = converter::convertScene(s);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return s.output;
}

const std::string& roomPath(bool paneCasts) {
    static const std::string casts = convertRoom(glassRoofRoom(), "", true),
                             passes = convertRoom(glassRoofRoom(), "", false);
    return paneCasts ? casts : passes;
}

const std::string& dividedRoomPath(bool paneCasts) {
    static const std::string casts = convertRoom(paneDividedRoom(), "divided-", true),
                             passes = convertRoom(paneDividedRoom(), "divided-", false);
    return paneCasts ? casts : passes;
}

// Inside the room, looking at the back wall.
const CameraState kWallView = lookAt({0, 1.5, 1.6}, {0, 1.5, -2});
// In the divided room's right half, the pane at the camera's back, looking at the far wall (x = 2).
const CameraState kFarWallView = lookAt({0.6, 1.5, 0}, {2, 1.5, 0});
constexpr uint32_t kW = 64, kH = 48;

struct Captures {
    CapturedImage indirect, sky;
    uint64_t giBytes = 0;
};

Captures renderRoom(bool paneCasts, const RenderSettings& s, bool divided = false) {
    Captures out;
    const CameraState view = divided ? kFarWallView : kWallView;
    auto scene = loadScene(divided ? dividedRoomPath(paneCasts) : roomPath(paneCasts));
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
    if (!scene) return out;
    auto renderer = Renderer::create(**scene, s);
    EXPECT_TRUE(renderer.ok());
    if (!renderer) return out;
    EXPECT_TRUE((*renderer)->warmUp(view, kW, kH).ok());
    EXPECT_TRUE((*renderer)->render(view, kW, kH).ok());
    out.indirect = std::move(*(*renderer)->capture(CaptureBuffer::Indirect));
    out.sky = std::move(*(*renderer)->capture(CaptureBuffer::Sky));
    out.giBytes = (*renderer)->targetMemory().giBytes;
    return out;
}

// The mean rgb over the middle half of the image (the back wall, clear of the roof and floor).
glm::dvec3 wallMean(const CapturedImage& image) {
    glm::dvec3 sum(0.0);
    size_t n = 0;
    for (uint32_t y = kH / 4; y < 3 * kH / 4; ++y)
        for (uint32_t x = kW / 4; x < 3 * kW / 4; ++x) {
            const float* p = &image.f32[(size_t(y) * kW + x) * 4];
            sum += glm::dvec3(p[0], p[1], p[2]);
            ++n;
        }
    return n ? sum / double(n) : sum;
}

RenderSettings glassSettings(GiTechnique technique) {
    RenderSettings s;
    s.giEnabled = true;
    s.giTechnique = technique;
    s.shadowResolution = 512;
    s.iblVisibility = technique == GiTechnique::Probes ? SkyVisibility::Probes : SkyVisibility::None;
    return s;
}

void expectRedAtHalf(GiTechnique technique, const char* name) {
    const RenderSettings s = glassSettings(technique);
    Captures passes = renderRoom(false, s), casts = renderRoom(true, s);
    ASSERT_FALSE(passes.indirect.f32.empty());
    ASSERT_FALSE(casts.indirect.f32.empty());
    ASSERT_TRUE(allFinite(casts.indirect));
    const glm::dvec3 before = wallMean(passes.indirect), after = wallMean(casts.indirect);
    // Through the pane the white floor's bounce is as grey as the floor: green as red.
    ASSERT_GT(before.r, 0.0) << name;
    EXPECT_GT(before.g, 0.5 * before.r) << name;
    // Casting: red at about half, green and blue near zero (what remains comes from elsewhere).
    EXPECT_NEAR(after.r / before.r, 0.5, 0.1) << name;
    EXPECT_LT(after.g, 0.05 * before.g) << name;
    EXPECT_LT(after.b, 0.05 * before.b) << name;
}

} // namespace

TEST(GiGlass, LpvBounceBehindARedPaneIsRedAndHalved) { expectRedAtHalf(GiTechnique::Lpv, "lpv"); }

TEST(GiGlass, LpvBounceAcrossARedPaneIsTinted) {
    // The sun reaches the divided room's left floor only; its bounce reaches the right half's far
    // wall only through the pane's cells, where propagation multiplies each colour by its T.
    // One cascade: lighting reads the finest cascade holding a point, and a finer one around the
    // camera would not hold the lit floor (each cascade propagates only what it holds).
    RenderSettings s = glassSettings(GiTechnique::Lpv);
    s.giCascades = 1;
    Captures passes = renderRoom(false, s, true), casts = renderRoom(true, s, true);
    ASSERT_FALSE(passes.indirect.f32.empty());
    ASSERT_FALSE(casts.indirect.f32.empty());
    ASSERT_TRUE(allFinite(casts.indirect));
    const glm::dvec3 before = wallMean(passes.indirect), after = wallMean(casts.indirect);
    std::printf("divided room, far wall indirect: passes (%g %g %g), casts (%g %g %g)\n", before.r, before.g,
                before.b, after.r, after.g, after.b);
    ASSERT_GT(before.r, 0.0);
    EXPECT_GT(before.g, 0.5 * before.r); // the floor's bounce is grey through a pane letting all through
    EXPECT_GT(after.r, 0.3 * before.r);  // red dimmed by about T = 0.5 (not blocked)
    EXPECT_LT(after.r, 0.7 * before.r);
    EXPECT_LT(after.g, 0.2 * before.g);  // green and blue stopped (T = 0): what remains leaks round
    EXPECT_LT(after.b, 0.2 * before.b);
    EXPECT_GT(after.r, 2.0 * after.g);   // red-dominant
}

TEST(GiGlass, LpvGlassCellsOnlyWithCastingGlass) {
    // The LPV's glass cells (RGBA8, cells^3 per cascade) exist only with a casting pane.
    const RenderSettings s = glassSettings(GiTechnique::Lpv);
    Captures passes = renderRoom(false, s, true), casts = renderRoom(true, s, true);
    ASSERT_GT(passes.giBytes, 0u);
    const uint64_t cells = uint64_t(s.giCells) * s.giCells * s.giCells * s.giCascades;
    EXPECT_EQ(casts.giBytes - passes.giBytes, cells * 4);
}

TEST(GiGlass, ProbesBounceBehindARedPaneIsRedAndHalved) { expectRedAtHalf(GiTechnique::Probes, "probes"); }

TEST(GiGlass, ProbesExactVisibilityBounceBehindARedPaneIsRedAndHalved) {
    // The exact walk instead of the depth maps; the same bounce.
    RenderSettings s = glassSettings(GiTechnique::Probes);
    s.giProbeVisibility = ProbeVisibility::Exact;
    Captures passes = renderRoom(false, s), casts = renderRoom(true, s);
    const glm::dvec3 before = wallMean(passes.indirect), after = wallMean(casts.indirect);
    ASSERT_GT(before.r, 0.0);
    EXPECT_NEAR(after.r / before.r, 0.5, 0.1);
    EXPECT_LT(after.g, 0.05 * before.g);
}

TEST(GiGlass, SkySeenThroughAPaneIsTintedAndDimmed) {
    // The sun off: the sky the wall receives comes through the roof alone.
    RenderSettings s = glassSettings(GiTechnique::Probes);
    s.giIntensity = 0;
    Captures passes = renderRoom(false, s), casts = renderRoom(true, s);
    ASSERT_FALSE(passes.sky.f32.empty());
    ASSERT_TRUE(allFinite(casts.sky));
    const glm::dvec3 before = wallMean(passes.sky), after = wallMean(casts.sky);
    ASSERT_GT(before.r, 0.0);
    ASSERT_GT(before.g, 0.0);
    EXPECT_NEAR(after.r / before.r, 0.5, 0.15);
    EXPECT_LT(after.g / before.g, 0.1);
    EXPECT_LT(after.b / before.b, 0.1);
}

TEST(GiGlass, NothingAllocatedWithoutCastingGlass) {
    // Probes: the transmittance grid, the depth rays' transmittance maps and the sky's two more
    // colours exist only with a casting pane.
    const RenderSettings s = glassSettings(GiTechnique::Probes);
    Captures passes = renderRoom(false, s), casts = renderRoom(true, s);
    ASSERT_GT(passes.giBytes, 0u);
    const uint64_t voxels = uint64_t(s.giVoxels) * s.giVoxels * s.giVoxels * 4;
    const uint64_t probes = uint64_t(s.giProbeCells) * s.giProbeCells * s.giProbeCells;
    EXPECT_EQ(casts.giBytes - passes.giBytes, voxels + probes * 18 * 18 * 4 + probes * 2 * 8);
}

} // namespace pnb::player::test
