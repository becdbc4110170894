// pnb-flip end to end: images written here with OpenImageIO, the executable run as a user would,
// its figures and files checked; usage and input errors have their exit codes.
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace pnb::reference::test {

namespace {

namespace fs = std::filesystem;

struct RunResult {
    int exitCode = -1;
    std::string output;
};

RunResult runFlip(const std::string& args) {
    const std::string command = std::string("'") + PNB_FLIP_EXE + "' " + args + " 2>&1";
    RunResult r;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return r;
    char buffer[4096];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0)
        r.output.append(buffer, n);
    const int status = ::pclose(pipe);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

fs::path scratch(const std::string& name) {
    const fs::path dir =
        fs::temp_directory_path() / ("pnb_flip_cli_" + std::to_string(::getpid())) / name;
    fs::create_directories(dir);
    return dir;
}

template <class T>
void writeImage(const fs::path& path, int w, int h, OIIO::TypeDesc type,
                const std::vector<T>& rgb) {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(w, h, 3, type)));
    ASSERT_TRUE(out->write_image(type, rgb.data()));
    ASSERT_TRUE(out->close());
}

nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

} // namespace

TEST(FlipCli, PngPairGivesLdrFlipMapAndJson) {
    const fs::path dir = scratch("png");
    const int w = 64, h = 48;
    std::vector<uint8_t> a(size_t(w) * h * 3, 128), b = a;
    for (int x = 20; x < 40; ++x)
        b[size_t(24 * w + x) * 3 + 1] = 250; // a green line
    writeImage(dir / "a.png", w, h, OIIO::TypeDesc::UINT8, a);
    writeImage(dir / "b.png", w, h, OIIO::TypeDesc::UINT8, b);
    const RunResult r = runFlip((dir / "b.png").string() + " " + (dir / "a.png").string() +
                                " --out " + (dir / "o").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("LDR-FLIP of the sRGB display images"), std::string::npos) << r.output;
    const nlohmann::json j = readJson(dir / "o" / "flip.json");
    EXPECT_EQ(j["mode"], "ldr");
    EXPECT_GT(j["flip"]["mean"].get<double>(), 0.001);
    EXPECT_GT(j["flip"]["max"].get<double>(), 0.5);
    EXPECT_GT(j["relmse"]["mean"].get<double>(), 0.0);
    auto map = OIIO::ImageInput::open((dir / "o" / "flip.png").string());
    ASSERT_TRUE(map);
    EXPECT_EQ(map->spec().width, w);
    EXPECT_EQ(map->spec().nchannels, 3);

    const RunResult same = runFlip((dir / "a.png").string() + " " + (dir / "a.png").string() +
                                   " --out " + (dir / "s").string());
    ASSERT_EQ(same.exitCode, 0) << same.output;
    EXPECT_EQ(readJson(dir / "s" / "flip.json")["flip"]["mean"].get<double>(), 0.0);
}

TEST(FlipCli, ExrPairDefaultsToHdrAndLdrUsesThePlayersToneMap) {
    const fs::path dir = scratch("exr");
    const int w = 32, h = 32;
    std::vector<float> ref(size_t(w) * h * 3), test(ref.size());
    for (size_t i = 0; i < ref.size(); ++i) {
        ref[i] = 0.05f + 0.1f * float(i % 37);
        test[i] = 2.0f * ref[i];
    }
    writeImage(dir / "ref.exr", w, h, OIIO::TypeDesc::FLOAT, ref);
    writeImage(dir / "test.exr", w, h, OIIO::TypeDesc::FLOAT, test);
    const std::string pair = (dir / "test.exr").string() + " " + (dir / "ref.exr").string();
    const RunResult hdr = runFlip(pair + " --out " + (dir / "h").string());
    ASSERT_EQ(hdr.exitCode, 0) << hdr.output;
    const nlohmann::json jh = readJson(dir / "h" / "flip.json");
    EXPECT_EQ(jh["mode"], "hdr");
    EXPECT_GE(jh["exposures"]["count"].get<int>(), 2);
    EXPECT_GT(jh["flip"]["mean"].get<double>(), 0.02);
    EXPECT_NEAR(jh["relmse"]["mean"].get<double>(), 1.0,
                0.05); // (2r - r)^2 / (r^2 + eps), r mostly >> 0.1
    EXPECT_TRUE(fs::exists(dir / "h" / "flip_exposure.png"));

    // Burnt to white by a huge exposure, the displayed frames agree.
    const RunResult ldr = runFlip(pair + " --ldr --exposure 1e6 --out " + (dir / "l").string());
    ASSERT_EQ(ldr.exitCode, 0) << ldr.output;
    const nlohmann::json jl = readJson(dir / "l" / "flip.json");
    EXPECT_EQ(jl["mode"], "ldr");
    EXPECT_EQ(jl["exposure"].get<double>(), 1e6);
    EXPECT_LT(jl["flip"]["mean"].get<double>(), 1e-3);
}

TEST(FlipCli, UsageAndInputErrors) {
    const fs::path dir = scratch("errors");
    writeImage(dir / "a.png", 8, 8, OIIO::TypeDesc::UINT8, std::vector<uint8_t>(8 * 8 * 3, 9));
    writeImage(dir / "b.png", 9, 8, OIIO::TypeDesc::UINT8, std::vector<uint8_t>(9 * 8 * 3, 9));
    EXPECT_EQ(runFlip("").exitCode, 1);
    EXPECT_EQ(runFlip((dir / "a.png").string()).exitCode, 1);
    EXPECT_EQ(runFlip("--bogus").exitCode, 1);
    EXPECT_EQ(
        runFlip((dir / "a.png").string() + " " + (dir / "a.png").string() + " --ppd -3").exitCode,
        1);
    const RunResult size = runFlip((dir / "a.png").string() + " " + (dir / "b.png").string() +
                                   " --out " + dir.string());
    EXPECT_EQ(size.exitCode, 2);
    EXPECT_NE(size.output.find("9x8"), std::string::npos) << size.output;
    const RunResult missing = runFlip((dir / "none.png").string() + " " + (dir / "a.png").string());
    EXPECT_EQ(missing.exitCode, 2);
    EXPECT_NE(missing.output.find("none.png"), std::string::npos) << missing.output;
    const RunResult help = runFlip("--help");
    EXPECT_EQ(help.exitCode, 0);
    EXPECT_NE(help.output.find("usage: pnb-flip TEST REFERENCE"), std::string::npos);
}

} // namespace pnb::reference::test
