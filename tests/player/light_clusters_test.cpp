// Clustered light culling (docs/PLAYER.md "Many lights"): the image with clusters is the image
// with every light at every pixel, in deferred and forward materials, and stays so at the
// extremes (a light at the camera, lights behind the near plane, none, thousands, far from the
// origin).
#include <cmath>

#include "render_fixture.h"

namespace pnb::player::test {

namespace {

struct FieldOptions {
    uint32_t lights = 64;
    gltf::Float3 origin{0, 0, 0};
    float range = 3.0f;
    float height = 1.2f;
};

// A 16 m floor with a row of boxes, lit by `lights` point lights on a jittered grid just above it
// (each reaching a few metres) and no sun, so every lit pixel comes from the clustered lights.
gltf::Document pointField(const FieldOptions& o) {
    gltf::Document doc;
    gltf::Material floor;
    floor.name = "floor";
    floor.baseColorFactor = {0.7f, 0.7f, 0.7f, 1};
    gltf::Material boxes;
    boxes.name = "boxes";
    boxes.baseColorFactor = {0.3f, 0.5f, 0.8f, 1};
    boxes.roughnessFactor = 0.35f;
    doc.materials = {floor, boxes};
    const gltf::Float3 at = o.origin;
    addObject(doc, "floor", quad(16, 16, 0), at, {-0.70710678f, 0, 0, 0.70710678f});
    for (int i = 0; i < 5; ++i)
        addObject(doc, "box" + std::to_string(i), box(1, 1.5f, 1, 1),
                  {at[0] - 5.0f + 2.5f * float(i), at[1] + 0.75f, at[2] - 1.0f});
    const auto side = uint32_t(std::ceil(std::sqrt(double(o.lights))));
    const float cell = 16.0f / float(side);
    for (uint32_t k = 0; k < o.lights; ++k) {
        gltf::Light l;
        l.name = "light" + std::to_string(k);
        l.type = gltf::LightType::Point;
        l.color = {0.5f + 0.5f * float(k % 3 == 0), 0.5f + 0.5f * float(k % 3 == 1), 0.5f + 0.5f * float(k % 3 == 2)};
        l.intensity = 2.0f;
        l.range = o.range;
        doc.lights.push_back(l);
        gltf::Node n;
        n.name = l.name;
        n.light = int32_t(doc.lights.size() - 1);
        const float jitter = 0.3f * std::sin(float(k) * 12.9898f);
        n.translation = {at[0] - 8.0f + (float(k % side) + 0.5f + jitter) * cell,
                         at[1] + o.height + 0.4f * std::cos(float(k) * 4.1414f),
                         at[2] - 8.0f + (float(k / side) + 0.5f - jitter) * cell};
        doc.nodes.push_back(n);
    }
    return doc;
}

RenderSettings culling(LightCulling c) {
    RenderSettings s;
    s.lightCulling = c;
    s.shadowTechnique = ShadowTechnique::Off; // the lights' shading alone
    return s;
}

// Clusters against every light at every pixel: the same picture within one 8-bit step, and the
// cluster pass really ran. Returns the clustered render.
Rendered expectClustersMatchEveryLight(const std::string& pnb, const CameraState& view, uint32_t w = 160,
                                       uint32_t h = 120) {
    Rendered clustered = render(pnb, view, w, h, culling(LightCulling::Clusters));
    Rendered every = render(pnb, view, w, h, culling(LightCulling::Off));
    EXPECT_GT(clustered.stats.lightClusters, 0u);
    EXPECT_EQ(every.stats.lightClusters, 0u);
    const ImageDiff d = compareRgba8(clustered.color, every.color);
    EXPECT_LE(d.maxAbs, 1) << "mean " << d.meanAbs;
    EXPECT_TRUE(allFinite(clustered.hdr));
    EXPECT_TRUE(allFinite(every.hdr));
    return clustered;
}

const CameraState kView = lookAt({0, 4.5, 9}, {0, 0, -1});

} // namespace

TEST(LightClusters, SixtyFourLightsShadeLikeEveryLightAtEveryPixel) {
    const std::string deferred = convert(pointField({}), "deferred");
    Rendered c = expectClustersMatchEveryLight(deferred, kView);
    // Not vacuous: the lights light the picture (black without them: no sun, tiny ambient).
    EXPECT_GT(c.color.u8.size(), 0u);
    double sum = 0;
    for (size_t i = 0; i < c.color.u8.size(); i += 4) sum += c.color.u8[i] + c.color.u8[i + 1];
    EXPECT_GT(sum / double(c.color.u8.size() / 4), 40.0);
    // Forward materials read the same clusters.
    const std::string forward = convert(pointField({}), "forward", R"({"materials": {"*": {"shading_path": "forward"}}})");
    expectClustersMatchEveryLight(forward, kView);
}

TEST(LightClusters, TheClusterDebugViewCountsTheLightsThatReachEachPixel) {
    const std::string pnb = convert(pointField({}), "debug");
    RenderSettings s = culling(LightCulling::Clusters);
    s.debugView = DebugView::LightClusters;
    Rendered r = render(pnb, kView, 160, 120, s);
    // Heat: count / 8 -> red, then green, then blue. Where lights reach, the counts are
    // between 1 and 64 (all of them) and differ across the view.
    int lit = 0, hot = 0;
    for (size_t i = 0; i < r.color.u8.size(); i += 4) {
        lit += r.color.u8[i] > 0;
        hot += r.color.u8[i + 1] > 0;
    }
    const int pixels = int(r.color.u8.size() / 4);
    EXPECT_GT(lit, pixels / 4);
    EXPECT_LT(hot, lit); // not every cluster holds more than 8 lights
}

TEST(LightClusters, ALightAtTheCameraAndLightsBehindTheNearPlaneAreKept) {
    gltf::Document doc = pointField({.lights = 16});
    // One light exactly at the camera, one just behind it reaching in front, one between the
    // camera and the near plane.
    const glm::dvec3 eye = kView.position;
    const glm::dvec3 forward = kView.rotation * glm::dvec3(0, 0, -1);
    for (double along : {0.0, -0.5, 0.05}) {
        gltf::Light l;
        l.name = "near" + std::to_string(doc.lights.size());
        l.type = gltf::LightType::Point;
        l.intensity = 20.0f;
        l.range = 8.0f;
        doc.lights.push_back(l);
        gltf::Node n;
        n.name = l.name;
        n.light = int32_t(doc.lights.size() - 1);
        const glm::dvec3 p = eye + forward * along;
        n.translation = {float(p.x), float(p.y), float(p.z)};
        doc.nodes.push_back(n);
    }
    CameraState view = kView;
    view.znear = 0.1f;
    expectClustersMatchEveryLight(convert(doc, "near"), view);
}

TEST(LightClusters, NoLocalLightsNeedNoClusters) {
    gltf::Document doc = pointField({.lights = 0});
    addLights(doc); // a sun and one lamp: below any cluster threshold...
    const std::string pnb = convert(doc, "few");
    Rendered autoChoice = render(pnb, kView, 96, 64, culling(LightCulling::Auto));
    EXPECT_EQ(autoChoice.stats.lightClusters, 0u);
    EXPECT_TRUE(allFinite(autoChoice.hdr));
    // ...but asked for, one lamp still clusters and shades like every light everywhere.
    expectClustersMatchEveryLight(pnb, kView, 96, 64);
    doc.lights.clear(); // none at all: the converter's default sun only
    for (auto& n : doc.nodes) n.light = gltf::kNone;
    Rendered none = render(convert(doc, "none"), kView, 96, 64, culling(LightCulling::Clusters));
    EXPECT_EQ(none.stats.lightClusters, 0u);
    EXPECT_TRUE(allFinite(none.hdr));
}

TEST(LightClusters, FourThousandLightsMissNoLight) {
    expectClustersMatchEveryLight(convert(pointField({.lights = 4096, .range = 1.0f, .height = 0.6f}), "many"),
                                  kView, 96, 64);
}

TEST(LightClusters, LightsAMillionUnitsFromTheOriginAreCulledExactly) {
    FieldOptions far{.lights = 64, .origin = {1e6f, 0, -1e6f}};
    CameraState view = kView;
    view.position += glm::dvec3(1e6, 0, -1e6);
    expectClustersMatchEveryLight(convert(pointField(far), "far"), view);
}

} // namespace pnb::player::test

namespace pnb::player::test {

TEST(LightClusters, EveryLightOfAPixelCountsPastTheShadingBatch) {
    // 100 coincident lights of a hundredth of the intensity light the floor exactly as one: a
    // pixel shades its lights in batches of 32 (lights.glsl), and none may be left out.
    auto scene = [](uint32_t copies) {
        gltf::Document doc = pointField({.lights = 0});
        for (uint32_t k = 0; k < copies; ++k) {
            gltf::Light l;
            l.name = "copy" + std::to_string(k);
            l.type = gltf::LightType::Point;
            l.intensity = 20.0f / float(copies);
            l.range = 30.0f;
            doc.lights.push_back(l);
            gltf::Node n;
            n.name = l.name;
            n.light = int32_t(doc.lights.size() - 1);
            n.translation = {0.5f, 2.5f, 1.0f};
            doc.nodes.push_back(n);
        }
        return doc;
    };
    for (LightCulling c : {LightCulling::Clusters, LightCulling::Off}) {
        RenderSettings s = culling(c);
        s.shadowLocal = false;
        Rendered many = render(convert(scene(100), "hundred"), kView, 96, 64, s);
        Rendered one = render(convert(scene(1), "one"), kView, 96, 64, s);
        const ImageDiff d = compareRgba8(many.color, one.color);
        EXPECT_LE(d.maxAbs, 1) << "mean " << d.meanAbs;
        EXPECT_GT(compareRgba8(many.color, render(convert(scene(0), "none"), kView, 96, 64, s).color).meanAbs, 5.0);
    }
}

} // namespace pnb::player::test
