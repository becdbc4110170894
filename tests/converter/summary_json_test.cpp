// pnb-convert --summary-json, run as a process: the JSON carries what the printed summary says
// (sizes, quantisation error, worst texture PSNR), null where an option was off, and it is
// refused where it would name one file for several outputs.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "child_process.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using pnb::test::runChild;

const std::string kBox = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
// Curved and textured (4 JPEG textures): quantisation and block compression both cost something.
const std::string kSpider = "/usr/share/assimp/models/OBJ/spider.obj";

class SummaryJson : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_summary_" + std::string(info->name()) + "_" + std::to_string(getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    pnb::test::ChildResult convert(std::vector<std::string> args) {
        args.insert(args.begin(), PNB_CONVERT_EXE);
        return runChild(args, (dir / "child-output.txt").string());
    }
    static json read(const fs::path& p) {
        std::ifstream f(p);
        return json::parse(f);
    }
};

TEST_F(SummaryJson, CarriesThePrintedErrorsAndSizes) {
    const fs::path out = dir / "spider.pnb", summary = dir / "spider.json";
    // --no-default-environment: the spider has no lights, and the default environment's three
    // textures would count beside its four (DefaultLook tests count those).
    auto r = convert({kSpider, "-o", out.string(), "--quantize", "--compress-textures",
                      "--no-default-environment", "--summary-json", summary.string()});
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const json j = read(summary);
    EXPECT_EQ(j["output_bytes"].get<uint64_t>(), fs::file_size(out));
    EXPECT_GT(j["mesh_bytes"].get<uint64_t>(), 0u);
    EXPECT_GT(j["texture_bytes"].get<uint64_t>(), 0u);
    EXPECT_EQ(j["counts"]["textures"].get<int>(), 4);
    EXPECT_TRUE(j["quantized"].get<bool>());
    // 16-bit positions: off by a fraction of a percent of the spider's size, never exact.
    const double pos = j["max_position_error"].get<double>();
    EXPECT_GT(pos, 0.0);
    EXPECT_LT(pos, 0.01);
    EXPECT_GE(j["max_normal_error_deg"].get<double>(), 0.0);
    const double psnr = j["min_texture_psnr_db"].get<double>();
    EXPECT_GT(psnr, 20.0);
    EXPECT_LT(psnr, 80.0);
    // The same figures as the printed summary (which rounds to 3 significant digits / 0.1 dB).
    char text[64];
    std::snprintf(text, sizeof(text), "max position error %.3g units", pos);
    EXPECT_NE(r.output.find(text), std::string::npos) << text << "\n" << r.output;
    std::snprintf(text, sizeof(text), "worst PSNR %.1f dB", psnr);
    EXPECT_NE(r.output.find(text), std::string::npos) << text << "\n" << r.output;
    EXPECT_GT(j["seconds"].get<double>(), 0.0);
    EXPECT_FALSE(fs::exists(dir / "spider.json.tmp"));
}

TEST_F(SummaryJson, OptionsOffAreNullNotZero) {
    const fs::path summary = dir / "plain.json";
    auto r = convert({kBox, "-o", (dir / "plain.pnb").string(), "-q", "--summary-json",
                      summary.string()});
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output, "") << "-q prints errors only; the JSON is still written";
    const json j = read(summary);
    EXPECT_FALSE(j["quantized"].get<bool>());
    EXPECT_TRUE(j["max_position_error"].is_null());
    EXPECT_TRUE(j["min_texture_psnr_db"].is_null());
    EXPECT_TRUE(j["lod_errors"].empty());
}

// What the converter adds to a source that lacks it is one summary line (and the JSON's
// "added"), not a warning per file; --no-default-environment leaves the environment out.
TEST_F(SummaryJson, AdditionsAreOneSummaryLineNotWarnings) {
    const fs::path summary = dir / "box.json";
    auto r = convert({kBox, "-o", (dir / "box.pnb").string(), "--summary-json", summary.string()});
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("  added: default sun, default environment, default camera, default "
                            "orbit (flagged generated; --no-default-environment leaves the "
                            "environment out; --path gives your own camera path)\n"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("Warning: "), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("default-sun"), std::string::npos) << "the old warning" << r.output;
    const json j = read(summary);
    EXPECT_EQ(j["added"], json({"default sun", "default environment", "default camera", "default orbit"}));
    EXPECT_TRUE(j["warnings"].empty()) << j["warnings"];
    ASSERT_TRUE(j.contains("environment"));
    EXPECT_EQ(j["environment"]["name"], "default-studio");
    EXPECT_TRUE(j["environment"]["generated"].get<bool>());

    const fs::path without = dir / "none.json";
    auto n = convert({kBox, "-o", (dir / "none.pnb").string(), "--no-default-environment",
                      "--summary-json", without.string()});
    ASSERT_EQ(n.exitCode, 0) << n.output;
    EXPECT_NE(n.output.find("  added: default sun, default camera, default orbit (flagged "
                            "generated; --path gives your own camera path)\n"),
              std::string::npos)
        << n.output;
    const json k = read(without);
    EXPECT_EQ(k["added"], json({"default sun", "default camera", "default orbit"}));
    EXPECT_FALSE(k.contains("environment"));

    // A batch: one line for all its inputs at the end, none per file.
    auto b = convert({kBox, kSpider, "-o", (dir / "many").string()});
    ASSERT_EQ(b.exitCode, 0) << b.output;
    EXPECT_EQ(b.output.find("Warning: "), std::string::npos) << b.output;
    EXPECT_NE(b.output.find("batch: added default sun to 2, default environment to 2, default "
                            "camera to 2, default orbit to 2 (flagged generated"),
              std::string::npos)
        << b.output;
}

TEST_F(SummaryJson, RefusedForSeveralInputsAndNamedWhenUnwritable) {
    auto batch = convert({kBox, kBox, "-o", (dir / "many").string(), "--summary-json",
                          (dir / "s.json").string()});
    EXPECT_EQ(batch.exitCode, 1) << batch.output;
    EXPECT_NE(batch.output.find("--summary-json"), std::string::npos) << batch.output;

    const std::string bad = (dir / "no-such-dir" / "s.json").string();
    auto r = convert({kBox, "-o", (dir / "box.pnb").string(), "-q", "--summary-json", bad});
    EXPECT_EQ(r.exitCode, 4) << r.output;
    EXPECT_NE(r.output.find(bad), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(dir / "box.pnb")) << "the container is written before the summary";
}

} // namespace
