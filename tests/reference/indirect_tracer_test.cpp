// The one-bounce truth checks itself against closed forms: a point facing a lit square floor
// receives rho E F (F the view factor of the square), per colour; a sun below the floor gives
// nothing; the estimate's standard error shrinks as 1/sqrt(N); the same seed gives the same
// answer on all threads; shadow rays towards a point light stop at the light. More bounces: inside
// a closed box every reflection lands on a wall, so the wall-averaged light of each bounce is the
// albedo times the last one's: two bounces give (1 + a) and the converged light 1 / (1 - a) times
// the one-bounce light.
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/glm.hpp>

#include "pnb_reference/indirect_metrics.h"
#include "pnb_reference/indirect_tracer.h"
#include "pnb_reference/shadow_tracer.h"
#include "reference_test_util.h"

namespace pnb::reference::test {
namespace {

constexpr double kPi = std::numbers::pi;

// View factor from a differential area facing a parallel square of half-size a, centred below
// it at distance h (Howell's catalogue, C-11, four a x a rectangles meeting below the point).
double squareViewFactor(double a, double h) {
    double x = a / h, y = a / h;
    double f = (x / std::sqrt(1 + x * x)) * std::atan(y / std::sqrt(1 + x * x)) +
               (y / std::sqrt(1 + y * y)) * std::atan(x / std::sqrt(1 + y * y));
    return 4.0 * f / (2.0 * kPi);
}

// A lit square floor (half-size `half`, albedo `albedo`) and a sun of `lux` along `travel`.
std::unique_ptr<LoadedScene> floorScene(const TempDir& dir, double half, gltf::Float3 albedo, float lux,
                                        gltf::Float4 sunRotation) {
    gltf::Document doc;
    gltf::Material m = material("floor");
    m.baseColorFactor = {albedo[0], albedo[1], albedo[2], 1};
    doc.materials.push_back(m);
    pnb::test::addObject(doc, "floor", pnb::test::quad(float(2 * half), float(2 * half), 0), {0, 0, 0}, kFaceUp);
    gltf::Light sun;
    sun.name = "sun";
    sun.intensity = lux;
    doc.lights.push_back(sun);
    gltf::Node n;
    n.name = "sun";
    n.light = 0;
    n.rotation = sunRotation;
    doc.nodes.push_back(n);
    std::string path = pnb::test::convertDocument(dir.str(), doc, "floor", "", false);
    return loadPnb(path);
}

// A floor scene and its tracer, kept together (the tracer reads the scene's mapping).
struct Floor {
    TempDir dir;
    std::unique_ptr<LoadedScene> scene;
    std::unique_ptr<IndirectTracer> tracer;
    explicit Floor(const std::string& name) : dir(name) {}
};

std::unique_ptr<Floor> floorTracer(const std::string& name, double half, gltf::Float3 albedo, float lux,
                                   gltf::Float4 sunRotation) {
    auto f = std::make_unique<Floor>(name);
    f->scene = floorScene(f->dir, half, albedo, lux, sunRotation);
    if (!f->scene) return nullptr;
    auto tracer = IndirectTracer::build(f->scene->scene, glm::dvec3(0.0));
    EXPECT_TRUE(tracer.ok()) << (tracer.ok() ? "" : tracer.error().message);
    if (!tracer) return nullptr;
    f->tracer = std::move(*tracer);
    return f;
}

struct Estimate {
    std::vector<glm::vec3> mean, error;
};

Estimate estimate(const IndirectTracer& tracer, const std::vector<glm::vec3>& points, glm::vec3 normal,
                  uint32_t samples, uint64_t seed = 1) {
    Estimate e;
    e.mean.resize(points.size());
    e.error.resize(points.size());
    std::vector<glm::vec3> normals(points.size(), normal);
    IndirectSettings s;
    s.samples = samples;
    s.seed = seed;
    tracer.irradiance(points, normals, s, e.mean, e.error);
    return e;
}

TEST(IndirectTracer, APointOverALitFloorReceivesAlbedoTimesIrradianceTimesTheViewFactor) {
    const double half = 5.0, h = 1.0;
    const float lux = 3.0f;
    auto floor = floorTracer("indirect-floor", half, {0.8f, 0.4f, 0.2f}, lux, kFaceUp); // sun straight down
    ASSERT_TRUE(floor);
    const IndirectTracer& tracer = *floor->tracer;
    EXPECT_EQ(tracer.stats().lights, 1u);
    // Points facing down at height h over the floor's centre: nothing shadows the floor.
    std::vector<glm::vec3> points(64, glm::vec3(0.0f, float(h), 0.0f));
    Estimate e = estimate(tracer, points, {0, -1, 0}, 1024);
    const double f = squareViewFactor(half, h); // 0.9407 for a = 5, h = 1
    glm::dvec3 mean(0.0), se(0.0);
    for (size_t i = 0; i < points.size(); ++i) {
        mean += glm::dvec3(e.mean[i]) / double(points.size());
        se += glm::dvec3(e.error[i]) / double(points.size());
    }
    const double albedo[3] = {0.8, 0.4, 0.2};
    for (int c = 0; c < 3; ++c) {
        double truth = albedo[c] * lux * f;
        // The average of 64 independent estimates: its error is se / 8; allow 4 of those.
        EXPECT_NEAR(mean[c], truth, 4.0 * se[c] / 8.0 + 1e-6) << "channel " << c;
        EXPECT_NEAR(mean[c], truth, 0.02 * truth) << "channel " << c;
    }
}

TEST(IndirectTracer, StandardErrorShrinksWithTheSquareRootOfTheSampleCount) {
    auto floor = floorTracer("indirect-noise", 1.0, {1, 1, 1}, 1.0f, kFaceUp);
    ASSERT_TRUE(floor);
    const IndirectTracer& tracer = *floor->tracer;
    std::vector<glm::vec3> point(1, glm::vec3(0, 3, 0));
    Estimate a = estimate(tracer, point, {0, -1, 0}, 256), b = estimate(tracer, point, {0, -1, 0}, 4096);
    ASSERT_GT(a.error[0].x, 0.0f);
    EXPECT_NEAR(a.error[0].x / b.error[0].x, 4.0, 0.6);
    double truth = squareViewFactor(1.0, 3.0);
    EXPECT_NEAR(b.mean[0].x, truth, 4.0 * b.error[0].x);
}

TEST(IndirectTracer, ASunBelowTheFloorAndPointsWithoutSurfaceGiveNothing) {
    const gltf::Float4 up{0.70710678f, 0, 0, 0.70710678f}; // shines along +Y: from below
    auto floor = floorTracer("indirect-below", 5.0, {1, 1, 1}, 1e6f, up);
    ASSERT_TRUE(floor);
    const IndirectTracer& tracer = *floor->tracer;
    std::vector<glm::vec3> points = {{0, 1, 0}, {NAN, 0, 0}};
    Estimate e = estimate(tracer, points, {0, -1, 0}, 64);
    // The floor's top is what the point sees; the sun lights its underside only.
    EXPECT_EQ(e.mean[0], glm::vec3(0.0f));
    EXPECT_TRUE(std::isnan(e.mean[1].x));
}

TEST(IndirectTracer, TheSameSeedGivesTheSameAnswerAndPointsAreIndependent) {
    auto floor = floorTracer("indirect-seed", 5.0, {0.5f, 0.5f, 0.5f}, 2.0f, kFaceUp);
    ASSERT_TRUE(floor);
    const IndirectTracer& tracer = *floor->tracer;
    std::vector<glm::vec3> many(3000, glm::vec3(0, 1, 0));
    many[1234] = glm::vec3(2, 0.5f, 1);
    Estimate all = estimate(tracer, many, {0, -1, 0}, 32, 7);
    Estimate again = estimate(tracer, many, {0, -1, 0}, 32, 7);
    EXPECT_EQ(all.mean, again.mean);
    Estimate other = estimate(tracer, many, {0, -1, 0}, 32, 8);
    EXPECT_NE(all.mean[0], other.mean[0]);
}

// A closed 2 x 2 x 2 box (grey `albedo`) lit by a point light inside it, off centre, and
// points on a uniform grid over its six inner faces (equal areas), facing in.
struct ClosedBox {
    TempDir dir{"indirect-closed-box"};
    std::unique_ptr<LoadedScene> scene;
    std::unique_ptr<IndirectTracer> tracer;
    std::vector<glm::vec3> points, normals;
};

std::unique_ptr<ClosedBox> closedBox(float albedo, int grid) {
    auto b = std::make_unique<ClosedBox>();
    gltf::Document doc;
    gltf::Material m = material("wall");
    m.baseColorFactor = {albedo, albedo, albedo, 1};
    doc.materials.push_back(m);
    pnb::test::addObject(doc, "box", pnb::test::box(2, 2, 2, 0), {0, 0, 0});
    gltf::Light lamp;
    lamp.name = "lamp";
    lamp.type = gltf::LightType::Point;
    lamp.intensity = 10.0f;
    lamp.range = 100.0f; // far beyond the box: the inverse square alone inside it
    doc.lights.push_back(lamp);
    gltf::Node lampNode;
    lampNode.name = "lamp";
    lampNode.light = 0;
    lampNode.translation = {0.3f, 0.2f, -0.1f};
    doc.nodes.push_back(lampNode);
    b->scene = loadPnb(pnb::test::convertDocument(b->dir.str(), doc, "closed-box", "", false));
    if (!b->scene) return nullptr;
    auto tracer = IndirectTracer::build(b->scene->scene, glm::dvec3(0.0));
    EXPECT_TRUE(tracer.ok()) << (tracer.ok() ? "" : tracer.error().message);
    if (!tracer) return nullptr;
    b->tracer = std::move(*tracer);
    for (int axis = 0; axis < 3; ++axis)
        for (int sign = -1; sign <= 1; sign += 2)
            for (int i = 0; i < grid; ++i)
                for (int j = 0; j < grid; ++j) {
                    glm::vec3 p(0.0f), n(0.0f);
                    p[axis] = float(sign);
                    p[(axis + 1) % 3] = -1.0f + 2.0f * (float(i) + 0.5f) / float(grid);
                    p[(axis + 2) % 3] = -1.0f + 2.0f * (float(j) + 0.5f) / float(grid);
                    n[axis] = -float(sign);
                    b->points.push_back(p);
                    b->normals.push_back(n);
                }
    return b;
}

// The mean over the points (the wall average) of the estimate with `bounces`, and its standard
// error; every point's estimate in `each`.
double wallMean(const ClosedBox& b, uint32_t bounces, uint32_t samples, double& standardError,
                std::vector<glm::vec3>* each = nullptr, uint64_t seed = 1) {
    std::vector<glm::vec3> mean(b.points.size()), error(b.points.size());
    IndirectSettings s;
    s.samples = samples;
    s.bounces = bounces;
    s.seed = seed;
    b.tracer->irradiance(b.points, b.normals, s, mean, error);
    double sum = 0, variance = 0;
    for (size_t i = 0; i < mean.size(); ++i) {
        sum += mean[i].x;
        variance += double(error[i].x) * error[i].x;
    }
    const double count = double(mean.size());
    standardError = std::sqrt(variance) / count;
    if (each) *each = mean;
    return sum / count;
}

TEST(IndirectTracerBounces, EachBounceInAClosedBoxAddsTheAlbedoTimesTheLast) {
    const float a = 0.5f;
    auto box = closedBox(a, 12);
    ASSERT_TRUE(box);
    double se1 = 0, se2 = 0, seConverged = 0;
    std::vector<glm::vec3> one, two;
    const double e1 = wallMean(*box, 1, 128, se1, &one);
    const double e2 = wallMean(*box, 2, 128, se2, &two);
    const double converged = wallMean(*box, 0, 128, seConverged);
    ASSERT_GT(e1, 0.0);
    // The second bounce shares the first's rays: it only adds, at every point.
    for (size_t i = 0; i < one.size(); ++i) ASSERT_GE(two[i].x, one[i].x) << i;
    // Wall averages: exact for the integrals; the 12 x 12 grid's quadrature and the noise (a
    // few tenths of a percent) stay well inside 3 %.
    EXPECT_NEAR(e2 / e1, 1.0 + a, 0.03 * (1.0 + a)) << "se " << se1 << " " << se2;
    EXPECT_NEAR(converged / e1, 1.0 / (1.0 - a), 0.03 / (1.0 - a)) << "se " << seConverged;
    EXPECT_GT(seConverged, 0.0);
}

TEST(IndirectTracerBounces, ConvergedMatchesManyBouncesAndIsDeterministic) {
    auto box = closedBox(0.7f, 6);
    ASSERT_TRUE(box);
    double seConverged = 0, seMany = 0, seAgain = 0;
    std::vector<glm::vec3> first, again;
    const double converged = wallMean(*box, 0, 256, seConverged, &first, 3);
    const double many = wallMean(*box, 40, 256, seMany, nullptr, 3); // 0.7^40 < 1e-6
    wallMean(*box, 0, 256, seAgain, &again, 3);
    EXPECT_EQ(first, again);
    EXPECT_NEAR(converged, many, 4.0 * std::hypot(seConverged, seMany));
    // Roulette ends paths early and makes up for it in weight: no more noise than 40 bounces'
    // worth of it times a small factor.
    EXPECT_LT(seConverged, 3.0 * seMany);
    std::vector<glm::vec3> other;
    wallMean(*box, 0, 256, seAgain, &other, 4);
    EXPECT_NE(first, other);
}

// A flat floor cannot light itself: every path's second ray leaves for the black sky, so more
// bounces change nothing, bit for bit.
TEST(IndirectTracerBounces, AFlatFloorGetsNothingFromMoreBounces) {
    auto floor = floorTracer("indirect-flat-bounces", 5.0, {0.9f, 0.9f, 0.9f}, 2.0f, kFaceUp);
    ASSERT_TRUE(floor);
    std::vector<glm::vec3> points(16, glm::vec3(0, 1, 0)), normals(16, glm::vec3(0, -1, 0));
    std::vector<glm::vec3> one(16), converged(16), error(16);
    IndirectSettings s;
    s.samples = 64;
    floor->tracer->irradiance(points, normals, s, one, error);
    s.bounces = 0;
    floor->tracer->irradiance(points, normals, s, converged, error);
    EXPECT_EQ(one, converged);
    EXPECT_GT(one[0].x, 0.0f);
}

TEST(IndirectTracerBounces, ParsesTheCommandLineSpelling) {
    EXPECT_EQ(parseIndirectBounces("1"), 1u);
    EXPECT_EQ(parseIndirectBounces("8"), 8u);
    EXPECT_EQ(parseIndirectBounces("converged"), 0u);
    EXPECT_FALSE(parseIndirectBounces("0"));
    EXPECT_FALSE(parseIndirectBounces("-1"));
    EXPECT_FALSE(parseIndirectBounces("2x"));
    EXPECT_FALSE(parseIndirectBounces("100000"));
    EXPECT_EQ(indirectBouncesName(0), "converged");
    EXPECT_EQ(indirectBouncesName(3), "3");
}

TEST(ShadowTracerPointLight, SegmentsToThePointLightAreBlockedOnlyBetweenPointAndLight) {
    TempDir dir("point-visibility");
    auto scene = loadPnb(pnb::test::convertDocument(dir.str(), groundAndBox(), "ground-box", "", false));
    ASSERT_TRUE(scene);
    auto tracer = ShadowTracer::build(scene->scene, glm::dvec3(0.0));
    ASSERT_TRUE(tracer.ok());
    std::vector<glm::vec3> points = {{0, 0, 0}, {10, 0, 0}, {0, 0, 0}, {NAN, 0, 0}};
    std::vector<float> above(4), between(4);
    (*tracer)->visibilityToPoint(points, {0, 10, 0}, above);  // the box (y 2..4) is in the way
    (*tracer)->visibilityToPoint(points, {0, 1, 0}, between); // the light is under the box
    EXPECT_EQ(above[0], 0.0f);
    EXPECT_EQ(above[1], 1.0f);
    EXPECT_EQ(between[0], 1.0f);
    EXPECT_EQ(between[1], 1.0f);
    EXPECT_TRUE(std::isnan(above[3]));
    std::vector<float> bad(4);
    (*tracer)->visibilityToPoint(points, {NAN, 1, 0}, bad);
    for (float v : bad) EXPECT_TRUE(std::isnan(v));
}

TEST(IndirectMetrics, RmseEnergyChannelsAndLeak) {
    std::vector<glm::vec3> reference = {{1, 1, 1}, {1, 1, 1}, {0, 0, 0}, {NAN, NAN, NAN}};
    std::vector<glm::vec3> error(4, glm::vec3(0.01f));
    std::vector<glm::vec3> player = {{2, 1, 1}, {1, 1, 1}, {0.5f, 0.5f, 0.5f}, {9, 9, 9}};
    IndirectErrorMetrics m = compareIndirect(player, reference, error);
    EXPECT_EQ(m.pixels, 3u);
    double lum0 = luminance({2, 1, 1});
    EXPECT_NEAR(m.energyRatio, (lum0 + 1 + 0.5) / 2.0, 1e-9);
    EXPECT_NEAR(m.channelRatio[0], 3.5 / 2.0, 1e-9);
    EXPECT_NEAR(m.channelRatio[1], 2.5 / 2.0, 1e-9);
    EXPECT_NEAR(m.leakPercent, 100.0 * 0.5 / (lum0 + 1 + 0.5), 1e-9);
    double rmse = std::sqrt(((lum0 - 1) * (lum0 - 1) + 0.25) / 3.0);
    EXPECT_NEAR(m.relativeRmsePercent, 100.0 * rmse / (2.0 / 3.0), 1e-6);
    EXPECT_NEAR(m.referenceNoisePercent, 100.0 * 0.01 / (2.0 / 3.0), 1e-5);
    double se = luminance({0.01f, 0.01f, 0.01f});
    EXPECT_NEAR(m.correctedRmsePercent,
                100.0 * std::sqrt(((lum0 - 1) * (lum0 - 1) + 0.25) / 3.0 - se * se) / (2.0 / 3.0), 1e-5);
}

// The scorecard's baselines on fields whose answers are known: a pattern right up to scale, the
// best constant itself, no light at all, and an anti-correlated guess.
TEST(IndirectMetrics, ScorecardBaselines) {
    std::vector<glm::vec3> truth = {glm::vec3(1), glm::vec3(2), glm::vec3(3), glm::vec3(6)};
    std::vector<glm::vec3> noNoise(truth.size(), glm::vec3(0));
    const double mean = 3.0, varTruth = (4 + 1 + 0 + 9) / 4.0;

    std::vector<glm::vec3> doubled;
    for (auto v : truth) doubled.push_back(2.0f * v);
    IndirectErrorMetrics twice = compareIndirect(doubled, truth, noNoise);
    EXPECT_NEAR(twice.bestScale, 0.5, 1e-6);
    EXPECT_NEAR(twice.scaledRmsePercent, 0.0, 1e-3);
    EXPECT_NEAR(twice.correlation, 1.0, 1e-9);
    EXPECT_NEAR(twice.bestConstantRmsePercent, 100.0 * std::sqrt(varTruth) / mean, 1e-4);
    EXPECT_NEAR(twice.zeroRmsePercent, 100.0 * std::sqrt((1 + 4 + 9 + 36) / 4.0) / mean, 1e-4);
    EXPECT_NEAR(twice.rmseOverBestConstant, twice.correctedRmsePercent / twice.bestConstantRmsePercent, 1e-12);
    EXPECT_GT(twice.rmseOverBestConstant, 1.0); // twice the light is worse than the mean

    IndirectErrorMetrics constant = compareIndirect(std::vector<glm::vec3>(4, glm::vec3(3)), truth, noNoise);
    EXPECT_NEAR(constant.rmseOverBestConstant, 1.0, 1e-6);
    EXPECT_EQ(constant.correlation, 0.0); // a constant has no pattern to correlate

    IndirectErrorMetrics zero = compareIndirect(std::vector<glm::vec3>(4, glm::vec3(0)), truth, noNoise);
    EXPECT_NEAR(zero.correctedRmsePercent, zero.zeroRmsePercent, 1e-6);
    EXPECT_EQ(zero.bestScale, 0.0);

    std::vector<glm::vec3> reversed(truth.rbegin(), truth.rend());
    EXPECT_LT(compareIndirect(reversed, truth, noNoise).correlation, -0.5);

    // The truth's noise is taken out of every baseline alike: a noisy truth (standard error 0.5)
    // lowers the best constant's error, not raise it, and leaves the correlation at 1.
    std::vector<glm::vec3> noise(truth.size(), glm::vec3(0.5f));
    IndirectErrorMetrics noisy = compareIndirect(doubled, truth, noise);
    const double se = luminance(glm::vec3(0.5f));
    EXPECT_NEAR(noisy.bestConstantRmsePercent, 100.0 * std::sqrt(varTruth - se * se) / mean, 1e-4);
    EXPECT_NEAR(noisy.correlation, 1.0, 1e-9); // clamped: noise removal can overshoot 1
}

} // namespace
} // namespace pnb::reference::test
