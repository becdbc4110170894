// What real glTF files use, headless: a mirrored node (negative scale) is drawn and lit like its
// unmirrored twin (glTF's NegativeScaleTest), EXT_mesh_gpu_instancing copies are drawn as one
// instanced draw with the same image as the same copies as separate nodes (SimpleInstancing), and
// a KHR_materials_unlit surface shows its colour whatever the light, in both shading paths
// (UnlitTest). The Khronos models themselves: tests/conformance/.
#include <array>
#include <cmath>

#include "render_fixture.h"

namespace pnb::player::test {
namespace {

constexpr uint32_t kW = 160, kH = 120;

gltf::Document litDocument() {
    gltf::Document doc;
    gltf::Material grey;
    grey.name = "grey";
    grey.baseColorFactor = {0.7f, 0.7f, 0.7f, 1};
    grey.metallicFactor = 0.0f;
    doc.materials.push_back(grey);
    addSun(doc, 3.0f, gltf::lookRotation({0.0f, -1.0f, -0.6f})); // symmetric in x
    return doc;
}

struct Half {
    uint64_t covered = 0;
    double luminance = 0; // sum over covered pixels, display values
};

// The left and right halves of the image (x < W/2, x >= W/2): covered pixels and their light.
std::pair<Half, Half> halves(const Rendered& r) {
    Half left, right;
    for (uint32_t y = 0; y < r.depth.height; ++y)
        for (uint32_t x = 0; x < r.depth.width; ++x) {
            const size_t i = size_t(y) * r.depth.width + x;
            if (!(r.depth.f32[i] > 0)) continue;
            const uint8_t* c = &r.color.u8[i * 4];
            Half& h = x < r.depth.width / 2 ? left : right;
            ++h.covered;
            h.luminance += 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        }
    return {left, right};
}

// A box and its mirror image (scale -1 in x) side by side, seen and lit symmetrically: the
// mirrored one must show its outside (front faces wind clockwise under the mirror) with the same
// light. Drawn with the winding unflipped, culling keeps its inside faces, which face away from
// the sun and the camera.
TEST(MirroredNode, IsDrawnAndLitLikeItsTwin) {
    gltf::Document doc = litDocument();
    addObject(doc, "plain", box(1.2f, 1.2f, 1.2f, 0), {-1.5f, 0, 0},
              gltf::Float4{0, 0.38268343f, 0, 0.92387953f}); // turned 45 degrees about y
    const uint32_t mirrored = addObject(doc, "mirrored", box(1.2f, 1.2f, 1.2f, 0), {1.5f, 0, 0},
                                        gltf::Float4{0, -0.38268343f, 0, 0.92387953f});
    doc.nodes[mirrored].scale = {-1, 1, 1};
    const std::string file = convert(doc, "mirrored-twins");
    const Rendered r = render(file, lookAt({0, 2, 7}, {0, 0, 0}), kW, kH);
    const auto [left, right] = halves(r);
    ASSERT_GT(left.covered, 500u);
    EXPECT_NEAR(double(right.covered), double(left.covered), 0.03 * double(left.covered));
    const double meanLeft = left.luminance / double(left.covered);
    const double meanRight = right.luminance / double(std::max<uint64_t>(right.covered, 1));
    EXPECT_NEAR(meanRight, meanLeft, 0.03 * meanLeft) << "mean display luminance, 0..255";
    EXPECT_TRUE(allFinite(r.hdr));
}

// 27 copies of a box: as one EXT_mesh_gpu_instancing node they are one mesh and one instanced
// draw; as 27 nodes, 27 draws; the two images are the same.
TEST(Instancing, CopiesAreOneInstancedDrawWithTheSameImageAsSeparateNodes) {
    std::vector<gltf::Float3> grid;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z) grid.push_back({1.6f * x, 1.6f * y, 1.6f * z});
    gltf::Document instanced = litDocument();
    const uint32_t node = addObject(instanced, "cubes", box(0.8f, 0.8f, 0.8f, 0), {0, 0, 0});
    instanced.nodes[node].instanceTranslations = grid;
    gltf::Document separate = litDocument();
    for (size_t k = 0; k < grid.size(); ++k)
        addObject(separate, "cube" + std::to_string(k), box(0.8f, 0.8f, 0.8f, 0), grid[k]);

    const CameraState view = lookAt({6, 5, 9}, {0, 0, 0});
    const Rendered a = render(convert(instanced, "instanced"), view, kW, kH);
    const Rendered b = render(convert(separate, "separate"), view, kW, kH);
    EXPECT_EQ(a.stats.visibleItems, 27u) << "culling and LOD still see every copy";
    EXPECT_EQ(a.stats.drawCalls, 1u);
    EXPECT_EQ(b.stats.drawCalls, 27u);
    EXPECT_EQ(a.stats.triangles, b.stats.triangles);
    const ImageDiff d = compareRgba8(a.color, b.color);
    EXPECT_LE(d.maxAbs, 2) << "mean " << d.meanAbs;
}

// Unlit surfaces (deferred: opaque; forward: blended at alpha 1) keep their colour when the sun
// is ten times brighter; the lit twin of each does not.
TEST(Unlit, TheColourIsTheSameWhateverTheLightInBothPaths) {
    auto scene = [](float sunIntensity) {
        gltf::Document doc = litDocument();
        doc.lights[0].intensity = sunIntensity;
        gltf::Material unlit;
        unlit.name = "unlit";
        unlit.baseColorFactor = {0.6f, 0.3f, 0.1f, 1};
        unlit.unlit = true;
        gltf::Material unlitForward = unlit;
        unlitForward.name = "unlitForward";
        unlitForward.alphaMode = gltf::AlphaMode::Blend;
        gltf::Material lit = unlit;
        lit.name = "lit";
        lit.unlit = false;
        doc.materials = {unlit, unlitForward, lit};
        addObject(doc, "deferred", quad(1.8f, 1.8f, 0), {-2, 1, 0});
        addObject(doc, "forward", quad(1.8f, 1.8f, 1), {0, 1, 0});
        addObject(doc, "lit", quad(1.8f, 1.8f, 2), {2, 1, 0});
        return doc;
    };
    const CameraState view = lookAt({0, 1, 6}, {0, 1, 0});
    const Rendered dim = render(convert(scene(0.5f), "unlit-dim"), view, kW, kH);
    const Rendered bright = render(convert(scene(5.0f), "unlit-bright"), view, kW, kH);
    // The view's half width at the quads (distance 6, yfov 0.8, aspect 4:3): 6 tan(0.4) 4/3.
    const float halfWidth = 6.0f * std::tan(0.4f) * float(kW) / float(kH);
    auto pixel = [&](const Rendered& r, float worldX) { // the centre of the quad at x = worldX
        const uint32_t x = uint32_t(float(kW) / 2 * (1 + worldX / halfWidth)), y = kH / 2;
        const uint8_t* c = &r.color.u8[(size_t(y) * kW + x) * 4];
        return std::array<int, 3>{c[0], c[1], c[2]};
    };
    for (float x : {-2.0f, 0.0f}) {
        const auto a = pixel(dim, x), b = pixel(bright, x);
        EXPECT_EQ(a, b) << "unlit quad at x = " << x;
        EXPECT_GT(a[0], a[1]) << "its own colour, not black";
        EXPECT_GT(a[1], a[2]);
    }
    const auto litDim = pixel(dim, 2.0f), litBright = pixel(bright, 2.0f);
    EXPECT_GT(litBright[0], litDim[0] + 20) << "the lit twin does brighten";
}

} // namespace
} // namespace pnb::player::test
