// Numerical stability at the extremes: camera-relative transforms in double and reversed-Z with
// a float depth buffer make a scene 10^6 units from the origin, or a near/far ratio of 10^-5,
// render as the reference does. No output may hold NaN or Inf.
#include "render_fixture.h"

namespace pnb::player::test {

namespace {

// A floor, a box, and a thin decal 2 mm above the floor: z-fighting shows up at once if depth
// precision is lost.
gltf::Document precisionScene(gltf::Float3 offset) {
    gltf::Document doc;
    gltf::Material floor, decal, boxMat;
    floor.name = "floor";
    floor.baseColorFactor = {0.6f, 0.6f, 0.6f, 1};
    decal.name = "decal";
    decal.baseColorFactor = {0.9f, 0.1f, 0.1f, 1};
    boxMat.name = "box";
    boxMat.baseColorFactor = {0.1f, 0.4f, 0.9f, 1};
    doc.materials = {floor, decal, boxMat};
    const gltf::Float4 flat{-0.70710678f, 0, 0, 0.70710678f};
    auto at = [&](float x, float y, float z) { return gltf::Float3{offset[0] + x, offset[1] + y, offset[2] + z}; };
    addObject(doc, "floor", quad(10, 10, 0), at(0, 0, 0), flat);
    addObject(doc, "decal", quad(1.5f, 1.5f, 1), at(-1, 0.002f, 0), flat);
    addObject(doc, "box", box(1, 1, 1, 2), at(1.25f, 0.5f, -0.5f), gltf::rotationY(0.4f));
    addLights(doc, offset);
    return doc;
}

} // namespace

TEST(Precision, SceneFarFromTheOriginRendersAsAtTheOrigin) {
    // 10^6 and the offsets below are exact in float, so both files hold the same geometry.
    const gltf::Float3 far{1.0e6f, 0, -1.0e6f};
    std::string nearFile = convert(precisionScene({0, 0, 0}), "origin");
    std::string farFile = convert(precisionScene(far), "far");
    glm::dvec3 eye(0.5, 2.0, 5.0), target(0, 0.2, 0);
    glm::dvec3 shift(far[0], far[1], far[2]);
    // Tight cascade fits: computed in camera-relative double, so both scenes get the same maps.
    // (Sphere fits snap to a texel grid fixed in world space, whose phase differs between the
    // two places by design; ShadowRendering.FarFromTheOrigin covers them.)
    RenderSettings settings;
    settings.shadowFit = CascadeFit::Tight;
    settings.shadowResolution = 512;
    Rendered a = render(nearFile, lookAt(eye, target), 160, 120, settings);
    Rendered b = render(farFile, lookAt(eye + shift, target + shift), 160, 120, settings);
    ImageDiff d = compareRgba8(a.color, b.color);
    EXPECT_LE(d.maxAbs, 2) << "mean " << d.meanAbs;
    EXPECT_TRUE(allFinite(a.hdr));
    EXPECT_TRUE(allFinite(b.hdr));
    // The decal is visible in both (not lost to z-fighting).
    size_t red = 0;
    for (size_t i = 0; i < b.color.u8.size(); i += 4) red += b.color.u8[i] > 150 && b.color.u8[i + 1] < 80;
    EXPECT_GT(red, b.color.u8.size() / 4 / 50);
}

TEST(Precision, NearFarRatioOfOneInTenToTheFive) {
    std::string file = convert(precisionScene({0, 0, 0}), "scene");
    glm::dvec3 eye(0.5, 2.0, 5.0), target(0, 0.2, 0);
    Rendered reference = render(file, lookAt(eye, target, 0.1f, 0.0f));
    // near 1e-3, far 100 (the scene's far edge is 10 away): ratio 1e-5; and near 1e-5 with an
    // infinite far plane.
    Rendered finite = render(file, lookAt(eye, target, 1e-3f, 100.0f));
    Rendered tiny = render(file, lookAt(eye, target, 1e-5f, 0.0f));
    for (const Rendered* r : {&finite, &tiny}) {
        ImageDiff d = compareRgba8(reference.color, r->color);
        // A different projection matrix may move a silhouette edge by one pixel; nothing else.
        EXPECT_LE(d.fractionOver(2), 0.001) << "mean " << d.meanAbs;
        EXPECT_LT(d.meanAbs, 0.05);
        EXPECT_TRUE(allFinite(r->hdr));
        EXPECT_TRUE(allFinite(r->depth));
    }
}

// The reference (docs/REFERENCE.md, "Tolerances") allows a reconstructed position to be off its
// surface by 2^-16 of its distance from the eye. Measured here: the floor (y = 0) seen at
// grazing and steep angles, at three scales, near and far from the origin; every floor pixel's
// height over its distance must stay 16 x inside that band.
TEST(Precision, ReconstructedPositionsStayFarInsideTheReferencesBand) {
    for (float scale : {1e-4f, 1.0f, 1e4f}) {
        const gltf::Float3 offset{scale * 1e3f, 0, 0};
        gltf::Document doc;
        gltf::Material floor;
        floor.name = "floor";
        doc.materials = {floor};
        addObject(doc, "floor", quad(200 * scale, 200 * scale, 0), offset, {-0.70710678f, 0, 0, 0.70710678f});
        addLights(doc, offset);
        std::string file = convert(doc, "floor");
        const glm::dvec3 o(offset[0], offset[1], offset[2]);
        for (glm::dvec3 eye : {glm::dvec3(0, 0.3, 5), glm::dvec3(0, 4, 3)}) {
            Rendered r = render(file, lookAt(o + eye * double(scale), o + glm::dvec3(0, 0, -20) * double(scale),
                                             0.05f * scale, 0.0f), 160, 120);
            double worst = 0;
            size_t floorPixels = 0;
            for (size_t i = 0; i + 2 < r.position.f32.size(); i += 3) {
                glm::dvec3 p(r.position.f32[i], r.position.f32[i + 1], r.position.f32[i + 2]);
                if (!std::isfinite(p.x)) continue;
                ++floorPixels;
                worst = std::max(worst, std::fabs(p.y + eye.y * scale) / glm::length(p));
            }
            EXPECT_GT(floorPixels, 160u * 120u / 4);
            EXPECT_LT(worst, 1.0 / 65536 / 16) << "scale " << scale << ", eye height " << eye.y;
            RecordProperty("worst_relative_position_error_x1e9_scale_" + std::to_string(scale) +
                               "_eye_height_" + std::to_string(eye.y),
                           std::to_string(worst * 1e9));
        }
    }
}

TEST(Precision, NoNanOrInfFromDegenerateInput) {
    // Zero-area light cone, zero roughness, a camera inside the box: nothing may produce NaN.
    gltf::Document doc = precisionScene({0, 0, 0});
    doc.materials[2].roughnessFactor = 0.0f;
    doc.materials[2].metallicFactor = 1.0f;
    std::string file = convert(doc, "degenerate");
    for (const CameraState& cam : {lookAt({1.25, 0.5, -0.5}, {0, 0, 0}), lookAt({0, 30, 0.001}, {0, 0, 0}),
                                   lookAt({0, 0.0005, 3}, {0, 0.0005, 0}, 1e-5f)}) {
        Rendered r = render(file, cam, 96, 64);
        EXPECT_TRUE(allFinite(r.hdr));
        EXPECT_TRUE(allFinite(r.depth));
    }
}

} // namespace pnb::player::test
