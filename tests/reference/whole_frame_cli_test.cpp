// pnb-reference --whole-frame end to end: frame.json alone (the camera pnb-play records) gives
// the path-traced HDR image, its standard error, the tone-mapped PNG and metrics.json's
// "whole_frame" (added beside what the file held); a frame.json without the camera's axes is
// exit code 2 naming the key; bad option values are usage errors.
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "reference_test_util.h"

namespace pnb::reference::test {
namespace {

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

// The camera at (0, 10, 10) looking at the origin (down 45 degrees), +Y up: view +X = world +X,
// view +Z = (0, 1, 1) / sqrt 2, view +Y = Z x X.
void writeFrameJson(const fs::path& dir, bool withAxes) {
    fs::create_directories(dir);
    const double s = std::sqrt(0.5);
    nlohmann::json j = {{"camera_position", {0, 10, 10}}, {"toward_light", {0.3, 1, 0.2}}, {"width", 32},
                        {"height", 24}, {"projection", "perspective"}, {"yfov", 0.9}, {"aspect", 32.0 / 24.0},
                        {"exposure", 0.5}};
    if (withAxes) j["camera_world_from_view"] = {{1, 0, 0}, {0, s, -s}, {0, s, s}};
    std::ofstream(dir / "frame.json") << j.dump(2);
}

std::vector<float> readImage(const fs::path& path, int& width, int& height, int& channels) {
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << path << ": " << OIIO::geterror();
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    width = spec.width, height = spec.height, channels = spec.nchannels;
    std::vector<float> pixels(size_t(width) * size_t(height) * size_t(channels));
    EXPECT_TRUE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data()));
    return pixels;
}

TEST(WholeFrameCli, TracesTheFrameFromFrameJsonAlone) {
    TempDir dir("whole-frame");
    const std::string scene = pnb::test::convertDocument(dir.str(), groundAndBox(), "ground-box", "", false);
    writeFrameJson(dir.path / "in", true);
    // An earlier run's metrics stay.
    fs::create_directories(dir.path / "out");
    std::ofstream(dir.path / "out" / "metrics.json") << R"({"shadow": {"pixels": 7}})";
    const RunResult r = run(quote(scene) + " --frame " + quote(dir.path / "in") + " --out " + quote(dir.path / "out") +
                            " --whole-frame --spp 8 --bounces 3 --seed 5");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("8 samples/pixel"), std::string::npos) << r.output;

    int w = 0, h = 0, c = 0;
    const std::vector<float> hdr = readImage(dir.path / "out" / "whole_frame.exr", w, h, c);
    ASSERT_EQ(w, 32);
    ASSERT_EQ(h, 24);
    ASSERT_EQ(c, 3);
    size_t lit = 0;
    for (float v : hdr) {
        ASSERT_TRUE(std::isfinite(v));
        ASSERT_GE(v, 0.0f);
        lit += v > 0.0f;
    }
    EXPECT_GT(lit, hdr.size() / 2); // the ground and the box fill most of the view, and they are lit
    const std::vector<float> se = readImage(dir.path / "out" / "whole_frame_stderr.exr", w, h, c);
    EXPECT_EQ(se.size(), hdr.size());
    readImage(dir.path / "out" / "whole_frame.png", w, h, c);
    EXPECT_EQ(w, 32);
    EXPECT_EQ(c, 3);

    std::ifstream in(dir.path / "out" / "metrics.json");
    const nlohmann::json m = nlohmann::json::parse(in, nullptr, false);
    ASSERT_FALSE(m.is_discarded());
    EXPECT_EQ(m["shadow"]["pixels"], 7);
    const nlohmann::json& f = m["whole_frame"];
    EXPECT_EQ(f["samples"], 8);
    EXPECT_EQ(f["bounces"], 3);
    EXPECT_EQ(f["seed"], 5);
    EXPECT_EQ(f["exposure"], 0.5);
    EXPECT_EQ(f["non_finite_samples"], 0);
    EXPECT_GT(f["relative_noise"].get<double>(), 0.0);
    EXPECT_GT(f["rays_per_second"].get<double>(), 0.0);

    // Deterministic: the same seed, the same image.
    const RunResult again = run(quote(scene) + " --frame " + quote(dir.path / "in") + " --out " +
                                quote(dir.path / "again") + " --whole-frame --spp 8 --bounces 3 --seed 5 -q");
    ASSERT_EQ(again.exitCode, 0) << again.output;
    EXPECT_EQ(readImage(dir.path / "again" / "whole_frame.exr", w, h, c), hdr);
}

TEST(WholeFrameCli, AFrameWithoutTheCameraOrBadValuesAreErrors) {
    TempDir dir("whole-frame-bad");
    const std::string scene = pnb::test::convertDocument(dir.str(), groundAndBox(), "ground-box", "", false);
    writeFrameJson(dir.path / "in", false);
    RunResult r = run(quote(scene) + " --frame " + quote(dir.path / "in") + " --whole-frame --spp 1");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("camera_world_from_view"), std::string::npos) << r.output;
    for (const char* bad : {"--bounces -1", "--spp 0", "--noise-target x", "--time-limit -3"}) {
        r = run(quote(scene) + " --frame " + quote(dir.path / "in") + " --whole-frame " + bad);
        EXPECT_EQ(r.exitCode, 1) << bad << ": " << r.output;
    }
}

} // namespace
} // namespace pnb::reference::test
