// Layered deferred + forward shading (seed 003): translucent deferred layers match forward
// blending, the shared depth is the forward depth, and only what the scene uses is allocated.
#include <cmath>

#include "render_fixture.h"

namespace pnb::player::test {

namespace {

// An opaque floor and back wall, and three translucent quads stacked in depth, each tilted
// differently so blending their normals (the G-buffer mistake) would light them wrongly.
gltf::Document stackedQuads() {
    gltf::Document doc;
    gltf::Material floor;
    floor.name = "floor";
    floor.baseColorFactor = {0.7f, 0.7f, 0.65f, 1};
    gltf::Material wall;
    wall.name = "wall";
    wall.baseColorFactor = {0.2f, 0.35f, 0.8f, 1};
    doc.materials = {floor, wall};
    const gltf::Float4 colors[3] = {{0.9f, 0.2f, 0.1f, 0.5f}, {0.1f, 0.9f, 0.2f, 0.4f}, {0.9f, 0.9f, 0.1f, 0.6f}};
    for (int i = 0; i < 3; ++i) {
        gltf::Material glass;
        glass.name = "glass" + std::to_string(i);
        glass.baseColorFactor = colors[i];
        glass.alphaMode = gltf::AlphaMode::Blend;
        glass.doubleSided = true;
        glass.roughnessFactor = 0.3f + 0.2f * float(i);
        doc.materials.push_back(glass);
    }
    addObject(doc, "floor", quad(8, 8, 0), {0, 0, 0}, {-0.70710678f, 0, 0, 0.70710678f});
    addObject(doc, "wall", quad(8, 4, 1), {0, 2, -3});
    for (int i = 0; i < 3; ++i)
        addObject(doc, "pane" + std::to_string(i), quad(2.2f, 1.6f, uint32_t(2 + i)),
                  {0.3f * float(i) - 0.3f, 1.0f, -1.5f + 1.0f * float(i)},
                  gltf::rotationY(0.35f * float(i - 1)));
    addLights(doc);
    return doc;
}

const CameraState kView = lookAt({0.4, 1.6, 4.0}, {0, 0.9, -1});

} // namespace

TEST(LayeredShading, TranslucentDeferredLayersMatchForwardBlending) {
    gltf::Document doc = stackedQuads();
    // Farthest pane in the lowest layer: layers compose back to front.
    std::string deferred = convert(doc, "layers", R"({"materials": {
        "glass0": {"shading_path": "deferred", "layer_priority": 1},
        "glass1": {"shading_path": "deferred", "layer_priority": 2},
        "glass2": {"shading_path": "deferred", "layer_priority": 3}}})");
    std::string forward = convert(doc, "forward", R"({"materials": {
        "*": {"shading_path": "forward"}}})");
    Rendered d = render(deferred, kView);
    Rendered f = render(forward, kView);
    EXPECT_EQ(d.deferredLayers, 4u);
    EXPECT_EQ(d.stats.deferredLayersDrawn, 4u);
    EXPECT_EQ(f.deferredLayers, 0u);

    ImageDiff diff = compareRgba8(d.color, f.color);
    // Only the 8-bit sRGB base colour and 16-bit normals of the G-buffer differ from forward.
    EXPECT_LE(diff.maxAbs, 3) << "mean " << diff.meanAbs;
    EXPECT_LT(diff.meanAbs, 0.3);

    // Guard against a vacuous pass: the panes really change the picture.
    gltf::Document noPanes = doc;
    for (int i = 0; i < 3; ++i) noPanes.nodes[size_t(2 + i)].mesh = gltf::kNone;
    Rendered bare = render(convert(noPanes, "bare"), kView);
    EXPECT_GT(compareRgba8(bare.color, d.color).fractionOver(20), 0.1);
    EXPECT_TRUE(allFinite(d.hdr));
}

TEST(LayeredShading, DepthAfterDeferredLayersEqualsForwardDepth) {
    gltf::Document doc = stackedQuads();
    for (auto& m : doc.materials) m.alphaMode = gltf::AlphaMode::Opaque; // every object writes depth
    std::string layered = convert(doc, "layered", R"({"materials": {
        "glass0": {"layer_priority": 2}, "glass1": {"layer_priority": 5}, "wall": {"layer_priority": 1}}})");
    std::string forward = convert(doc, "forward", R"({"materials": {"*": {"shading_path": "forward"}}})");
    Rendered d = render(layered, kView);
    Rendered f = render(forward, kView);
    EXPECT_EQ(d.stats.deferredLayersDrawn, 4u);
    ASSERT_EQ(d.depth.f32.size(), f.depth.f32.size());
    size_t covered = 0;
    for (size_t i = 0; i < d.depth.f32.size(); ++i) {
        ASSERT_EQ(d.depth.f32[i], f.depth.f32[i]) << "pixel " << i;
        covered += d.depth.f32[i] > 0;
    }
    EXPECT_GT(covered, d.depth.f32.size() / 2);
}

TEST(LayeredShading, ForwardObjectIntersectingDeferredGeometryIsDepthCorrect) {
    gltf::Document doc = stackedQuads();
    for (auto& m : doc.materials) m.alphaMode = gltf::AlphaMode::Opaque;
    gltf::Material probe;
    probe.name = "probe";
    probe.baseColorFactor = {0.9f, 0.5f, 0.1f, 1};
    doc.materials.push_back(probe);
    // A box poking through the floor and the middle pane.
    addObject(doc, "probe", box(0.8f, 1.6f, 0.8f, uint32_t(doc.materials.size() - 1)), {0.2f, 0.4f, -0.5f});
    std::string mixed = convert(doc, "mixed", R"({"materials": {"probe": {"shading_path": "forward"}}})");
    std::string forward = convert(doc, "forward", R"({"materials": {"*": {"shading_path": "forward"}}})");
    Rendered m = render(mixed, kView);
    Rendered f = render(forward, kView);
    ImageDiff diff = compareRgba8(m.color, f.color);
    EXPECT_LE(diff.maxAbs, 3);
    EXPECT_EQ(m.depth.f32, f.depth.f32);
}

TEST(LayeredShading, AllocatesOnlyWhatTheSceneUses) {
    gltf::Document doc = stackedQuads();
    for (auto& m : doc.materials) m.alphaMode = gltf::AlphaMode::Opaque;
    Rendered opaque = render(convert(doc, "opaque"), kView, 128, 96);
    EXPECT_EQ(opaque.deferredLayers, 1u);
    EXPECT_EQ(opaque.stats.deferredLayersDrawn, 1u);
    EXPECT_EQ(opaque.memory.gbufferBytes, uint64_t(16) * 128 * 96); // one G-buffer, 16 B/px + shared depth
    EXPECT_EQ(opaque.memory.depthBytes, uint64_t(4) * 128 * 96);
    EXPECT_TRUE(opaque.lightingProgramCompiled);

    std::string allForward = convert(doc, "forward", R"({"materials": {"*": {"shading_path": "forward"}}})");
    Rendered forward = render(allForward, kView, 128, 96);
    EXPECT_EQ(forward.deferredLayers, 0u);
    EXPECT_EQ(forward.memory.gbufferBytes, 0u);
    EXPECT_FALSE(forward.lightingProgramCompiled);
    EXPECT_EQ(forward.memory.debugBytes, 0u);
}

TEST(LayeredShading, EmptyLayersCostNothing) {
    gltf::Document doc = stackedQuads();
    for (auto& m : doc.materials) m.alphaMode = gltf::AlphaMode::Opaque;
    // glass2's layer exists, but its pane is behind the camera.
    doc.nodes[4].translation = {0, 1, 20};
    std::string path = convert(doc, "culled", R"({"materials": {"glass2": {"layer_priority": 9}}})");
    Rendered r = render(path, kView);
    EXPECT_EQ(r.deferredLayers, 2u);
    EXPECT_EQ(r.stats.deferredLayersDrawn, 1u);
    EXPECT_EQ(r.stats.culledItems, 1u);
}

} // namespace pnb::player::test

#include "pnb/scene.h"

namespace pnb::player::test {

// The editor's path: a decoded scene uploaded once, then materials changed in place. Moving the
// nearest pane down to layer 0 composes it first, so the farther panes blend over it: the picture
// departs from forward blending as layer ordering predicts; moving it back restores the match.
TEST(LayeredShading, ReorderingLayersLive) {
    gltf::Document doc = stackedQuads();
    std::string path = convert(doc, "layers", R"({"materials": {
        "glass0": {"shading_path": "deferred", "layer_priority": 1},
        "glass1": {"shading_path": "deferred", "layer_priority": 2},
        "glass2": {"shading_path": "deferred", "layer_priority": 3}}})");
    Rendered reference = render(convert(doc, "forward", R"({"materials": {"*": {"shading_path": "forward"}}})"), kView);
    auto container = Container::open(path);
    ASSERT_TRUE(container.ok());
    auto scene = readScene(*container);
    ASSERT_TRUE(scene.ok());
    auto gpu = uploadScene(*scene);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    auto renderer = Renderer::create(**gpu, {});
    ASSERT_TRUE(renderer.ok());
    auto frame = [&] {
        EXPECT_TRUE((*renderer)->render(kView, 160, 120).ok());
        return compareRgba8(reference.color, *(*renderer)->capture(CaptureBuffer::Color));
    };
    EXPECT_LE(frame().maxAbs, 3);

    uint32_t nearest = 0;
    for (uint32_t i = 0; i < scene->materials.size(); ++i)
        if (scene->str(scene->materials[i].name) == "glass2") nearest = i;
    // Into the opaque layer 0: one G-buffer holds one surface per pixel, so the pane hides the
    // floor and wall behind it, and the two farther panes then blend over it.
    scene->materials[nearest].layerPriority = 0;
    ASSERT_TRUE(updateMaterials(**gpu, *scene).ok());
    EXPECT_EQ((*gpu)->deferredLayers.size(), 3u);
    ImageDiff wrongOrder = frame();
    EXPECT_GT(wrongOrder.fractionOver(10), 0.05);

    scene->materials[nearest].layerPriority = 3;
    ASSERT_TRUE(updateMaterials(**gpu, *scene).ok());
    EXPECT_LE(frame().maxAbs, 3);
}

} // namespace pnb::player::test
