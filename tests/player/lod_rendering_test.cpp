// Levels of detail in the renderer: far draws coarse and near draws full detail, hysteresis at the
// threshold, lod.force and lod.bias, the shadow pass at the main view's level, the debug view, and
// a scene without LODs (or with them forced to level 0) rendering exactly as one converted without.
// A UV sphere converted with the real converter's LOD chain (pnb-convert --lods), headless.
#include <cmath>
#include <filesystem>
#include <numbers>

#include "render_fixture.h"

#include "lod_select.h"
#include "pnb_player/gpu_scene.h"
#include "pnb_player/scene_stream.h"

namespace pnb::player::test {

namespace {

constexpr uint32_t kWidth = 160, kHeight = 120;

gltf::Document greyDocument() {
    gltf::Document doc;
    gltf::Material grey;
    grey.name = "grey";
    grey.baseColorFactor = {0.7f, 0.7f, 0.7f, 1};
    doc.materials.push_back(grey);
    return doc;
}

// `doc` converted with `lods` extra levels (and their proxies), in the test's directory.
std::string convertWithLods(const gltf::Document& doc, uint32_t lods, const std::string& name, bool gi,
                            bool proxies) {
    // Under the fixture's per-process directory, which HeadlessEnvironment removes at the end.
    auto dir = std::filesystem::temp_directory_path() /
               ("pnb-render-test-" + std::to_string(::getpid())) / "lod";
    std::filesystem::create_directories(dir);
    std::string glb = (dir / (name + ".glb")).string();
    EXPECT_TRUE(isOk(pnb::writeFileAtomic(glb, gltf::encodeGlb(doc))));
    converter::ConvertSettings s;
    s.input = glb;
    s.output = (dir / (name + ".pnb")).string();
    s.jobs = 1;
    s.validateShaders = false;
    s.noSidecar = true;
    s.mesh.lodCount = lods;
    s.mesh.proxies = proxies;
    if (gi) s.renderSettings.emplace_back("gi.enabled", "true");
    auto r = converter::convertScene(s);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return s.output;
}

// The sphere (material 0) at the origin, optionally a ground plane below it, and the fixture's
// sun and lamp; converted with `lods` extra levels.
std::string sphereScene(uint32_t lods, bool ground, const std::string& name, bool gi = false,
                        bool proxies = true) {
    gltf::Document doc = greyDocument();
    addObject(doc, "sphere", uvSphere(1.0f, 48, 96, 0), {0, 0, 0});
    if (ground) {
        // The quad faces +Z; rotated -90 degrees about x it faces +Y.
        float h = std::sqrt(0.5f);
        addObject(doc, "ground", quad(30, 30, 0), {0, -1.2f, 0}, {-h, 0, 0, h});
    }
    addLights(doc);
    return convertWithLods(doc, lods, name, gi, proxies);
}

// Two spheres of different tessellation (two meshes), at the origin and at `far` down -Z.
std::string twoSpheresScene(double far, const std::string& name) {
    gltf::Document doc = greyDocument();
    addObject(doc, "near", uvSphere(1.0f, 48, 96, 0), {0, 0, 0});
    addObject(doc, "far", uvSphere(1.0f, 40, 80, 0), {0, 0, -float(far)});
    addLights(doc);
    return convertWithLods(doc, 3, name, false, true);
}

struct Loaded {
    std::unique_ptr<GpuScene> scene;
    std::unique_ptr<Renderer> renderer;
    uint32_t sphere = 0; // the sphere's draw item

    const DrawItem& item() const { return scene->items[sphere]; }
    uint32_t levels() const { return item().levelCount; }
    uint32_t triangles(uint32_t level) const { return scene->levels[item().firstLevel + level].triangles; }
    float error(uint32_t level) const { return scene->levels[item().firstLevel + level].error; }
    // The level whose triangle count a frame drew (the sphere alone in view).
    int levelOf(uint64_t drawn) const {
        for (uint32_t l = 0; l < levels(); ++l)
            if (triangles(l) == drawn) return int(l);
        return -1;
    }
};

Loaded load(const std::string& path, RenderSettings settings = {}) {
    Loaded l;
    auto s = loadScene(path);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    if (!s.ok()) return l;
    l.scene = std::move(*s);
    settings.warmUp = false;
    auto r = Renderer::create(*l.scene, settings);
    EXPECT_TRUE(r.ok());
    if (r.ok()) l.renderer = std::move(*r);
    for (uint32_t i = 0; i < l.scene->items.size(); ++i)
        if (l.scene->items[i].levelCount > 1) l.sphere = i;
    return l;
}

// A camera on +Z looking at the sphere, `distance` from its bounds (the sphere's radius is 1).
CameraState at(double distance) { return lookAt({0, 0, 1.0 + distance}, {0, 0, 0}, 0.001f); }

// Where level `level`'s error projects to exactly the threshold (1 px) at the test's resolution.
double switchDistance(const Loaded& l, uint32_t level) {
    return double(l.error(level)) * lodPixelScale(0.8, kHeight) / 1.0;
}

int drawnLevel(Loaded& l, double distance) {
    auto r = l.renderer->render(at(distance), kWidth, kHeight);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return l.levelOf(l.renderer->lastFrame().triangles);
}

RenderSettings noShadows() {
    RenderSettings s;
    s.shadowTechnique = ShadowTechnique::Off;
    return s;
}

} // namespace

TEST(Lod, TheConverterChainLoadsAsOneItemWithItsLevels) {
    Loaded l = load(sphereScene(3, false, "chain"));
    ASSERT_TRUE(l.renderer);
    ASSERT_EQ(l.scene->items.size(), 1u); // one item, not one per submesh level
    ASSERT_GE(l.levels(), 3u);
    EXPECT_EQ(l.scene->lodItems, std::vector<uint32_t>{0});
    EXPECT_EQ(l.error(0), 0.0f);
    for (uint32_t k = 1; k < l.levels(); ++k) {
        EXPECT_LT(l.triangles(k), l.triangles(k - 1));
        EXPECT_GE(l.error(k), l.error(k - 1));
        EXPECT_GT(l.error(k), 0.0f);
    }
    EXPECT_EQ(l.scene->triangles, l.triangles(0)); // the scene's count is at full detail
}

TEST(Lod, FarDrawsTheCoarsestLevelNearDrawsLevel0) {
    Loaded l = load(sphereScene(3, false, "farnear"), noShadows());
    ASSERT_TRUE(l.renderer);
    const uint32_t coarsest = l.levels() - 1;
    EXPECT_EQ(drawnLevel(l, 0.2), 0);
    // Beyond where the coarsest level's error is within threshold x (1 - hysteresis).
    EXPECT_EQ(drawnLevel(l, 2.0 * switchDistance(l, coarsest) / 0.8), int(coarsest));
    // Back near: full detail at once, whatever the level before.
    EXPECT_EQ(drawnLevel(l, 0.2), 0);
    // Inside the bounds: full detail.
    EXPECT_EQ(drawnLevel(l, -0.5), 0);
}

// Through an orthographic camera the sphere is the same size on screen from any distance, so it
// draws the same level from any distance: the level of a view ymag high, wherever it stands.
TEST(Lod, AnOrthographicViewDrawsTheSameLevelFromAnyDistance) {
    Loaded l = load(sphereScene(3, false, "ortho"), noShadows());
    ASSERT_TRUE(l.renderer);
    const uint32_t coarsest = l.levels() - 1;
    // The far distance draws the coarsest level in perspective (FarDrawsTheCoarsestLevel...).
    const double far = 2.0 * switchDistance(l, coarsest) / 0.8;
    auto orthoLevel = [&](double distance, float ymag) {
        CameraState c = lookAt({0, 0, 1.0 + distance}, {0, 0, 0}, 0.001f, float(distance + 10.0));
        c.projection = Projection::Orthographic;
        c.ymag = ymag;
        auto r = l.renderer->render(c, kWidth, kHeight);
        EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
        return l.levelOf(l.renderer->lastFrame().triangles);
    };
    // A view so narrow that level 1's error is 2 px: full detail, near or far.
    const float narrow = float(double(l.error(1)) * kHeight / (2.0 * 2.0));
    for (double d : {0.2, 5.0, far, 10.0 * far}) EXPECT_EQ(orthoLevel(d, narrow), 0) << d;
    // A view so wide that the coarsest level is within the threshold: coarsest, near or far.
    const float wide = float(double(l.error(coarsest)) * kHeight / (2.0 * 0.5));
    for (double d : {0.2, 5.0, far}) EXPECT_EQ(orthoLevel(d, wide), int(coarsest)) << d;
    // The perspective view differs near and far (what the orthographic one must not do).
    EXPECT_EQ(drawnLevel(l, 0.2), 0);
    EXPECT_EQ(drawnLevel(l, far), int(coarsest));
}

TEST(Lod, HysteresisKeepsTheLevelAcrossTheThresholdWhileALargeMoveSwitches) {
    Loaded l = load(sphereScene(3, false, "hysteresis"), noShadows());
    ASSERT_TRUE(l.renderer);
    const double d1 = switchDistance(l, 1);
    RecordProperty("switch_distance_level1", std::to_string(d1));
    ASSERT_GT(switchDistance(l, 2), 1.3 * d1); // level 2 stays out of the band below
    EXPECT_EQ(drawnLevel(l, 0.5 * d1), 0);
    uint32_t switches = 0;
    for (int k = 0; k < 20; ++k) {
        EXPECT_EQ(drawnLevel(l, (k % 2 ? 0.95 : 1.05) * d1), 0) << "frame " << k;
        switches += l.renderer->lastFrame().lodSwitches;
    }
    EXPECT_EQ(switches, 0u);
    // A large move switches to level 1 and a move back inside the threshold returns at once.
    EXPECT_EQ(drawnLevel(l, 1.3 * d1), 1);
    EXPECT_EQ(l.renderer->lastFrame().lodSwitches, 1u);
    EXPECT_EQ(drawnLevel(l, 1.05 * d1), 1); // inside the band from above: stays
    EXPECT_EQ(drawnLevel(l, 0.95 * d1), 0);

    // The same walk without hysteresis flips every frame: what the band prevents.
    RenderSettings s = noShadows();
    s.lodHysteresis = 0;
    l.renderer->setSettings(s);
    switches = 0;
    for (int k = 0; k < 20; ++k) {
        drawnLevel(l, (k % 2 ? 0.95 : 1.05) * d1);
        switches += l.renderer->lastFrame().lodSwitches;
    }
    EXPECT_EQ(switches, 20u);
}

TEST(Lod, ForceAndBiasOverrideTheChoiceClampedToTheLevelsThereAre) {
    Loaded l = load(sphereScene(3, false, "force"), noShadows());
    ASSERT_TRUE(l.renderer);
    const int coarsest = int(l.levels()) - 1;
    const double far = 2.0 * switchDistance(l, uint32_t(coarsest)) / 0.8;
    RenderSettings s = noShadows();
    for (int force : {0, 1, coarsest}) {
        s.lodForce = force;
        l.renderer->setSettings(s);
        EXPECT_EQ(drawnLevel(l, 0.2), force);
        EXPECT_EQ(drawnLevel(l, far), force);
    }
    s.lodForce = 254;
    l.renderer->setSettings(s);
    EXPECT_EQ(drawnLevel(l, 0.2), coarsest);
    ASSERT_TRUE(applySetting(s, "lod.force", "-1").ok());
    ASSERT_TRUE(applySetting(s, "lod.bias", "-1").ok());
    l.renderer->setSettings(s);
    EXPECT_EQ(drawnLevel(l, far), coarsest - 1);
    ASSERT_TRUE(applySetting(s, "lod.bias", "2").ok());
    l.renderer->setSettings(s);
    EXPECT_EQ(drawnLevel(l, 0.2), 2);
    EXPECT_FALSE(applySetting(s, "lod.force", "-2").ok());
    EXPECT_FALSE(applySetting(s, "lod.bias", "9").ok());
}

TEST(Lod, ShadowPassesDrawTheMainViewsLevel) {
    for (const char* technique : {"single", "sdsm"}) {
        SCOPED_TRACE(technique);
        RenderSettings s;
        ASSERT_TRUE(applySetting(s, "shadows.technique", technique).ok());
        Loaded l = load(sphereScene(3, true, std::string("shadow-") + technique), s);
        ASSERT_TRUE(l.renderer);
        const uint32_t coarsest = l.levels() - 1;
        for (double distance : {0.2, 2.0 * switchDistance(l, coarsest) / 0.8}) {
            ASSERT_TRUE(l.renderer->render(at(distance), kWidth, kHeight).ok());
            const FrameStats& f = l.renderer->lastFrame();
            // Casters: the sphere (the ground is single-sided but casts too): one cascade, each
            // counted once, at the level the main view draws.
            uint64_t ground = l.scene->triangles - l.triangles(0);
            int level = l.levelOf(f.triangles - ground);
            ASSERT_GE(level, 0) << f.triangles;
            EXPECT_EQ(level, distance < 1 ? 0 : int(coarsest));
            EXPECT_EQ(f.shadowTriangles, l.triangles(uint32_t(level)) + ground);
            auto hdr = l.renderer->capture(CaptureBuffer::Hdr);
            ASSERT_TRUE(hdr.ok());
            EXPECT_TRUE(allFinite(*hdr));
        }
    }
}

TEST(Lod, TheGiReflectiveShadowMapDrawsTheMainViewsLevel) {
    Loaded l = load(sphereScene(3, true, "gi", true));
    ASSERT_TRUE(l.renderer);
    ASSERT_TRUE(l.scene->giPrograms);
    const uint32_t coarsest = l.levels() - 1;
    const uint64_t ground = l.scene->triangles - l.triangles(0);
    RenderSettings on, off;
    on.giEnabled = true;
    for (double distance : {0.2, 2.0 * switchDistance(l, coarsest) / 0.8}) {
        const uint32_t level = distance < 1 ? 0 : coarsest;
        l.renderer->setSettings(off);
        ASSERT_TRUE(l.renderer->render(at(distance), kWidth, kHeight).ok());
        const uint64_t mainView = l.renderer->lastFrame().triangles;
        EXPECT_EQ(mainView, l.triangles(level) + ground);
        l.renderer->setSettings(on);
        ASSERT_TRUE(l.renderer->render(at(distance), kWidth, kHeight).ok());
        // The RSM's draws count as draws: the sphere and the ground once more, at the same level.
        EXPECT_EQ(l.renderer->lastFrame().triangles - mainView, l.triangles(level) + ground);
        auto hdr = l.renderer->capture(CaptureBuffer::Hdr);
        ASSERT_TRUE(hdr.ok());
        EXPECT_TRUE(allFinite(*hdr));
    }
}

TEST(Lod, ForcedToLevel0ItRendersExactlyAsTheSceneConvertedWithoutLods) {
    RenderSettings s; // shadows on (PSSM): the shadow pass is compared too
    Loaded plain = load(sphereScene(0, true, "plain"), s);
    ASSERT_TRUE(plain.renderer);
    EXPECT_TRUE(plain.scene->lodItems.empty());
    s.lodForce = 0;
    Loaded lods = load(sphereScene(3, true, "lods"), s);
    ASSERT_TRUE(lods.renderer);
    ASSERT_GT(lods.levels(), 1u);
    for (double distance : {0.5, 40.0}) {
        ASSERT_TRUE(plain.renderer->render(at(distance), kWidth, kHeight).ok());
        ASSERT_TRUE(lods.renderer->render(at(distance), kWidth, kHeight).ok());
        EXPECT_EQ(plain.renderer->lastFrame().lodSwitches, 0u);
        EXPECT_EQ(plain.renderer->lastFrame().triangles, lods.renderer->lastFrame().triangles);
        EXPECT_EQ(plain.renderer->lastFrame().shadowTriangles, lods.renderer->lastFrame().shadowTriangles);
        auto a = plain.renderer->capture(CaptureBuffer::Color);
        auto b = lods.renderer->capture(CaptureBuffer::Color);
        ASSERT_TRUE(a.ok() && b.ok());
        EXPECT_EQ(compareRgba8(*a, *b).maxAbs, 0) << "distance " << distance;
    }
    // By error, far, it draws fewer triangles (and so a different image).
    RenderSettings byError;
    lods.renderer->setSettings(byError);
    ASSERT_TRUE(lods.renderer->render(at(40.0), kWidth, kHeight).ok());
    EXPECT_LT(lods.renderer->lastFrame().triangles, plain.renderer->lastFrame().triangles);
}

TEST(Lod, DebugViewColoursTheSphereByItsLevel) {
    RenderSettings s = noShadows();
    s.debugView = DebugView::Lod;
    Loaded l = load(sphereScene(3, false, "debugview"), s);
    ASSERT_TRUE(l.renderer);
    auto centre = [&](double distance) {
        EXPECT_TRUE(l.renderer->render(at(distance), kWidth, kHeight).ok());
        auto img = l.renderer->capture(CaptureBuffer::Color);
        EXPECT_TRUE(img.ok());
        size_t i = (size_t(kHeight / 2) * kWidth + kWidth / 2) * 4;
        return glm::ivec3(img->u8[i], img->u8[i + 1], img->u8[i + 2]);
    };
    // The view draws every visible item once more: the frame counts the level's triangles twice.
    auto level = [&] { return l.levelOf(l.renderer->lastFrame().triangles / 2); };
    const double d1 = switchDistance(l, 1);
    auto near = [](glm::ivec3 a, glm::ivec3 b) { return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::ivec3(1))); };
    EXPECT_PRED2(near, centre(0.1 * d1), glm::ivec3(38, 89, 255)); // level 0: blue (0.15, 0.35, 1)
    EXPECT_EQ(level(), 0);
    EXPECT_PRED2(near, centre(1.3 * d1), glm::ivec3(26, 204, 51)); // level 1: green (0.1, 0.8, 0.2)
    EXPECT_EQ(level(), 1);
}

} // namespace pnb::player::test

namespace pnb::player::test {

// Streaming a mesh with levels (docs/FORMAT.md "MDET"): the first frame draws the coarse proxy,
// the full detail replaces it within a few frames (through the staging ring, a few KiB a frame),
// and the finished stream draws what the full load draws.
TEST(Lod, StreamingDrawsTheCoarseProxyFirstThenTheFullDetail) {
    const std::string path = sphereScene(3, false, "stream");
    Loaded full = load(path, noShadows());
    ASSERT_TRUE(full.renderer);
    ASSERT_EQ(full.levels(), 4u);

    StreamOptions o;
    o.uploadBytesPerFrame = 16 << 10;
    auto opened = SceneStream::open(path, o);
    ASSERT_TRUE(opened.ok()) << (opened.ok() ? "" : opened.error().message);
    RenderSettings settings = noShadows();
    settings.warmUp = false;
    settings.lodForce = 0; // full detail once there is detail: the images compare exactly
    auto renderer = Renderer::create(*opened->scene, settings);
    ASSERT_TRUE(renderer.ok());
    const GpuScene& scene = *opened->scene;
    uint32_t sphere = 0;
    for (uint32_t i = 0; i < scene.items.size(); ++i)
        if (scene.items[i].mesh == full.item().mesh) sphere = i;
    const CameraState view = at(2.0);

    // First frame: the proxy, one level: the coarsest level's triangles.
    ASSERT_TRUE((*renderer)->render(view, kWidth, kHeight).ok());
    EXPECT_EQ(scene.items[sphere].levelCount, 1u);
    EXPECT_EQ((*renderer)->lastFrame().triangles, full.triangles(3));
    int frames = 0;
    for (StreamTimeLimit limit; !opened->stream->status().complete && limit.left();) {
        ASSERT_TRUE(opened->stream->update(view, kWidth, kHeight).ok());
        ASSERT_TRUE((*renderer)->render(view, kWidth, kHeight).ok());
        const uint64_t drawn = (*renderer)->lastFrame().triangles;
        // Never a half-uploaded mesh: the proxy's triangles or the detail's level 0, nothing else.
        EXPECT_TRUE(drawn == full.triangles(3) || drawn == full.triangles(0)) << drawn;
        ++frames;
    }
    ASSERT_TRUE(opened->stream->status().complete);
    EXPECT_GT(frames, 3); // the detail took several frames of 16 KiB
    EXPECT_EQ(opened->stream->status().meshesReplaced, 1u);
    EXPECT_EQ(scene.items[sphere].levelCount, 4u);
    EXPECT_EQ(scene.lodItems.size(), full.scene->lodItems.size());
    ASSERT_TRUE((*renderer)->render(view, kWidth, kHeight).ok());
    EXPECT_EQ((*renderer)->lastFrame().triangles, full.triangles(0));
    RenderSettings forced = noShadows();
    forced.lodForce = 0;
    full.renderer->setSettings(forced);
    ASSERT_TRUE(full.renderer->render(view, kWidth, kHeight).ok());
    EXPECT_EQ(compareRgba8(*(*renderer)->capture(CaptureBuffer::Color), *full.renderer->capture(CaptureBuffer::Color)).maxAbs, 0);
    renderer->reset(); // before the scene it draws
}

TEST(Lod, MeshProxiesChangeNothingInAFullLoad) {
    // The same scene converted with --no-mesh-proxies renders the same image: a full load draws
    // the MDET detail and never the proxy.
    auto render2 = [](const std::string& path) {
        Loaded l = load(path, noShadows());
        EXPECT_TRUE(l.renderer->render(at(3.0), kWidth, kHeight).ok());
        return std::move(*l.renderer->capture(CaptureBuffer::Color));
    };
    const std::string with = sphereScene(3, true, "proxies"), without = sphereScene(3, true, "no-proxies", false, false);
    EXPECT_GT(std::filesystem::file_size(with), std::filesystem::file_size(without)); // proxy + MDET
    EXPECT_EQ(compareRgba8(render2(with), render2(without)).maxAbs, 0);
}

} // namespace pnb::player::test

namespace pnb::player::test {

// Under stream.budget_mib a mesh with levels keeps its full detail only where the LOD rule would
// draw it finer than its proxy, and gives it up (the proxy drawn again) when another mesh needs
// the room: two spheres 200 units apart, a budget with room for the proxies and one detail.
// Walking from one to the other and back, each near sphere draws its detail and the far one its
// proxy, the detail given up is read again from the file, the budget is never exceeded, and the
// image is the full load's.
TEST(Lod, UnderABudgetOnlyTheMeshesTheViewDrawsFinerThanTheirProxyKeepTheirDetail) {
    constexpr double kFar = 200;
    const std::string path = twoSpheresScene(kFar, "budget");
    Loaded full = load(path, noShadows());
    ASSERT_TRUE(full.renderer);
    ASSERT_EQ(full.scene->items.size(), 2u);
    const uint32_t a = full.scene->items[0].boundsMin.z > -kFar / 2 ? 0 : 1, b = 1 - a;
    const DrawItem &itemA = full.scene->items[a], &itemB = full.scene->items[b];
    ASSERT_EQ(itemA.levelCount, 4u);
    ASSERT_EQ(itemB.levelCount, 4u);
    // Where each sphere's proxy (its level 3) projects to half the threshold: detail needed.
    const double pixelScale = lodPixelScale(0.8, kHeight);
    const double nearA = 0.5 * full.scene->levels[itemA.firstLevel + 3].error * pixelScale;
    const double nearB = 0.5 * full.scene->levels[itemB.firstLevel + 3].error * pixelScale;
    ASSERT_GT(kFar, 8 * std::max(nearA, nearB)); // seen from one, the other is far beyond its switch
    const CameraState viewA = at(nearA);
    const CameraState viewB = lookAt({0, 0, -kFar + 1.0 + nearB}, {0, 0, -kFar}, 0.001f);

    // GPU bytes: the details from the full load, the proxies from a stream's first frame.
    const uint64_t detailA = full.scene->meshes[itemA.mesh].bytes, detailB = full.scene->meshes[itemB.mesh].bytes;
    uint64_t proxyA = 0, proxyB = 0;
    {
        auto probe = SceneStream::open(path, {});
        ASSERT_TRUE(probe.ok());
        proxyA = probe->scene->meshes[itemA.mesh].bytes;
        proxyB = probe->scene->meshes[itemB.mesh].bytes;
    }
    ASSERT_LT(std::max(proxyA, proxyB), std::min(detailA, detailB) / 2);
    // The proxies, one detail, and a proxy more: while a detail is made, the planner counts its
    // proxy twice (old and new chain). Not both details.
    StreamOptions o;
    o.budgetBytes = proxyA + proxyB + std::max(detailA, detailB) + std::max(proxyA, proxyB) + 4096;
    ASSERT_LT(o.budgetBytes, proxyA + proxyB + detailA + detailB);
    o.uploadBytesPerFrame = 64 << 10;
    auto opened = SceneStream::open(path, o);
    ASSERT_TRUE(opened.ok()) << (opened.ok() ? "" : opened.error().message);
    RenderSettings settings = noShadows();
    settings.warmUp = false;
    auto renderer = Renderer::create(*opened->scene, settings);
    ASSERT_TRUE(renderer.ok());
    SceneStream& stream = *opened->stream;
    const GpuScene& scene = *opened->scene;

    auto settle = [&](const CameraState& view) {
        StreamTimeLimit limit;
        for (int k = 0; limit.left(); ++k) {
            EXPECT_TRUE(stream.update(view, kWidth, kHeight).ok());
            EXPECT_TRUE((*renderer)->render(view, kWidth, kHeight).ok());
            EXPECT_LE(stream.status().peakBytes, o.budgetBytes) << "frame " << k;
            EXPECT_LE(stream.status().residentBytes, o.budgetBytes) << "frame " << k;
            if (stream.status().complete) return true;
        }
        return false;
    };
    ASSERT_TRUE(settle(viewA));
    EXPECT_EQ(scene.items[a].levelCount, 4u); // the detail, by error
    EXPECT_EQ(scene.items[b].levelCount, 1u); // the proxy
    EXPECT_EQ(stream.status().residentMeshBytes, proxyA + proxyB + detailA);

    ASSERT_TRUE(settle(viewB));
    EXPECT_EQ(scene.items[a].levelCount, 1u);
    EXPECT_EQ(scene.items[b].levelCount, 4u);
    EXPECT_GE(stream.status().evictions, 1u);
    const uint32_t refetches = stream.status().refetches;
    EXPECT_GE(refetches, 1u); // B's detail was skipped as it streamed past

    ASSERT_TRUE(settle(viewA));
    EXPECT_EQ(scene.items[a].levelCount, 4u);
    EXPECT_EQ(scene.items[b].levelCount, 1u);
    EXPECT_GT(stream.status().refetches, refetches); // A's detail, read again
    EXPECT_EQ(scene.memory.meshBytes, proxyA + proxyB + detailA);

    // Drawn twice: the levels chosen (with hysteresis) no longer depend on the way here.
    for (int k = 0; k < 2; ++k) {
        ASSERT_TRUE((*renderer)->render(viewA, kWidth, kHeight).ok());
        ASSERT_TRUE(full.renderer->render(viewA, kWidth, kHeight).ok());
    }
    EXPECT_EQ((*renderer)->lastFrame().triangles, full.renderer->lastFrame().triangles);
    EXPECT_EQ(compareRgba8(*(*renderer)->capture(CaptureBuffer::Color), *full.renderer->capture(CaptureBuffer::Color)).maxAbs, 0);
    renderer->reset(); // before the scene it draws
}

} // namespace pnb::player::test
