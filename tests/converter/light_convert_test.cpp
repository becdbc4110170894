// Lights as pnb-convert writes them (docs/CONVERTER.md "Lights"): computed ranges and their
// warnings, --light-cutoff, invalid ranges and cones repaired by name, shadow-casting lamps, and
// the kMaxLights cap on a source with 100 000 lights. The glTF inputs are written here.

#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <deque>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "child_process.h"
#include "pnb/light_range.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_converter/convert.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;

// One triangle (three float3 positions) as a base64 data URI, so a scene is one .gltf file.
std::string triangleBufferUri() {
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const auto* bytes = reinterpret_cast<const unsigned char*>(p);
    const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out = "data:application/octet-stream;base64,";
    for (size_t i = 0; i < sizeof(p); i += 3) { // 36 bytes: no padding
        const unsigned v = unsigned(bytes[i]) << 16 | unsigned(bytes[i + 1]) << 8 | bytes[i + 2];
        for (int k = 3; k >= 0; --k) out += abc[(v >> (6 * k)) & 63];
    }
    return out;
}

// A glTF with one triangle and one node per light, `lights` being the KHR_lights_punctual light
// objects as JSON (without the brackets of the array).
std::string gltfWithLights(const std::vector<std::string>& lights) {
    std::string json = R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_lights_punctual"],)"
                       R"("buffers":[{"byteLength":36,"uri":")" +
                       triangleBufferUri() +
                       R"("}],"bufferViews":[{"buffer":0,"byteLength":36}],)"
                       R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",)"
                       R"("min":[0,0,0],"max":[1,1,0]}],)"
                       R"("meshes":[{"name":"Tri","primitives":[{"attributes":{"POSITION":0}}]}],)"
                       R"("extensions":{"KHR_lights_punctual":{"lights":[)";
    for (size_t i = 0; i < lights.size(); ++i) json += (i ? "," : "") + lights[i];
    json += R"(]}},"nodes":[{"mesh":0})";
    for (size_t i = 0; i < lights.size(); ++i)
        json += R"(,{"name":"n)" + std::to_string(i) + R"(","translation":[0,2,)" +
                std::to_string(i % 100) + R"(],"extensions":{"KHR_lights_punctual":{"light":)" +
                std::to_string(i) + "}}}";
    json += R"(],"scenes":[{"nodes":[)";
    for (size_t i = 0; i <= lights.size(); ++i) json += (i ? "," : "") + std::to_string(i);
    return json + "]}],\"scene\":0}";
}

std::string light(const std::string& name, const std::string& type, const std::string& rest = "") {
    return R"({"name":")" + name + R"(","type":")" + type + "\"" + (rest.empty() ? "" : "," + rest) +
           "}";
}

class LightConvert : public ::testing::Test {
protected:
    fs::path dir;
    std::deque<Container> containers;
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_lights_" + std::string(info->name()) + "_" + std::to_string(getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    std::string writeGltf(const std::string& name, const std::vector<std::string>& lights) {
        const fs::path p = dir / (name + ".gltf");
        std::ofstream(p, std::ios::binary) << gltfWithLights(lights);
        return p.string();
    }

    ConvertSettings settings(const std::string& in) {
        ConvertSettings s;
        s.input = in;
        s.output = (dir / "out.pnb").string();
        s.validateShaders = false; // the shaders are not what these tests look at
        return s;
    }

    // Converts and reads the container back (the reader's validation included). The container
    // stays open with the fixture: the scene's strings may be views of its mapping.
    Scene convertAndRead(const ConvertSettings& s, ConvertSummary* summary = nullptr) {
        auto r = convertScene(s);
        EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
        if (!r.ok()) return {};
        if (summary) *summary = *r;
        auto c = Container::open(s.output);
        EXPECT_TRUE(c.ok());
        if (!c.ok()) return {};
        containers.push_back(std::move(*c));
        auto scene = readScene(containers.back());
        EXPECT_TRUE(scene.ok()) << scene.error().describe();
        return scene.ok() ? std::move(*scene) : Scene{};
    }

    static const Light* named(const Scene& scene, const std::string& name) {
        for (const Light& l : scene.lights.lights)
            if (scene.str(l.name) == name) return &l;
        return nullptr;
    }

    static std::vector<std::string> warningsWith(const ConvertSummary& s, const std::string& text) {
        std::vector<std::string> out;
        for (const std::string& w : s.warnings)
            if (w.find(text) != std::string::npos) out.push_back(w);
        return out;
    }
    static std::string all(const ConvertSummary& s) {
        std::string out;
        for (const std::string& w : s.warnings) out += w + "\n";
        return out;
    }
};

TEST_F(LightConvert, APointLightWithoutRangeGetsTheCutoffRangeAndAWarningNamingIt) {
    const std::string in = writeGltf(
        "lamp", {light("sun", "directional", R"("intensity":3)"),
                 light("lamp", "point", R"("intensity":100,"color":[1,0.5,0.25])"),
                 light("ranged", "point", R"("intensity":100,"range":4)")});
    ConvertSummary sum;
    const Scene scene = convertAndRead(settings(in), &sum);
    const Light* lamp = named(scene, "lamp");
    ASSERT_NE(lamp, nullptr);
    EXPECT_FLOAT_EQ(lamp->range, lightCutoffRange(*lamp, kDefaultLightCutoffLux));
    EXPECT_FLOAT_EQ(lamp->range, 100.0f) << "sqrt(100 cd x 1 / 0.01 lux)";
    EXPECT_TRUE(lamp->castsShadows) << "a lamp casts shadows; the player picks which it draws";
    auto w = warningsWith(sum, "light 'lamp'");
    ASSERT_EQ(w.size(), 1u) << all(sum);
    EXPECT_NE(w[0].find("no range in the source; computed 100"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("0.01 lux"), std::string::npos) << w[0];

    const Light* ranged = named(scene, "ranged");
    ASSERT_NE(ranged, nullptr);
    EXPECT_EQ(ranged->range, 4.0f) << "the source's own range is kept";
    EXPECT_TRUE(warningsWith(sum, "light 'ranged'").empty()) << all(sum);
    const Light* sun = named(scene, "sun");
    ASSERT_NE(sun, nullptr);
    EXPECT_EQ(sun->range, 0.0f);
    EXPECT_TRUE(sun->castsShadows);
}

TEST_F(LightConvert, TheCutoffChangesTheRangeAndABadOneIsAUsageError) {
    const std::string in =
        writeGltf("cutoff", {light("lamp", "point", R"("intensity":100)")});
    ConvertSettings s = settings(in);
    s.lights.cutoffLux = 1.0f;
    ConvertSummary sum;
    const Scene scene = convertAndRead(s, &sum);
    const Light* lamp = named(scene, "lamp");
    ASSERT_NE(lamp, nullptr);
    EXPECT_FLOAT_EQ(lamp->range, 10.0f) << "sqrt(100 / 1)";
    EXPECT_EQ(warningsWith(sum, "falls to 1 lux").size(), 1u) << all(sum);
    s.lights.cutoffLux = 0;
    auto refused = convertScene(s);
    ASSERT_FALSE(refused.ok()) << "the API refuses what the command line refuses";
    EXPECT_NE(refused.error().message.find("cut-off"), std::string::npos) << refused.error().message;

    // The command line: --light-cutoff 4 gives sqrt(100 / 4) = 5; a bad value exits 1.
    const std::string log = (dir / "log.txt").string(), out = (dir / "cli.pnb").string();
    auto run = [&](std::vector<std::string> args) {
        args.insert(args.begin(), {PNB_CONVERT_EXE, in, "-o", out, "--no-validate-shaders"});
        return pnb::test::runChild(args, log);
    };
    auto ok = run({"--light-cutoff", "4"});
    ASSERT_EQ(ok.exitCode, 0) << ok.output;
    EXPECT_NE(ok.output.find("light 'lamp': no range in the source; computed 5,"), std::string::npos)
        << ok.output;
    {
        auto c = Container::open(out);
        ASSERT_TRUE(c.ok());
        auto scene4 = readScene(*c);
        ASSERT_TRUE(scene4.ok());
        const Light* l = named(*scene4, "lamp");
        ASSERT_NE(l, nullptr);
        EXPECT_FLOAT_EQ(l->range, 5.0f);
    }
    for (const char* bad : {"0", "-1", "nan", "inf", "1e-50", "1e39", "lots", ""}) {
        auto r = run({"--light-cutoff", bad});
        EXPECT_EQ(r.exitCode, 1) << "'" << bad << "': " << r.output;
        EXPECT_NE(r.output.find("invalid value '" + std::string(bad) + "' for --light-cutoff"),
                  std::string::npos)
            << r.output;
    }
}

TEST_F(LightConvert, InvalidRangesAreReplacedByTheComputedOneAndWarnedByName) {
    const std::string in = writeGltf(
        "neg", {light("neg", "point", R"("intensity":100,"range":-5)"),
                light("huge", "spot", R"("intensity":400,"range":1e39,"spot":{})"),
                light("dir", "directional", R"("range":7)")});
    ConvertSummary sum;
    const Scene scene = convertAndRead(settings(in), &sum);
    const Light* neg = named(scene, "neg");
    const Light* huge = named(scene, "huge");
    ASSERT_TRUE(neg && huge);
    EXPECT_FLOAT_EQ(neg->range, 100.0f);
    EXPECT_FLOAT_EQ(huge->range, 200.0f) << "1e39 is infinite as a float";
    EXPECT_EQ(warningsWith(sum, "light 'neg': range -5 is not a positive finite number; replaced by 100").size(),
              1u)
        << all(sum);
    EXPECT_EQ(warningsWith(sum, "light 'huge': range inf is not a positive finite number; replaced by 200").size(),
              1u)
        << all(sum);
    const Light* directional = named(scene, "dir");
    ASSERT_NE(directional, nullptr);
    EXPECT_EQ(directional->range, 0.0f) << "a range means nothing for a directional light";
}

TEST_F(LightConvert, SpotConesOutsideTheirDomainAreClampedAndWarned) {
    const std::string in = writeGltf(
        "cones",
        {light("wide", "spot", R"("spot":{"innerConeAngle":0.2,"outerConeAngle":2.0})"),
         light("crossed", "spot", R"("spot":{"innerConeAngle":0.8,"outerConeAngle":0.5})"),
         light("negative", "spot", R"("spot":{"innerConeAngle":-0.2,"outerConeAngle":0.5})"),
         light("half-pi", "spot",
               R"("spot":{"innerConeAngle":1.5707963267948966,"outerConeAngle":1.5707963267948966})")});
    ConvertSummary sum;
    const Scene scene = convertAndRead(settings(in), &sum);
    const Light* wide = named(scene, "wide");
    const Light* crossed = named(scene, "crossed");
    const Light* negative = named(scene, "negative");
    const Light* halfPi = named(scene, "half-pi");
    ASSERT_TRUE(wide && crossed && negative && halfPi);
    EXPECT_EQ(wide->outerConeRadians, kMaxSpotConeRadians);
    EXPECT_FLOAT_EQ(wide->innerConeRadians, 0.2f);
    EXPECT_FLOAT_EQ(crossed->outerConeRadians, 0.5f);
    EXPECT_FLOAT_EQ(crossed->innerConeRadians, 0.5f);
    EXPECT_EQ(negative->innerConeRadians, 0.0f);
    EXPECT_FLOAT_EQ(negative->outerConeRadians, 0.5f);
    for (const char* name : {"wide", "crossed", "negative"}) {
        auto w = warningsWith(sum, std::string("light '") + name + "': spot cone angles");
        EXPECT_EQ(w.size(), 1u) << name << "\n" << all(sum);
        if (!w.empty()) {
            EXPECT_NE(w[0].find("clamped to inner"), std::string::npos) << w[0];
        }
    }
    EXPECT_TRUE(warningsWith(sum, "light 'half-pi': spot").empty()) << "exactly pi/2 is allowed\n"
                                                                    << all(sum);
    EXPECT_FLOAT_EQ(halfPi->outerConeRadians, float(M_PI / 2));
}

TEST_F(LightConvert, ALightBrighterThanTheReaderAllowsIsLoweredToTheBoundAndWarned) {
    // Finite in the source but beyond kMaxLightOutput: intensity x colour overflowed the
    // renderer's sums (FLT_MAX x FLT_MAX filled the frame with NaN).
    const std::string in = writeGltf(
        "bright", {light("blinding", "point", R"("intensity":3e38,"color":[1,0.5,0.25],"range":5)"),
                   light("ok", "point", R"("intensity":1e9,"range":5)")});
    ConvertSummary sum;
    const Scene scene = convertAndRead(settings(in), &sum);
    const Light* blinding = named(scene, "blinding");
    const Light* ok = named(scene, "ok");
    ASSERT_TRUE(blinding && ok);
    EXPECT_FLOAT_EQ(blinding->intensity, kMaxLightOutput);
    EXPECT_FLOAT_EQ(blinding->color.y, 0.5f) << "the colour is kept";
    EXPECT_FLOAT_EQ(ok->intensity, 1e9f);
    auto w = warningsWith(sum, "light 'blinding': intensity 3e+38 x brightest colour channel 1 "
                               "exceeds 1e+10");
    EXPECT_EQ(w.size(), 1u) << all(sum);
    EXPECT_TRUE(warningsWith(sum, "light 'ok'").empty()) << all(sum);
}

TEST_F(LightConvert, ALightThatGivesNoLightKeepsRangeZeroAndCastsNoShadow) {
    const std::string in = writeGltf(
        "dark", {light("off", "point", R"("intensity":0)"),
                 light("black", "spot", R"("intensity":5,"color":[0,0,0],"range":3,"spot":{})")});
    ConvertSummary sum;
    const Scene scene = convertAndRead(settings(in), &sum);
    for (const char* name : {"off", "black"}) {
        const Light* l = named(scene, name);
        ASSERT_NE(l, nullptr) << name;
        EXPECT_EQ(l->range, 0.0f) << name;
        EXPECT_FALSE(l->castsShadows) << name;
        EXPECT_EQ(effectiveLightRange(*l), 0.0f) << name << ": renderers skip it";
        EXPECT_EQ(warningsWith(sum, std::string("light '") + name + "': gives no light").size(), 1u)
            << all(sum);
    }
}

TEST_F(LightConvert, ManyLightsWithoutRangeGetOneSummaryLine) {
    // 8 lights: one line each. 1024: one line with the count, the range span and a few names.
    std::vector<std::string> few, many;
    for (int i = 0; i < 1024; ++i) {
        const std::string l =
            light("lamp-" + std::to_string(i), "point", "\"intensity\":" + std::to_string(1 + i));
        if (i < 8) few.push_back(l);
        many.push_back(l);
    }
    ConvertSummary sum;
    convertAndRead(settings(writeGltf("few", few)), &sum);
    EXPECT_EQ(warningsWith(sum, "no range in the source").size(), 8u) << all(sum);

    const Scene scene = convertAndRead(settings(writeGltf("many", many)), &sum);
    auto w = warningsWith(sum, "no range in the source");
    ASSERT_EQ(w.size(), 1u) << all(sum);
    // sqrt(1 / 0.01) = 10 for lamp-0, sqrt(1024 / 0.01) = 320 for lamp-1023.
    EXPECT_NE(w[0].find("lights: 1024 point/spot lights have no range in the source"), std::string::npos)
        << w[0];
    EXPECT_NE(w[0].find(": 10 (light 'lamp-0') to 320 (light 'lamp-1023')"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("the first: light 'lamp-0', light 'lamp-1', light 'lamp-2'"), std::string::npos)
        << w[0];
    EXPECT_LT(sum.warnings.size(), 5u) << all(sum);
    size_t withRange = 0;
    for (const Light& l : scene.lights.lights)
        withRange += l.type == LightType::Point && l.range > 0 && l.castsShadows;
    EXPECT_EQ(withRange, 1024u);
}

TEST_F(LightConvert, AHundredThousandLightsKeepTheKMaxLightsThatLightTheMost) {
    // Intensity grows with the index, so the lights that light the most are the last 65535,
    // beside the sun (directional lights are kept first).
    constexpr int kLights = 100000;
    std::vector<std::string> lights{light("sun", "directional", R"("intensity":2)")};
    lights.reserve(kLights + 1);
    for (int i = 0; i < kLights; ++i)
        lights.push_back(light("l" + std::to_string(i), "point",
                               "\"intensity\":" + std::to_string(1 + i)));
    const std::string in = writeGltf("many", lights);
    const auto start = std::chrono::steady_clock::now();
    ConvertSummary sum;
    const Scene scene = convertAndRead(settings(in), &sum);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    RecordProperty("convert_and_read_seconds", std::to_string(seconds));
    std::printf("100 000 lights: converted and read back in %.2f s\n", seconds);
    for (const StageTiming& t : sum.stages) std::printf("  %s %.3f s\n", t.stage.c_str(), t.seconds);
    // A guard against quadratic work (100 000^2 would take minutes), not a benchmark.
    EXPECT_LT(seconds, 60.0);

    ASSERT_EQ(scene.lights.lights.size(), kMaxLights);
    EXPECT_EQ(sum.lights, size_t(kMaxLights));
    ASSERT_NE(named(scene, "sun"), nullptr);
    const uint32_t firstKept = kLights - (kMaxLights - 1); // l34465
    EXPECT_EQ(named(scene, "l" + std::to_string(firstKept - 1)), nullptr);
    EXPECT_NE(named(scene, "l" + std::to_string(firstKept)), nullptr);
    EXPECT_NE(named(scene, "l99999"), nullptr);
    // In source order, and every node points at its own light or, when it was dropped, none.
    EXPECT_EQ(scene.str(scene.lights.lights[1].name), "l" + std::to_string(firstKept));
    size_t placed = 0;
    for (const Node& n : scene.nodes.nodes) {
        if (n.light == kNone) continue;
        ++placed;
        const std::string nodeName(scene.str(n.name));
        const std::string lightName(scene.str(scene.lights.lights[n.light].name));
        // Node "n<j>" places source light j: "sun" is light 0, "l<k>" light k + 1.
        const int sourceLight = lightName == "sun" ? 0 : std::stoi(lightName.substr(1)) + 1;
        EXPECT_EQ(nodeName, "n" + std::to_string(sourceLight)) << lightName;
        if (::testing::Test::HasFailure()) break;
    }
    EXPECT_EQ(placed, size_t(kMaxLights));
    auto w = warningsWith(sum, "more than a container holds");
    ASSERT_EQ(w.size(), 1u) << all(sum).substr(0, 2000);
    EXPECT_NE(w[0].find("lights: 100001 lights"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("dropped 34465"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("the first dropped: light 'l0', light 'l1', light 'l2'"), std::string::npos) << w[0];
    EXPECT_LT(sum.warnings.size(), 6u) << "one line per kind of finding, not per light";
}

} // namespace
