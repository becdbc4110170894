// The texture stage's memory budget (converter/src/memory_budget.cpp, texture_processing.cpp,
// image_decode.cpp): an image is refused from its header when processing it would need more than
// its share of --max-memory, and an image whose header lies about its size fails before any big
// buffer is committed. In-process through processTextures, and as pnb-convert processes whose
// time and peak memory are measured.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "child_process.h"
#include "crafted_png.h"
#include "pnb_assets/png_writer.h"
#include "pnb_converter/memory_budget.h"
#include "pnb_converter/texture_processing.h"

#include "oiio_leak_guard.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;

constexpr uint32_t kHuge = 16384;
// What the 70-byte PNG may cost a failing conversion at most: pnb-convert itself needs about
// 140 MiB (shader compiler, scene); the bug committed 4.3 GB.
constexpr uint64_t kSmallRss = test::kAddressSanitizer ? (1024ull << 20) : (512ull << 20);

class ImageBudget : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_image_budget_" + std::to_string(getpid()) + "_" + info->name());
        fs::create_directories(dir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }

    fs::path writeBytes(const std::string& name, const std::vector<uint8_t>& bytes) {
        const fs::path p = dir / name;
        std::ofstream(p, std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        return p;
    }

    // A 256 x 256 RGB gradient: an ordinary texture.
    fs::path writeNormalPng(const std::string& name) {
        std::vector<uint8_t> pixels;
        for (uint32_t y = 0; y < 256; ++y)
            for (uint32_t x = 0; x < 256; ++x)
                pixels.insert(pixels.end(), {uint8_t(x), uint8_t(y), 90});
        return writeBytes(name, assets::encodePng(256, 256, 3, pixels));
    }

    // One textured triangle whose base colour image is `image` (a file next to the .gltf).
    fs::path writeScene(const std::string& name, const std::string& image) {
        std::vector<float> data = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1};
        std::vector<uint8_t> bytes(data.size() * sizeof(float));
        std::memcpy(bytes.data(), data.data(), bytes.size());
        writeBytes(name + ".bin", bytes);
        const fs::path p = dir / (name + ".gltf");
        std::ofstream(p) << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
                         << R"("nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":)"
                         << R"({"POSITION":0,"TEXCOORD_0":1},"material":0}]}],)"
                         << R"("materials":[{"pbrMetallicRoughness":{"baseColorTexture":)"
                         << R"({"index":0}}}],"textures":[{"source":0}],)"
                         << R"("images":[{"uri":")" << image << R"("}],)"
                         << R"("buffers":[{"byteLength":60,"uri":")" << name << R"(.bin"}],)"
                         << R"("bufferViews":[{"buffer":0,"byteLength":36},)"
                         << R"({"buffer":0,"byteOffset":36,"byteLength":24}],)"
                         << R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,)"
                         << R"("type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
                         << R"({"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}]})";
        return p;
    }

    test::ChildResult convert(const fs::path& scene, std::vector<std::string> options = {},
                              uint64_t addressSpaceLimit = 0) {
        std::vector<std::string> argv = {PNB_CONVERT_EXE, scene.string(), "-o",
                                         (dir / "out.pnb").string(), "--no-validate-shaders"};
        argv.insert(argv.end(), options.begin(), options.end());
        return test::runChild(argv, (dir / "output.txt").string(), addressSpaceLimit);
    }

    fs::path dir;
};

bool contains(const std::string& s, const std::string& needle) {
    return s.find(needle) != std::string::npos;
}

TEST(MemoryBudget, ParsesSizes) {
    EXPECT_EQ(parseByteSize("1048576"), 1048576u);
    EXPECT_EQ(parseByteSize("512K"), 512u << 10);
    EXPECT_EQ(parseByteSize("64M"), 64u << 20);
    EXPECT_EQ(parseByteSize("64m"), 64u << 20);
    EXPECT_EQ(parseByteSize("1.5G"), 3ull << 29);
    EXPECT_EQ(parseByteSize("2GiB"), 2ull << 30);
    EXPECT_EQ(parseByteSize("2GB"), 2ull << 30);
    EXPECT_EQ(parseByteSize("1T"), 1ull << 40);
    for (const char* bad : {"", "G", "-1", "12X", "0", "1.5.5", "1 G", "99999999T"})
        EXPECT_FALSE(parseByteSize(bad).has_value()) << bad;
    EXPECT_EQ(formatBytes(512), "512 B");
    EXPECT_EQ(formatBytes(64ull << 20), "64.00 MiB");
}

TEST(MemoryBudget, DefaultIsHalfOfWhatTheProcessMayUse) {
    const uint64_t usable = usableMemoryBytes();
    const uint64_t physical = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
    EXPECT_GT(usable, 0u);
    EXPECT_LE(usable, physical);
    EXPECT_EQ(defaultMemoryBudget(), usable / 2);
}

// The estimate is the sum of the buffers texture_processing.cpp lists, per declared texel.
TEST(MemoryBudget, EstimateCountsEveryBuffer) {
    TextureSettings s;
    const uint64_t texels = uint64_t(kHuge) * kHuge;
    // RGBA8: decoder copy 4 + native 4 + float 16 + next level 4 + packed 8 x 4/3.
    EXPECT_EQ(estimateTextureBytes(kHuge, kHuge, 4, 1, s),
              texels * 28 + texels * 8 + texels * 8 / 3);
    // 6-channel half EXR: decoder copy 12 + native 4 channels 8, the rest as above.
    EXPECT_EQ(estimateTextureBytes(100, 100, 6, 2, s), 10000u * 40 + 80000 + 80000 / 3);
    s.maxSize = 1024; // downscaling adds the resized copy
    EXPECT_EQ(estimateTextureBytes(kHuge, kHuge, 4, 1, s),
              texels * 44 + texels * 8 + texels * 8 / 3);
    EXPECT_EQ(estimateTextureBytes(1024, 1024, 4, 1, s), (1u << 20) * 36 + (1u << 20) * 8 / 3);
    // A header claiming 2^31 a side and thousands of channels does not overflow.
    EXPECT_EQ(estimateTextureBytes(1u << 31, 1u << 31, 4096, 4, s), UINT64_MAX);
}

// In-process: fails at once, naming the image and its declared size, and the process's peak
// memory does not grow by anything near the declared size.
TEST_F(ImageBudget, PngDeclaringHugeSizeFailsFastInProcess) {
    for (uint8_t colourType : {uint8_t(6), uint8_t(0)}) { // RGBA, grey
        IrImage image;
        image.name = "liar";
        image.encoded = test::pngDeclaringOnly(kHuge, kHuge, colourType);
        ASSERT_LE(image.encoded.size(), 70u);
        TextureRequest request;
        request.image = &image;
        request.name = image.name;
        TextureSettings s;
        s.jobs = 1; // on this thread, for PNB_IGNORE_OIIO_LEAKS
        rusage before{}, after{};
        getrusage(RUSAGE_SELF, &before);
        const auto start = std::chrono::steady_clock::now();
        Result<std::vector<ProcessedTexture>, ConvertError> r = [&] {
            PNB_IGNORE_OIIO_LEAKS;
            return processTextures({request}, s);
        }();
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        getrusage(RUSAGE_SELF, &after);
        ASSERT_FALSE(r.ok());
        EXPECT_TRUE(contains(r.error().message, "'liar'")) << r.error().message;
        EXPECT_TRUE(contains(r.error().message, "16384x16384")) << r.error().message;
        EXPECT_LT(seconds, 3.0);
        EXPECT_LT(uint64_t(after.ru_maxrss - before.ru_maxrss) * 1024, 256ull << 20);
    }
}

TEST_F(ImageBudget, ExplicitBudgetRefusesAnOrdinaryImageFromItsHeader) {
    IrImage image;
    image.name = "gradient";
    image.path = writeNormalPng("gradient.png").string();
    TextureRequest request;
    request.image = &image;
    request.name = image.name;
    TextureSettings s;
    s.jobs = 1;
    s.maxMemoryBytes = 1 << 20;
    auto refused = processTextures({request}, s);
    ASSERT_FALSE(refused.ok());
    const std::string& msg = refused.error().message;
    EXPECT_EQ(refused.error().kind, ConvertErrorKind::Input);
    for (const char* needle :
         {"'gradient'", "gradient.png", "256x256", "memory budget", "--max-memory 1.00 MiB"})
        EXPECT_TRUE(contains(msg, needle)) << needle << " not in: " << msg;

    // Two textures in flight share the budget: each gets half.
    s.jobs = 2;
    s.maxMemoryBytes = 4 << 20; // one 256x256 RGB texture needs about 2.3 MiB
    auto shared = processTextures({request, request}, s);
    ASSERT_FALSE(shared.ok());
    EXPECT_TRUE(contains(shared.error().message, "/ 2 parallel jobs")) << shared.error().message;
    s.jobs = 1;
    EXPECT_TRUE(processTextures({request, request}, s).ok());
    s.maxMemoryBytes = 0; // the machine's default
    EXPECT_TRUE(processTextures({request}, s).ok());
}

// [SECTION] pnb-convert as a process

TEST_F(ImageBudget, ConvertFailsFastAndSmallOnAPngDeclaringHugeSize) {
    writeNormalPng("gradient.png");
    const test::ChildResult baseline = convert(writeScene("ok", "gradient.png"));
    ASSERT_EQ(baseline.exitCode, 0) << baseline.output;
    writeBytes("huge.png", test::pngDeclaringOnly(kHuge, kHuge));
    const test::ChildResult r = convert(writeScene("liar", "huge.png"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "huge.png")) << r.output;
    EXPECT_TRUE(contains(r.output, "16384x16384")) << r.output;
    EXPECT_LT(r.seconds, test::startupBound(baseline));
    EXPECT_LT(r.maxRssBytes, kSmallRss);
    std::cout << "[ budget ] 70-byte PNG declaring 16384x16384: exit " << r.exitCode << " in "
              << r.seconds << " s, peak RSS " << formatBytes(r.maxRssBytes)
              << " (a 256x256 PNG: " << baseline.seconds << " s, "
              << formatBytes(baseline.maxRssBytes) << ")\n";
}

// On a machine (here: an address-space limit) too small for the declared size, the default
// budget refuses the image from its header, before the decoder is asked for a single pixel.
TEST_F(ImageBudget, DefaultBudgetFollowsTheMachine) {
    if (test::kAddressSanitizer) GTEST_SKIP() << "ASan cannot run under RLIMIT_AS";
    writeNormalPng("gradient.png");
    const test::ChildResult baseline = convert(writeScene("ok", "gradient.png"), {}, 3ull << 30);
    ASSERT_EQ(baseline.exitCode, 0) << baseline.output;
    writeBytes("huge.png", test::pngDeclaringOnly(kHuge, kHuge));
    const test::ChildResult r = convert(writeScene("liar", "huge.png"), {}, 3ull << 30);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    for (const char* needle : {"huge.png", "declared 16384x16384", "memory budget"})
        EXPECT_TRUE(contains(r.output, needle)) << needle << " not in: " << r.output;
    EXPECT_LT(r.seconds, test::startupBound(baseline));
}

TEST_F(ImageBudget, ConvertTakesOrdinaryTexturesAndHonoursMaxMemory) {
    writeNormalPng("gradient.png");
    const fs::path scene = writeScene("ok", "gradient.png");
    test::ChildResult r = convert(scene);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    r = convert(scene, {"--max-memory", "1M"});
    EXPECT_EQ(r.exitCode, 2) << r.output;
    for (const char* needle : {"gradient.png", "declared 256x256", "--max-memory 1.00 MiB"})
        EXPECT_TRUE(contains(r.output, needle)) << needle << " not in: " << r.output;
    r = convert(scene, {"--max-memory", "lots"});
    EXPECT_EQ(r.exitCode, 1) << r.output;
}

} // namespace
