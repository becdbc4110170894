// Light through glass on the window scene (issue 43's target): at every named floor point of
// pnb-make-scene window (pnb_assets/window_scene.h) the irradiance the player applies and the
// irradiance the truth traces are within 5 % of the analytic value per channel: the sun through
// the orange roof pane, the roof's shadow, and a spot through no pane, the green one, the blue
// one and both. Both sides' irradiance is the light's unshadowed irradiance at the point (the
// falloff and cone code every lit frame already runs) times the colour visibility they give it:
// the player's through its transmittance maps (--dump shadow_color), the truth's by Embree.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_assets/window_scene.h"
#include "pnb_reference/local_light.h"
#include "pnb_reference/shadow_tracer.h"
#include "render_fixture.h"

namespace pnb::player::test {
namespace {

constexpr uint32_t kWidth = 480, kHeight = 270;

CameraState windowCamera() {
    const assets::WindowSceneLayout& l = assets::windowSceneLayout();
    CameraState c = lookAt({l.cameraPosition[0], l.cameraPosition[1], l.cameraPosition[2]},
                           {l.cameraTarget[0], l.cameraTarget[1], l.cameraTarget[2]});
    c.yfovRadians = float(l.cameraYFovDegrees * 3.14159265358979 / 180.0);
    return c;
}

struct Frame {
    CapturedImage position, color;
};

// The colour visibility of `judgedLight` (-1: the sun) and the positions, one frame.
Frame capture(const std::string& file, int judgedLight, uint32_t divisorLog2) {
    Frame f;
    auto scene = loadScene(file);
    EXPECT_TRUE(scene.ok());
    if (!scene.ok()) return f;
    RenderSettings s;
    s.shadowJudgedLight = judgedLight;
    s.shadowTranslucentDivisorLog2 = divisorLog2;
    auto renderer = Renderer::create(**scene, s);
    EXPECT_TRUE(renderer.ok());
    if (!renderer.ok()) return f;
    EXPECT_TRUE((*renderer)->render(windowCamera(), kWidth, kHeight).ok());
    auto position = (*renderer)->capture(CaptureBuffer::Position);
    auto color = (*renderer)->capture(CaptureBuffer::ShadowColor);
    EXPECT_TRUE(position.ok() && color.ok());
    if (!position.ok() || !color.ok()) return f;
    f.position = std::move(*position);
    f.color = std::move(*color);
    return f;
}

// The pixel whose surface lies nearest to `world` on the floor, or -1 beyond `tolerance`.
long nearestPixel(const CapturedImage& position, glm::dvec3 eye, glm::dvec3 world, double tolerance) {
    long best = -1;
    double bestDistance = tolerance;
    for (size_t i = 0; i < size_t(position.width) * position.height; ++i) {
        glm::dvec3 p(position.f32[i * 3], position.f32[i * 3 + 1], position.f32[i * 3 + 2]);
        if (!std::isfinite(p.x)) continue;
        const double d = glm::length(p + eye - world);
        if (d < bestDistance) {
            bestDistance = d;
            best = long(i);
        }
    }
    return best;
}

// Within 5 % of the analytic irradiance per channel; where that is 0 (the roof's shadow), within
// 0.5 % of the unshadowed irradiance.
void expectIrradiance(const char* who, const assets::WindowProbe& probe, glm::dvec3 visibility) {
    for (int k = 0; k < 3; ++k) {
        const double expected = probe.irradiance[size_t(k)];
        const double got = probe.unshadowedIrradiance * visibility[k];
        const double tolerance = expected > 0 ? 0.05 * expected : 0.005 * probe.unshadowedIrradiance;
        EXPECT_NEAR(got, expected, tolerance) << who << ", " << probe.name << ", channel " << "rgb"[k];
    }
}

TEST(WindowGlass, IrradianceBehindThePanesWithinFivePercentInPlayerAndTruth) {
    const std::string file = convert(assets::buildWindowScene(), "window");
    auto container = Container::open(file);
    ASSERT_TRUE(container.ok());
    auto decoded = readScene(*container);
    ASSERT_TRUE(decoded.ok());
    const CameraState camera = windowCamera();
    auto tracer = reference::ShadowTracer::build(*decoded, camera.position);
    ASSERT_TRUE(tracer.ok()) << tracer.error().message;
    EXPECT_EQ((*tracer)->stats().translucentCasters, 3u);

    // Every companion size the player offers: the probes lie 0.4 m from any glass-shadow edge.
    for (uint32_t divisorLog2 : {0u, 2u, 3u}) {
        SCOPED_TRACE("shadows.translucent_divisor " + std::to_string(1u << divisorLog2));
        const Frame sun = capture(file, -1, divisorLog2), spot = capture(file, 1, divisorLog2);
        for (const assets::WindowProbe& probe : assets::windowSceneProbes()) {
            const bool isSun = probe.lightIndex == 0;
            const Frame& f = isSun ? sun : spot;
            const glm::dvec3 world(probe.position[0], probe.position[1], probe.position[2]);
            const long i = nearestPixel(f.position, camera.position, world, 0.03);
            ASSERT_GE(i, 0) << probe.name << " is not seen within 3 cm";
            const float* c = &f.color.f32[size_t(i) * 4];
            ASSERT_GE(c[0], 0.0f) << probe.name << ": the player left the pixel out";
            expectIrradiance("player", probe, glm::dvec3(c[0], c[1], c[2]));
            if (divisorLog2 != 0) continue; // the truth does not depend on the player's settings
            // The truth at the exact probe point (camera-relative, as the tracer's origin is
            // the camera).
            const glm::vec3 point(world - camera.position);
            glm::vec3 truth(NAN);
            if (isSun) {
                const glm::vec3 toward(-assets::windowSceneLayout().sunTravel[0],
                                       -assets::windowSceneLayout().sunTravel[1],
                                       -assets::windowSceneLayout().sunTravel[2]);
                (*tracer)->colorVisibility({&point, 1}, toward, {&truth, 1});
            } else {
                auto light = reference::placeLocalLight(*decoded, probe.lightIndex);
                ASSERT_TRUE(light.ok());
                (*tracer)->colorVisibilityToPoint({&point, 1}, glm::vec3(light->position - camera.position),
                                                  {&truth, 1});
            }
            expectIrradiance("truth", probe, glm::dvec3(truth));
            std::printf("  %-16s player (%.4f %.4f %.4f) truth (%.4f %.4f %.4f) analytic (%.4f %.4f %.4f)\n",
                        std::string(probe.name).c_str(), c[0], c[1], c[2], truth.r, truth.g, truth.b,
                        probe.colorVisibility[0], probe.colorVisibility[1], probe.colorVisibility[2]);
        }
    }
}

} // namespace
} // namespace pnb::player::test
