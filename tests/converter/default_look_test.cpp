// What the converter adds to a scene that lacks it (docs/CONVERTER.md "Defaults"): the neutral
// default environment ("default-studio", flagged generated in ENVM, left out by a flag, never
// replacing the source's or the command line's own, not added where the source has lights),
// and the default camera and orbit that keep the bounding sphere inside the frustum with a 10 %
// margin for tall, wide and flat objects. The command line's one summary line is in
// summary_json_test.cpp.

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "pnb/node_transform.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/procedural_scenes.h"
#include "pnb_converter/camera_path.h"
#include "pnb_converter/convert.h"
#include "pnb_converter/environment.h"
#include "pnb_lighting/sh9.h"
#include "gltf_fixture.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;

const char* kBoxTextured = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
constexpr double kPi = 3.14159265358979323846;

class DefaultLook : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_default_look_" + std::string(info->name()) + "_" + std::to_string(getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    ConvertSettings settings(const std::string& in, const char* out) {
        ConvertSettings s;
        s.input = in;
        s.output = (dir / out).string();
        s.validateShaders = false;
        s.noSidecar = true;
        s.defaultEnvironment = true; // as pnb-convert does
        return s;
    }
    fs::path writeScene(const char* name, const assets::gltf::Document& doc) {
        fs::path p = dir / (std::string(name) + ".glb");
        auto bytes = assets::gltf::encodeGlb(doc);
        std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                 std::streamsize(bytes.size()));
        return p;
    }
    static Scene read(const std::string& path, std::optional<Container>& keep) {
        auto c = Container::open(path);
        EXPECT_TRUE(c.ok());
        keep.emplace(std::move(*c));
        auto scene = readScene(*keep);
        EXPECT_TRUE(scene.ok());
        return std::move(*scene);
    }
};

glm::dvec3 irradiance(const pnb::Environment& e, glm::dvec3 n) {
    lighting::Sh9Rgb sh;
    for (int k = 0; k < 9; ++k) sh.c[k] = {e.irradianceSh[k].x, e.irradianceSh[k].y, e.irradianceSh[k].z};
    return lighting::sh9Evaluate(sh, glm::normalize(n));
}

// [SECTION] the default environment

TEST_F(DefaultLook, ALightlessSourceGetsTheStudioFlaggedGenerated) {
    auto sum = convertScene(settings(kBoxTextured, "box.pnb"));
    ASSERT_TRUE(sum.ok()) << sum.error().message;
    EXPECT_TRUE(sum->defaultEnvironment);
    EXPECT_TRUE(sum->defaultSun) << "the sun stays beside it, for shadows";
    ASSERT_TRUE(sum->environment.has_value());
    EXPECT_TRUE(sum->environment->generated);
    EXPECT_EQ(sum->environment->name, kDefaultEnvironmentName);
    EXPECT_EQ(addedDefaults(*sum), (std::vector<std::string>{"default sun", "default environment",
                                                             "default camera", "default orbit"}));
    for (const std::string& w : sum->warnings)
        EXPECT_EQ(w.find("default"), std::string::npos) << "additions are not warnings: " << w;

    std::optional<Container> c;
    Scene scene = read((dir / "box.pnb").string(), c);
    ASSERT_TRUE(scene.environment.has_value());
    const pnb::Environment& e = *scene.environment;
    EXPECT_TRUE(e.generated) << "ENVM version 2's flag survives the file";
    EXPECT_EQ(scene.str(e.name), kDefaultEnvironmentName);
    EXPECT_NE(e.specular, kNone);
    // The documented levels (environment.h): a white diffuse surface facing up sees about
    // 0.9 nits (E / pi), facing the camera's side about 0.5, facing down the dark floor: lit,
    // not blown out, brighter above than below.
    const double up = irradiance(e, {0, 1, 0}).y / kPi, side = irradiance(e, {0, 0, 1}).y / kPi,
                 down = irradiance(e, {0, -1, 0}).y / kPi;
    EXPECT_GT(up, 0.7);
    EXPECT_LT(up, 1.1);
    EXPECT_GT(side, 0.35);
    EXPECT_LT(side, 0.7);
    EXPECT_LT(down, 0.5 * side);
    EXPECT_GT(down, 0.0);
    const glm::dvec3 grey = irradiance(e, {0.3, 0.5, 0.8});
    EXPECT_NEAR(grey.x, grey.y, 1e-4 * grey.y) << "neutral: no colour of its own";
    EXPECT_NEAR(grey.z, grey.y, 1e-4 * grey.y);
}

TEST_F(DefaultLook, TheStudioIsBrighterAboveHasHighlightsAndIsTheSameForEveryConversion) {
    // The gradient where no softbox is: 45 degrees up towards +X, straight down, the horizon
    // behind the model.
    const double s45 = std::sqrt(0.5);
    const double up[3] = {s45, s45, 0}, down[3] = {0, -1, 0}, horizon[3] = {0, 0, -1};
    EXPECT_FLOAT_EQ(studioRadiance(up), kStudioHorizon + (kStudioZenith - kStudioHorizon) * float(s45));
    EXPECT_FLOAT_EQ(studioRadiance(down), kStudioGround);
    EXPECT_FLOAT_EQ(studioRadiance(horizon), kStudioHorizon);
    EXPECT_GT(kStudioZenith, kStudioHorizon);
    EXPECT_GT(kStudioHorizon, kStudioGround);
    for (const StudioLight& l : kStudioLights) {
        const double el = l.elevationDegrees * kPi / 180, az = l.azimuthDegrees * kPi / 180;
        const double d[3] = {std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
        EXPECT_GT(studioRadiance(d), l.radiance) << "a softbox's centre: its radiance over the walls";
    }
    // Baked once: a second conversion writes the same ENVM and texels.
    auto a = convertScene(settings(kBoxTextured, "a.pnb"));
    auto b = convertScene(settings(kBoxTextured, "b.pnb"));
    ASSERT_TRUE(a.ok() && b.ok());
    std::ifstream fa(dir / "a.pnb", std::ios::binary), fb(dir / "b.pnb", std::ios::binary);
    std::vector<char> ba{std::istreambuf_iterator<char>(fa), {}}, bb{std::istreambuf_iterator<char>(fb), {}};
    EXPECT_EQ(ba, bb);
}

TEST_F(DefaultLook, TheFlagLeavesItOut) {
    // pnb-convert --no-default-environment (summary_json_test.cpp runs the command line).
    ConvertSettings s = settings(kBoxTextured, "none.pnb");
    s.defaultEnvironment = false;
    auto sum = convertScene(s);
    ASSERT_TRUE(sum.ok()) << sum.error().message;
    EXPECT_FALSE(sum->defaultEnvironment);
    EXPECT_FALSE(sum->environment.has_value());
    EXPECT_TRUE(sum->defaultSun);
    std::optional<Container> c;
    Scene scene = read(s.output, c);
    EXPECT_FALSE(scene.environment.has_value());
    EXPECT_EQ(std::count(sum->omitted.begin(), sum->omitted.end(),
                         "environment (no --environment or --sky): no sky light, IBL programs, "
                         "cube map or SH"),
              1);
}

TEST_F(DefaultLook, ASourceEnvironmentIsKept) {
    ConvertSettings s = settings(kBoxTextured, "sky.pnb");
    s.environment.sky = true;
    s.environment.skyWidth = 32;
    s.environment.specularSize = 8;
    s.environment.specularLevels = 2;
    s.environment.prefilterSamples = 8;
    s.environment.lutSize = 8;
    s.environment.lutSamples = 8;
    auto sum = convertScene(s);
    ASSERT_TRUE(sum.ok()) << sum.error().message;
    EXPECT_FALSE(sum->defaultEnvironment);
    ASSERT_TRUE(sum->environment.has_value());
    EXPECT_FALSE(sum->environment->generated);
    std::optional<Container> c;
    Scene scene = read(s.output, c);
    ASSERT_TRUE(scene.environment.has_value());
    EXPECT_EQ(scene.str(scene.environment->name), "preetham");
    EXPECT_EQ(scene.environment->source, EnvironmentSource::AnalyticSky);
    EXPECT_FALSE(scene.environment->generated);
}

TEST_F(DefaultLook, ASourceWithLightsKeepsItsOwnLook) {
    // The box room lights itself (a sun and a lamp): no environment is made up for it, so its
    // images and accuracy figures stay what they were.
    auto sum = convertScene(settings(writeScene("room", assets::buildBoxRoomGltf({})).string(), "room.pnb"));
    ASSERT_TRUE(sum.ok()) << sum.error().message;
    EXPECT_FALSE(sum->defaultEnvironment);
    EXPECT_FALSE(sum->environment.has_value());
    EXPECT_FALSE(sum->defaultSun);
    // Only a lamp, no sun: the default sun is added, the environment still not.
    assets::gltf::Document lampRoom = *assets::buildProceduralScene("lamp-room", {});
    auto lamp = convertScene(settings(writeScene("lamp", lampRoom).string(), "lamp.pnb"));
    ASSERT_TRUE(lamp.ok()) << lamp.error().message;
    EXPECT_TRUE(lamp->defaultSun);
    EXPECT_FALSE(lamp->defaultEnvironment);
}

// [SECTION] framing

// Every point of the sphere (centre c, radius r) seen from `eye` with `rotation` (looking down
// its -Z) through a perspective of vertical field `yfov` and `aspect` lands inside the NDC
// square shrunk by the margin: |x|, |y| <= 1 / margin. Returns the largest |x| or |y| seen.
double largestNdc(glm::dvec3 eye, glm::dquat rotation, glm::dvec3 c, double r, double yfov,
                  double aspect) {
    const glm::dmat3 toView = glm::mat3_cast(glm::conjugate(rotation));
    const double f = 1.0 / std::tan(yfov / 2);
    double worst = 0;
    // The silhouette: points of the sphere on the cone from the eye, in 720 directions around it.
    const glm::dvec3 axis = glm::normalize(c - eye);
    const double dist = glm::length(c - eye);
    const glm::dvec3 u = glm::normalize(glm::cross(axis, std::abs(axis.y) < 0.9 ? glm::dvec3(0, 1, 0)
                                                                                : glm::dvec3(1, 0, 0)));
    const glm::dvec3 v = glm::cross(axis, u);
    const double sinA = r / dist, cosA = std::sqrt(1 - sinA * sinA);
    for (int k = 0; k < 720; ++k) {
        const double t = k * kPi / 360;
        const glm::dvec3 ray = cosA * axis + sinA * (std::cos(t) * u + std::sin(t) * v);
        const glm::dvec3 p = toView * ray; // a direction to a silhouette point, in view space
        if (!(p.z < 0)) return 1e9;        // behind the camera: not framed at all
        worst = std::max({worst, std::abs(f / aspect * p.x / -p.z), std::abs(f * p.y / -p.z)});
    }
    return worst;
}

glm::dquat quat(const Vec4& q) { return glm::dquat(q.w, q.x, q.y, q.z); }

struct Shape {
    const char* name;
    Aabb bounds;
};

const Shape kShapes[] = {
    {"tall", {{-0.5f, 0, -0.5f}, {0.5f, 10, 0.5f}}},
    {"wide", {{-20, 0, -1}, {20, 1, 1}}},
    {"flat", {{-50, -0.01f, -50}, {50, 0.01f, 50}}},
    {"small, far from the origin", {{1000, 2000, -3000}, {1000.01f, 2000.02f, -2999.99f}}},
    {"a point", {{1, 2, 3}, {1, 2, 3}}},
};

TEST(DefaultFraming, EveryOrbitKeyKeepsTheSphereInsideTheFrameWithTheMargin) {
    for (const Shape& shape : kShapes) {
        SCOPED_TRACE(shape.name);
        const Framing f = frameBounds(shape.bounds);
        const glm::dvec3 c(f.center.x, f.center.y, f.center.z);
        const PathSpec path = defaultCameraPath(shape.bounds);
        ASSERT_EQ(path.keys.size(), 8u);
        // Keys are float positions: far from the origin they are rounded to the float grid
        // there (2^-24 of the coordinates), which a tiny object there sees.
        const double grid = 4 * std::ldexp(1.0, -24) *
                            std::max({1.0, std::abs(c.x), std::abs(c.y), std::abs(c.z)});
        const double slack = 1e-3 + 4 * grid / f.radius;
        for (const CameraKey& k : path.keys) {
            const glm::dvec3 eye(k.position.x, k.position.y, k.position.z);
            EXPECT_NEAR(glm::length(eye - c), f.distance, 1e-4 * f.distance + 2 * grid);
            for (double aspect : {16.0 / 9.0, 1.0}) {
                const double worst = largestNdc(eye, quat(k.rotation), c, f.radius, k.yfovRadians, aspect);
                EXPECT_LE(worst, 1.0 / kFramingMargin + slack) << "aspect " << aspect;
                // Not needlessly far either: the sphere fills the margin in the narrower direction.
                if (aspect == 1.0) {
                    EXPECT_GT(worst, 1.0 / kFramingMargin - 0.01 - slack);
                }
            }
            EXPECT_GT(f.znear, 0.0f);
            EXPECT_LT(f.znear, f.distance - f.radius) << "the whole sphere beyond the near plane";
            EXPECT_GT(f.zfar, f.distance + f.radius) << "and before the far plane";
        }
    }
}

TEST_F(DefaultLook, TheDefaultCameraFramesTallWideAndFlatObjects) {
    for (const char* shape : {"tall", "wide", "flat"}) {
        SCOPED_TRACE(shape);
        // One box, stretched.
        const std::string s(shape);
        assets::gltf::Document doc;
        doc.materials.emplace_back();
        pnb::test::addObject(doc, "box",
                             s == "tall"   ? pnb::test::box(1, 30, 1, 0)
                             : s == "wide" ? pnb::test::box(30, 1, 1, 0)
                                           : pnb::test::box(30, 0.01f, 30, 0),
                             {5, -2, 7});
        auto sum = convertScene(settings(writeScene(shape, doc).string(), "framed.pnb"));
        ASSERT_TRUE(sum.ok()) << sum.error().message;
        ASSERT_TRUE(sum->defaultCamera);
        std::optional<Container> keep;
        Scene scene = read((dir / "framed.pnb").string(), keep);
        ASSERT_EQ(scene.cameras.cameras.size(), 1u);
        const Camera& cam = scene.cameras.cameras[0];
        const Aabb& b = scene.info.bounds;
        const glm::dvec3 c = (glm::dvec3(b.min.x, b.min.y, b.min.z) + glm::dvec3(b.max.x, b.max.y, b.max.z)) * 0.5;
        const double r = glm::length(glm::dvec3(b.max.x, b.max.y, b.max.z) - c);
        std::vector<Matrix4d> world = nodeWorldMatrices(scene.nodes);
        bool found = false;
        for (size_t i = 0; i < scene.nodes.nodes.size(); ++i) {
            const Node& n = scene.nodes.nodes[i];
            if (n.camera != 0) continue;
            found = true;
            const glm::dvec3 eye(world[i][12], world[i][13], world[i][14]);
            const double worst = largestNdc(eye, quat(n.rotation), c, r, cam.yfovRadians, 16.0 / 9.0);
            EXPECT_LE(worst, 1.0 / kFramingMargin + 1e-3);
            EXPECT_GT(worst, 0.8 / kFramingMargin) << "framed, not lost in the distance";
            const double d = glm::length(eye - c);
            EXPECT_GT(cam.znear, 0.0f);
            EXPECT_LT(cam.znear, d - r);
            EXPECT_GT(cam.zfar, d + r);
            // Where the default orbit starts: opening the file shows the same view either way.
            ASSERT_FALSE(scene.cameraPaths.empty());
            const CameraKey& k0 = scene.cameraPaths[0].keys[0];
            EXPECT_NEAR(k0.position.x, eye.x, 1e-3 * d);
            EXPECT_NEAR(k0.position.y, eye.y, 1e-3 * d);
            EXPECT_NEAR(k0.position.z, eye.z, 1e-3 * d);
        }
        EXPECT_TRUE(found);
    }
}

} // namespace
