// The subsystems' CPU plan steps (planLights, planShadows, planGi, planIbl) on a scene built in
// memory: no GL context, no GL object (every handle stays empty).
#include <cmath>

#include <gtest/gtest.h>

#include "frame/frame_context.h"
#include "gi/gi.h"
#include "lights/light_clusters.h"
#include "shadows/shadow_maps.h"
#include "sky/ibl.h"

namespace pnb::player {
namespace {

// A 20 m ground and ten 1 m boxes marching away along -Z, a sun from above and ahead, three
// point lights; the camera at (0, 2, 5) looking down -Z.
struct PlanFixture : ::testing::Test {
    GpuScene scene;
    RenderSettings settings;
    ViewMatrices view;
    LodState lod;
    ShadowContext shadows;

    void SetUp() override {
        GpuMaterial m;
        m.desc.metallicFactor = 0; // diffuse: GI has something to bounce
        m.program = 0;
        m.rsmProgram = 0;
        scene.materials.push_back(m);
        scene.meshes.emplace_back();
        DrawLevel level;
        level.indexCount = 36;
        scene.levels.push_back(level);
        auto addItem = [&](glm::dvec3 lo, glm::dvec3 hi) {
            DrawItem item;
            item.boundsMin = lo;
            item.boundsMax = hi;
            scene.items.push_back(item);
            shadows.casters.push_back({uint32_t(scene.items.size() - 1), 0});
        };
        addItem({-10, -0.1, -20}, {10, 0, 0});
        for (int i = 0; i < 10; ++i) addItem({-0.5, 0, -2.0 * i - 1.5}, {0.5, 1, -2.0 * i - 0.5});
        SceneLight sun;
        sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, -0.2f));
        scene.lights.push_back(sun);
        for (int i = 0; i < 3; ++i) {
            SceneLight point;
            point.desc.type = LightType::Point;
            point.desc.range = 2;
            point.position = {0, 1, -4.0 * i};
            scene.lights.push_back(point);
        }
        scene.shadowProgram = 0;
        scene.giPrograms = true;
        shadows.light = 0;
        shadows.sceneMin = {-10, -0.1, -20};
        shadows.sceneMax = {10, 1, 0};
        CameraState camera;
        camera.position = {0, 2, 5};
        camera.zfar = 100;
        view = makeViewMatrices(camera, 1.5f);
    }
    FrameView in() const { return {scene, settings, view, lod, 384, 256, false}; }
};

TEST_F(PlanFixture, ShadowsFitEveryCascadeAndCullTheirCasters) {
    settings.shadowTechnique = ShadowTechnique::Pssm;
    settings.shadowCascades = 3;
    ShadowBlock block;
    planShadows(in(), shadows, block);
    const ShadowFrame& f = shadows.frame;
    ASSERT_TRUE(f.active);
    EXPECT_EQ(f.off, nullptr);
    EXPECT_EQ(f.cascades, 3u);
    EXPECT_EQ(block.params.x, 3.0f);
    for (uint32_t c = 0; c < 3; ++c) {
        EXPECT_LT(f.splits[c], f.splits[c + 1]);
        EXPECT_EQ(block.cascade[c].y, f.splits[c + 1]);
        EXPECT_GT(block.cascade[c].z, 0.0f) << "texel world size";
    }
    EXPECT_FLOAT_EQ(f.splits[0], 0.1f); // the camera's near plane
    // Every caster in view is listed once, with the cascades it touches.
    EXPECT_EQ(f.casters.size(), scene.items.size());
    ASSERT_EQ(f.masks.size(), f.casters.size());
    for (uint32_t mask : f.masks) EXPECT_NE(mask, 0u);
    EXPECT_TRUE(f.casterBounds.empty());
    // The ground spans every cascade; the farthest box is beyond the first.
    EXPECT_EQ(f.masks[0], 0b111u);
    EXPECT_FALSE(f.masks.back() & 1u);
}

TEST_F(PlanFixture, ShadowsCullCastersOutsideEveryCascade) {
    settings.shadowDistance = 8; // the far boxes are beyond the shadowed depths
    ShadowBlock block;
    planShadows(in(), shadows, block);
    ASSERT_TRUE(shadows.frame.active);
    EXPECT_LT(shadows.frame.casters.size(), scene.items.size());
    EXPECT_GE(shadows.frame.casters.size(), 3u);
}

TEST_F(PlanFixture, SdsmListsEveryCasterForTheGpuCull) {
    settings.shadowTechnique = ShadowTechnique::Sdsm;
    ShadowBlock block;
    planShadows(in(), shadows, block);
    const ShadowFrame& f = shadows.frame;
    ASSERT_TRUE(f.gpuFit);
    EXPECT_EQ(f.casterBounds.size(), scene.items.size());
    EXPECT_EQ(f.casterBounds[1].indexCount, 36u);
    EXPECT_FLOAT_EQ(f.casterBounds[1].hi.z, float(-0.5 - 5.0)); // camera-relative
    EXPECT_FLOAT_EQ(block.cascade[0].x, 0.1f);                  // the range SDSM reduces
}

TEST_F(PlanFixture, ShadowsOffSayWhy) {
    settings.shadowTechnique = ShadowTechnique::Off;
    ShadowBlock block;
    planShadows(in(), shadows, block);
    EXPECT_FALSE(shadows.frame.active);
    EXPECT_STREQ(shadows.frame.off, "shadows.technique is off");
    shadows.casters.clear();
    settings.shadowTechnique = ShadowTechnique::Pssm;
    planShadows(in(), shadows, block);
    EXPECT_STREQ(shadows.frame.off, "nothing in the scene casts a shadow");
}

TEST_F(PlanFixture, LightsAreCameraRelativeAndClusterOverTheDepthsTheyReach) {
    settings.lightCulling = LightCulling::Clusters;
    LightContext lights;
    planLights(in(), lights);
    ASSERT_EQ(lights.list.size(), 4u);
    EXPECT_EQ(lights.localLights, 3u);
    ASSERT_TRUE(lights.clustered);
    EXPECT_EQ(lights.list[3].positionRange, glm::vec4(0, -1, -13, 2)); // (0, 1, -8) - camera
    EXPECT_GT(lights.grid.tilesX, 0u);
    EXPECT_GT(lights.grid.slices, 0u);
    ASSERT_EQ(lights.spheres.size(), 4u);
    EXPECT_LT(lights.spheres[1].w, lights.spheres[3].w + 1e-3f); // every sphere bounds its range
    settings.lightCulling = LightCulling::Off;
    planLights(in(), lights);
    EXPECT_FALSE(lights.clustered);
    EXPECT_TRUE(lights.spheres.empty());
}

TEST_F(PlanFixture, GiPlacesItsCascadesAndTheSunsRsm) {
    settings.giEnabled = true;
    settings.giCascades = 2;
    GiContext gi;
    GiBlock block;
    planGi(in(), gi, shadows, block);
    const GiFrame& f = gi.frame;
    ASSERT_EQ(f.off, nullptr);
    ASSERT_EQ(f.cascades.size(), 2u);
    EXPECT_LT(f.cascades[0].cellSize, f.cascades[1].cellSize);
    EXPECT_EQ(block.grid.y, 2.0f);
    EXPECT_NEAR(glm::length(f.toward), 1.0, 1e-9);
    EXPECT_GT(f.toward.y, 0.0); // toward the sun, above
    EXPECT_FALSE(f.rsmItems.empty());
    EXPECT_GT(f.rsmTexelArea, 0.0);
    EXPECT_FALSE(f.active) << "active only once its volumes exist (prepareGi)";
    settings.giEnabled = false;
    planGi(in(), gi, shadows, block);
    EXPECT_TRUE(gi.frame.cascades.empty());
    EXPECT_STREQ(gi.frame.off, "gi.enabled is false");
}

TEST_F(PlanFixture, IblTurnsItsIrradianceAndFallsBackToWhatTheFrameHas) {
    GpuEnvironment env;
    for (size_t k = 0; k < 9; ++k) env.irradianceSh[k] = glm::vec3(float(k + 1), 0.5f, -float(k));
    scene.environment = env;
    scene.iblPrograms = true;
    settings.iblIntensity = 2;
    settings.iblVisibility = SkyVisibility::Volume; // needs GI, which is off
    IblContext ibl;
    GiContext gi;
    IblBlock unturned, turned, fullTurn;
    planIbl(in(), ibl, gi, unturned);
    ASSERT_TRUE(ibl.active);
    for (size_t k = 0; k < 9; ++k) EXPECT_EQ(glm::vec3(unturned.sh[k]), 2.0f * env.irradianceSh[k]) << k;
    EXPECT_EQ(ibl.visibility, SkyVisibility::None);
    EXPECT_EQ(unturned.heightRange.z, 0.0f);
    settings.iblRotationDeg = 90;
    planIbl(in(), ibl, gi, turned);
    settings.iblRotationDeg = 360;
    planIbl(in(), ibl, gi, fullTurn);
    EXPECT_EQ(turned.sh[0], unturned.sh[0]); // the constant term does not turn
    float moved = 0;
    for (size_t k = 1; k < 9; ++k) {
        moved += glm::length(turned.sh[k] - unturned.sh[k]);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(fullTurn.sh[k][c], unturned.sh[k][c], 1e-4f) << k;
    }
    EXPECT_GT(moved, 1.0f);
    settings.iblEnabled = false;
    planIbl(in(), ibl, gi, turned);
    EXPECT_FALSE(ibl.active);
    EXPECT_EQ(turned.sh[1], glm::vec4(0.0f));
}

// ibl.visibility=auto (the default) is the probes' term where GI runs with the probes and no
// term elsewhere: no height map, no radius, no mode that loses to a constant on a bundled scene.
TEST_F(PlanFixture, AutoSkyVisibilityIsTheProbesWithGiProbesAndNoneElsewhere) {
    EXPECT_EQ(RenderSettings{}.iblVisibility, SkyVisibility::Auto);
    RenderSettings s;
    EXPECT_EQ(resolvedSkyVisibility(s), SkyVisibility::None) << "GI off";
    s.giEnabled = true;
    EXPECT_EQ(resolvedSkyVisibility(s), SkyVisibility::None) << "GI with the LPV";
    s.giTechnique = GiTechnique::Probes;
    EXPECT_EQ(resolvedSkyVisibility(s), SkyVisibility::Probes);
    s.iblVisibility = SkyVisibility::Height;
    EXPECT_EQ(resolvedSkyVisibility(s), SkyVisibility::Height) << "an explicit mode stays";

    GpuEnvironment env;
    scene.environment = env;
    scene.iblPrograms = true;
    scene.bounds.min = {0.0f, 0.0f, 0.0f};
    scene.bounds.max = {8.0f, 8.0f, 8.0f}; // radius: 1/8 of the diagonal
    IblContext ibl;
    GiContext gi;
    IblBlock block;
    planIbl(in(), ibl, gi, block); // the fixture's settings: auto, GI off
    EXPECT_EQ(ibl.visibility, SkyVisibility::None);
    EXPECT_EQ(block.params.z, 0.0f) << "no radius: no rays";
    EXPECT_FALSE(wantsSkyHeightMap(in()));
    settings.giEnabled = true;
    settings.giTechnique = GiTechnique::Probes;
    planIbl(in(), ibl, gi, block); // asks for the probes, whose volume does not exist here
    EXPECT_EQ(ibl.visibility, SkyVisibility::None);
    EXPECT_FALSE(ibl.warnedVisibility) << "auto does not warn: it was not asked for explicitly";
    EXPECT_NEAR(block.params.z, std::sqrt(192.0f) / 8.0f, 1e-5f);
}

} // namespace
} // namespace pnb::player
