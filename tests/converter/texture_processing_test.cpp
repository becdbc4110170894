// Tests for processTextures (converter/src/texture_processing.cpp and its helpers). Every test
// image is written at test time with OpenImageIO into a temporary directory: no binary fixtures.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb_converter/texture_processing.h"
#include "texture_internal.h"

#include "oiio_leak_guard.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;
namespace detail = pnb::converter::texture_detail;

// A float image in row-major RGBA-or-fewer channels, values in file units (0..1 for 8-bit).
struct TestImage {
    int width = 0, height = 0, channels = 4;
    std::vector<float> pixels;
    float& at(int x, int y, int c) { return pixels[(size_t(y) * width + x) * channels + c]; }
};

TestImage makeImage(int w, int h, int channels) {
    return {w, h, channels, std::vector<float>(size_t(w) * h * channels, 0.0f)};
}

class TextureProcessing : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        mDir = fs::temp_directory_path() / (std::string("pnb_texture_test_") + info->name() + "_" +
                                            std::to_string(std::random_device{}()));
        fs::create_directories(mDir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(mDir, ec);
    }

    // Writes `img` as `name` (format from the extension); returns an IrImage pointing at it.
    IrImage write(const std::string& name, const TestImage& img,
                  OIIO::TypeDesc format = OIIO::TypeDesc::UINT8) {
        fs::path path = mDir / name;
        auto out = OIIO::ImageOutput::create(path.string());
        EXPECT_TRUE(out) << OIIO::geterror();
        if (!out) return {};
        OIIO::ImageSpec spec(img.width, img.height, img.channels, format);
        spec.attribute("oiio:UnassociatedAlpha", 1); // write alpha as given, not un-premultiplied
        spec.attribute("CompressionQuality", 100);
        spec.attribute("jpeg:subsampling", "4:4:4");
        EXPECT_TRUE(out->open(path.string(), spec)) << out->geterror();
        EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data())) << out->geterror();
        out->close();
        IrImage ir;
        ir.name = name;
        ir.path = path.string();
        return ir;
    }

    fs::path mDir;
};

TextureRequest requestFor(const IrImage& image, ColorSpace cs = ColorSpace::Linear) {
    TextureRequest r;
    r.image = &image;
    r.name = image.name;
    r.colorSpace = cs;
    return r;
}

ProcessedTexture processOne(const TextureRequest& request, TextureSettings settings = {}) {
    settings.jobs = 1;
    auto r = processTextures({request}, settings);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value().front() : ProcessedTexture{};
}

std::vector<uint8_t> readFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

uint32_t positionsOf(TextureFormat f) {
    switch (f) {
    case TextureFormat::R8:
    case TextureFormat::BC4:
    case TextureFormat::R16F:
        return 1;
    case TextureFormat::RG8:
    case TextureFormat::BC5:
    case TextureFormat::RG16F:
        return 2;
    case TextureFormat::RGB8:
    case TextureFormat::BC1:
        return 3;
    default:
        return 4;
    }
}

bool isBlock(TextureFormat f) {
    return f == TextureFormat::BC1 || f == TextureFormat::BC3 || f == TextureFormat::BC4 ||
           f == TextureFormat::BC5;
}

uint32_t levelWidth(const TextureDesc& d, uint32_t l) {
    return std::max(1u, d.width >> l);
}
uint32_t levelHeight(const TextureDesc& d, uint32_t l) {
    return std::max(1u, d.height >> l);
}

// The stored 8-bit channels of a level (BC levels decoded), positions interleaved.
std::vector<uint8_t> storedLevel(const ProcessedTexture& t, uint32_t l) {
    const TextureDesc& d = t.desc;
    uint32_t w = levelWidth(d, l), h = levelHeight(d, l);
    if (isBlock(d.format))
        return detail::decompressLevel(t.levels[l], positionsOf(d.format), w, h, d.format);
    std::vector<uint8_t> out(t.levels[l].size());
    std::transform(t.levels[l].begin(), t.levels[l].end(), out.begin(),
                   [](std::byte b) { return uint8_t(b); });
    return out;
}

// What a shader samples for channel c at (x, y) of level l of an 8-bit texture, 0..255 (before
// any sRGB decode).
struct Sampler {
    const ProcessedTexture& t;
    uint32_t level;
    std::vector<uint8_t> data = storedLevel(t, level);
    int operator()(uint32_t x, uint32_t y, int c) const {
        Swizzle s = t.desc.swizzle[size_t(c)];
        if (s == Swizzle::Zero) return 0;
        if (s == Swizzle::One) return 255;
        uint32_t positions = positionsOf(t.desc.format);
        return data[(size_t(y) * levelWidth(t.desc, level) + x) * positions + uint32_t(s)];
    }
};

// One texel of one level (a function, so a macro's argument list holds it without braces).
int sampleAt(const ProcessedTexture& t, uint32_t level, uint32_t x, uint32_t y, int c) {
    return Sampler{t, level}(x, y, c);
}

using Sw = Swizzle;
std::array<Swizzle, 4> swz(Sw r, Sw g, Sw b, Sw a) {
    return {r, g, b, a};
}

// [SECTION] channel packing

TEST_F(TextureProcessing, GreyscaleSavedAsRgbaBecomesR8) {
    TestImage img = makeImage(16, 8, 4);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            float v = float((x * 16 + y * 3) % 256) / 255.0f;
            img.at(x, y, 0) = img.at(x, y, 1) = img.at(x, y, 2) = v;
            img.at(x, y, 3) = 1.0f;
        }
    IrImage ir = write("grey.png", img);
    ProcessedTexture t = processOne(requestFor(ir));
    EXPECT_EQ(t.desc.format, TextureFormat::R8);
    EXPECT_EQ(t.desc.swizzle, swz(Sw::R, Sw::R, Sw::R, Sw::One));
    EXPECT_EQ(t.desc.colorSpace, ColorSpace::Linear);
    EXPECT_EQ(t.sourceChannels, 4u);
    ASSERT_EQ(t.levels[0].size(), 16u * 8u);
    Sampler s{t, 0};
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(s(x, y, c), (x * 16 + y * 3) % 256);

    // sRGB greyscale: still one channel, but linearised (GL has no core sRGB R8 format).
    ProcessedTexture ts = processOne(requestFor(ir, ColorSpace::Srgb));
    EXPECT_EQ(ts.desc.format, TextureFormat::R8);
    EXPECT_EQ(ts.desc.colorSpace, ColorSpace::Linear);
    EXPECT_EQ(ts.desc.swizzle, swz(Sw::R, Sw::R, Sw::R, Sw::One));
    Sampler ss{ts, 0};
    float encoded = float((5 * 16 + 2 * 3) % 256) / 255.0f;
    EXPECT_EQ(ss(5, 2, 0), detail::quantizeUnorm8(detail::srgbToLinear(encoded)));
}

TEST_F(TextureProcessing, RgbWithOpaqueAlphaBecomesRgb8AndKeepsSrgbBytes) {
    TestImage img = makeImage(8, 8, 4);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            img.at(x, y, 0) = float(x * 30) / 255.0f;
            img.at(x, y, 1) = float(y * 30) / 255.0f;
            img.at(x, y, 2) = float(200 - x * y) / 255.0f;
            img.at(x, y, 3) = 1.0f;
        }
    IrImage ir = write("rgb_opaque.png", img);
    ProcessedTexture t = processOne(requestFor(ir, ColorSpace::Srgb));
    EXPECT_EQ(t.desc.format, TextureFormat::RGB8);
    EXPECT_EQ(t.desc.colorSpace, ColorSpace::Srgb);
    EXPECT_EQ(t.desc.swizzle, swz(Sw::R, Sw::G, Sw::B, Sw::One));
    Sampler s{t, 0};
    // Linearise → re-encode is exact for 8-bit sources: level 0 holds the file's bytes.
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            ASSERT_EQ(s(x, y, 0), x * 30);
            ASSERT_EQ(s(x, y, 1), y * 30);
            ASSERT_EQ(s(x, y, 2), 200 - x * y);
        }
    // Rows are stored top row first (see the orientation note in texture_processing.cpp).
    EXPECT_EQ(uint8_t(t.levels[0][1]), 0);                 // (0, 0).g: top row, y = 0
    EXPECT_EQ(uint8_t(t.levels[0][(7 * 8) * 3 + 1]), 210); // (0, 7).g: last stored row
}

TEST_F(TextureProcessing, ConstantDuplicateAndUnrequestedChannelsAreNotStored) {
    TestImage img = makeImage(8, 4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            img.at(x, y, 0) = float(x * 20 + y) / 255.0f;   // varies
            img.at(x, y, 1) = 0.0f;                         // constant 0
            img.at(x, y, 2) = img.at(x, y, 0);              // duplicate of r
            img.at(x, y, 3) = float(255 - x * 10) / 255.0f; // varies
        }
    IrImage ir = write("packed.png", img);
    ProcessedTexture t = processOne(requestFor(ir));
    EXPECT_EQ(t.desc.format, TextureFormat::RG8);
    EXPECT_EQ(t.desc.swizzle, swz(Sw::R, Sw::Zero, Sw::R, Sw::G));
    Sampler s{t, 0};
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            ASSERT_EQ(s(x, y, 0), x * 20 + y);
            ASSERT_EQ(s(x, y, 2), x * 20 + y);
            ASSERT_EQ(s(x, y, 3), 255 - x * 10);
        }

    // Only r read (e.g. an occlusion slot): R8, the rest sample as (0, 0, 1).
    TextureRequest onlyR = requestFor(ir);
    std::fill(std::begin(onlyR.channels), std::end(onlyR.channels), false);
    onlyR.channels[0] = true;
    ProcessedTexture r = processOne(onlyR);
    EXPECT_EQ(r.desc.format, TextureFormat::R8);
    EXPECT_EQ(r.desc.swizzle, swz(Sw::R, Sw::Zero, Sw::Zero, Sw::One));

    // An alpha-masked texture never merges alpha into a colour channel (its mips differ).
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x)
            img.at(x, y, 3) = img.at(x, y, 0);
    IrImage ir2 = write("alpha_equals_red.png", img);
    TextureRequest plain = requestFor(ir2);
    EXPECT_EQ(processOne(plain).desc.swizzle, swz(Sw::R, Sw::Zero, Sw::R, Sw::R));
    plain.alphaMask = true;
    ProcessedTexture masked = processOne(plain);
    EXPECT_EQ(masked.desc.format, TextureFormat::RG8);
    EXPECT_EQ(masked.desc.swizzle, swz(Sw::R, Sw::Zero, Sw::R, Sw::G));
}

TEST_F(TextureProcessing, GreyAlphaSourceKeepsChannelMeaning) {
    TestImage img = makeImage(4, 4, 2);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            img.at(x, y, 0) = float(x * 60) / 255.0f;
            img.at(x, y, 1) = float(y * 80) / 255.0f;
        }
    IrImage ir = write("grey_alpha.png", img);
    ProcessedTexture t = processOne(requestFor(ir));
    EXPECT_EQ(t.sourceChannels, 2u);
    EXPECT_EQ(t.desc.format, TextureFormat::RG8);
    EXPECT_EQ(t.desc.swizzle, swz(Sw::R, Sw::R, Sw::R, Sw::G));
    Sampler s{t, 0};
    EXPECT_EQ(s(3, 2, 0), 180);
    EXPECT_EQ(s(3, 2, 3), 160);
}

TEST_F(TextureProcessing, SrgbColourKeepsSrgbStorageWithLinearAlpha) {
    // r and g differ, b duplicates r, alpha varies: sRGB colour must stay at R, G, B of an
    // SRGB8_ALPHA8 texture and alpha at A, so the position B is left unused.
    TestImage img = makeImage(8, 8, 4);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            img.at(x, y, 0) = img.at(x, y, 2) = float(x * 30) / 255.0f;
            img.at(x, y, 1) = float(y * 30) / 255.0f;
            img.at(x, y, 3) = float(x * y * 5) / 255.0f;
        }
    IrImage ir = write("srgb_alpha.png", img);
    ProcessedTexture t = processOne(requestFor(ir, ColorSpace::Srgb));
    EXPECT_EQ(t.desc.format, TextureFormat::RGBA8);
    EXPECT_EQ(t.desc.colorSpace, ColorSpace::Srgb);
    EXPECT_EQ(t.desc.swizzle, swz(Sw::R, Sw::G, Sw::R, Sw::A));
    Sampler s{t, 0};
    EXPECT_EQ(s(7, 3, 2), 210);
    EXPECT_EQ(s(7, 3, 3), 105); // alpha stored as is, not sRGB-encoded
}

// [SECTION] mips

TEST_F(TextureProcessing, SrgbMipsAverageInLinearLight) {
    // 1-texel checkers: every level-1 texel averages two dark and two bright texels.
    TestImage grey = makeImage(8, 8, 3), colour = makeImage(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            bool on = (x + y) % 2 == 0;
            for (int c = 0; c < 3; ++c)
                grey.at(x, y, c) = on ? 1.0f : 0.0f;
            colour.at(x, y, 0) = on ? 1.0f : 0.0f;
            colour.at(x, y, 1) = on ? 0.0f : 1.0f;
        }
    IrImage greyIr = write("checker_grey.png", grey), colourIr = write("checker_rg.png", colour);

    // sRGB colour stays sRGB: linear mean 0.5 encodes as 188 (a gamma-space average gives 128).
    ProcessedTexture c = processOne(requestFor(colourIr, ColorSpace::Srgb));
    ASSERT_EQ(c.desc.format, TextureFormat::RGB8);
    ASSERT_EQ(c.desc.colorSpace, ColorSpace::Srgb);
    ASSERT_EQ(c.desc.mipCount, 4u);
    for (uint32_t l = 1; l < 4; ++l) {
        Sampler s{c, l};
        for (uint32_t y = 0; y < levelHeight(c.desc, l); ++y)
            for (uint32_t x = 0; x < levelWidth(c.desc, l); ++x) {
                ASSERT_EQ(s(x, y, 0), 188) << "level " << l;
                ASSERT_EQ(s(x, y, 1), 188) << "level " << l;
            }
    }
    // Grey sRGB is linearised into R8: the same light, stored linear.
    ProcessedTexture g = processOne(requestFor(greyIr, ColorSpace::Srgb));
    ASSERT_EQ(g.desc.format, TextureFormat::R8);
    EXPECT_EQ(g.desc.colorSpace, ColorSpace::Linear);
    EXPECT_EQ(sampleAt(g, 1, 0, 0, 0), 128);
    // Linear data is averaged as is.
    EXPECT_EQ(sampleAt(processOne(requestFor(colourIr)), 1, 2, 1, 0), 128);
}

TEST_F(TextureProcessing, NonPowerOfTwoUsesFloorHalvingAndAreaWeights) {
    TestImage img = makeImage(5, 3, 1);
    double sum = 0;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) {
            img.at(x, y, 0) = float(x * 50 + y * 20) / 255.0f;
            sum += x * 50 + y * 20;
        }
    IrImage ir = write("npot.png", img);
    ProcessedTexture t = processOne(requestFor(ir));
    ASSERT_EQ(t.desc.mipCount, 3u);
    ASSERT_EQ(t.levels.size(), 3u);
    uint32_t expected[3][2] = {{5, 3}, {2, 1}, {1, 1}};
    for (uint32_t l = 0; l < 3; ++l) {
        EXPECT_EQ(levelWidth(t.desc, l), expected[l][0]);
        EXPECT_EQ(levelHeight(t.desc, l), expected[l][1]);
        EXPECT_EQ(t.levels[l].size(),
                  textureLevelSizeBytes(t.desc.format, expected[l][0], expected[l][1], 1));
    }
    // Level 1 texel 0 covers x in [0, 2.5): columns 0 and 1 fully, column 2 half, so its value
    // is (0 + 50 + 0.5 * 100) / 2.5 + (0 + 20 + 40) / 3 = 60; a 2×2 average that drops the odd
    // column would give 45. The 1×1 level is the mean of the whole image, 100 + 20.
    EXPECT_NEAR(sampleAt(t, 1, 0, 0, 0), 60, 0.51);
    EXPECT_NEAR(sampleAt(t, 1, 1, 0, 0), 180, 0.51); // (0.5 * 100 + 150 + 200) / 2.5 + 20
    EXPECT_NEAR(sampleAt(t, 2, 0, 0, 0), sum / 15.0, 0.51);
}

TEST_F(TextureProcessing, NonMipmappedFilterStoresOneLevel) {
    TestImage img = makeImage(16, 16, 3);
    for (size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = float(i % 7) / 7.0f;
    IrImage ir = write("nomip.png", img);
    TextureRequest r = requestFor(ir);
    r.minFilter = MinFilter::Linear;
    r.magFilter = MagFilter::Nearest;
    r.wrapU = Wrap::ClampToEdge;
    r.wrapV = Wrap::MirroredRepeat;
    ProcessedTexture t = processOne(r);
    EXPECT_EQ(t.desc.mipCount, 1u);
    EXPECT_EQ(t.levels.size(), 1u);
    EXPECT_EQ(t.desc.minFilter, MinFilter::Linear);
    EXPECT_EQ(t.desc.magFilter, MagFilter::Nearest);
    EXPECT_EQ(t.desc.wrapU, Wrap::ClampToEdge);
    EXPECT_EQ(t.desc.wrapV, Wrap::MirroredRepeat);
    EXPECT_EQ(t.desc.dimension, TextureDimension::Tex2D);
    EXPECT_EQ(t.desc.layers, 1u);
    EXPECT_EQ(t.desc.name, kNone);
}

TEST_F(TextureProcessing, MaxSizeLimitsTheLongestEdgeAndKeepsAspect) {
    TestImage img = makeImage(64, 32, 3);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) {
            img.at(x, y, 0) = float(x) / 63.0f;
            img.at(x, y, 1) = float(y) / 31.0f;
            img.at(x, y, 2) = 0.5f;
        }
    IrImage ir = write("big.png", img);
    TextureSettings s;
    s.maxSize = 16;
    ProcessedTexture t = processOne(requestFor(ir, ColorSpace::Srgb), s);
    EXPECT_EQ(t.desc.width, 16u);
    EXPECT_EQ(t.desc.height, 8u);
    EXPECT_EQ(t.desc.mipCount, 5u);
    EXPECT_EQ(t.sourceWidth, 64u);
    EXPECT_EQ(t.sourceHeight, 32u);
    // A ramp survives the filter: monotonic, and ends near its ends.
    Sampler s0{t, 0};
    for (int x = 1; x < 16; ++x)
        EXPECT_GE(s0(x, 4, 0), s0(x - 1, 4, 0));
    EXPECT_LE(s0(0, 4, 0), 40);
    EXPECT_GE(s0(15, 4, 0), 240);

    s.maxSize = 128; // never upsized
    EXPECT_EQ(processOne(requestFor(ir), s).desc.width, 64u);

    TestImage thin = makeImage(3, 100, 1);
    for (size_t i = 0; i < thin.pixels.size(); ++i)
        thin.pixels[i] = float(i % 3) / 2.0f;
    IrImage thinIr = write("thin.png", thin);
    s.maxSize = 10;
    ProcessedTexture tt = processOne(requestFor(thinIr), s);
    EXPECT_EQ(tt.desc.width, 1u); // 0.3 rounds to 0: at least 1
    EXPECT_EQ(tt.desc.height, 10u);
}

// [SECTION] alpha coverage

// Fraction of texels of level l whose sampled alpha passes `alpha >= cutoff`.
double storedCoverage(const ProcessedTexture& t, uint32_t l, float cutoff) {
    Sampler s{t, l};
    uint32_t w = levelWidth(t.desc, l), h = levelHeight(t.desc, l), pass = 0;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            pass += float(s(x, y, 3)) / 255.0f >= cutoff;
    return double(pass) / double(w * h);
}

TEST_F(TextureProcessing, AlphaCoverageIsPreservedForMaskedTextures) {
    // Foliage-like: 220 soft-edged leaves (discs) scattered over 256², ~25 % opaque. A plain box
    // chain averages them into a thin haze below the cutoff, so distant foliage vanishes.
    TestImage img = makeImage(256, 256, 4);
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> pos(0.0f, 256.0f), radius(2.5f, 6.0f);
    for (int i = 0; i < 220; ++i) {
        float cx = pos(rng), cy = pos(rng), r = radius(rng);
        int x0 = std::max(0, int(cx - r) - 1), x1 = std::min(255, int(cx + r) + 1);
        int y0 = std::max(0, int(cy - r) - 1), y1 = std::min(255, int(cy + r) + 1);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                float d = std::hypot(x + 0.5f - cx, y + 0.5f - cy);
                float a = std::clamp(r - d, 0.0f, 1.0f); // one-texel soft edge
                img.at(x, y, 3) = std::max(img.at(x, y, 3), a);
            }
    }
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            img.at(x, y, 0) = 0.2f + 0.1f * float(x % 5) / 4.0f;
            img.at(x, y, 1) = 0.6f;
            img.at(x, y, 2) = 0.1f + 0.1f * float(y % 3) / 2.0f;
        }
    IrImage ir = write("foliage.png", img);
    TextureRequest masked = requestFor(ir, ColorSpace::Srgb);
    masked.alphaMask = true;
    masked.alphaCutoff = 0.5f;
    TextureRequest naive = masked;
    naive.alphaMask = false;
    ProcessedTexture m = processOne(masked), n = processOne(naive);
    ASSERT_EQ(m.desc.mipCount, 9u);
    ASSERT_EQ(m.desc.format, TextureFormat::RGBA8);

    double c0 = storedCoverage(m, 0, 0.5f);
    EXPECT_NEAR(c0, storedCoverage(n, 0, 0.5f), 1e-12);
    EXPECT_GT(c0, 0.1);
    EXPECT_LT(c0, 0.5);
    double naiveDrift = 0;
    for (uint32_t l = 1; l < m.desc.mipCount; ++l) {
        uint32_t texels = levelWidth(m.desc, l) * levelHeight(m.desc, l);
        double cm = storedCoverage(m, l, 0.5f), cn = storedCoverage(n, l, 0.5f);
        std::printf(
            "    level %u (%u texels): coverage %.4f preserved, %.4f naive (level 0 %.4f)\n", l,
            texels, cm, cn, c0);
        // Coverage comes in steps of 1/texels: hold the 2 % bound where it can be met.
        if (texels >= 64)
            EXPECT_NEAR(cm, c0, 0.02) << "level " << l;
        else
            EXPECT_NEAR(cm, c0, 1.0 / texels) << "level " << l;
        naiveDrift = std::max(naiveDrift, std::abs(cn - c0));
    }
    EXPECT_GT(naiveDrift, 0.15) << "the unscaled chain should lose the leaves";
}

TEST(TextureQuantize, CoverageScaleSearch) {
    // Half the texels at 0.4, half at 0.8; cutoff 0.5: coverage 0.5. A blurred level at 0.45
    // everywhere has coverage 0, and the scale must lift it above the cutoff.
    detail::ImageF img;
    img.width = 4;
    img.height = 4;
    img.texels.assign(64, 0.0f);
    for (int i = 0; i < 16; ++i)
        img.texels[i * 4 + 3] = i < 8 ? 0.30f : 0.45f;
    EXPECT_EQ(detail::alphaCoverage(img, 0.5f, 1.0f, detail::AlphaStorage::Unorm8), 0.0);
    float s = detail::findAlphaScale(img, 0.5f, 0.5, detail::AlphaStorage::Unorm8);
    EXPECT_EQ(detail::alphaCoverage(img, 0.5f, s, detail::AlphaStorage::Unorm8), 0.5);
    EXPECT_EQ(detail::findAlphaScale(img, 0.0f, 0.5, detail::AlphaStorage::Unorm8), 1.0f);
}

// [SECTION] block compression

TEST_F(TextureProcessing, BlockCompressionFormatsSizesAndPsnr) {
    // A smooth gradient with a size that is not a multiple of 4 (edge blocks are padded).
    const int w = 62, h = 46;
    TestImage img = makeImage(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float u = float(x) / (w - 1), v = float(y) / (h - 1);
            img.at(x, y, 0) = u;
            img.at(x, y, 1) = v;
            img.at(x, y, 2) = 0.5f * (u + v);
            img.at(x, y, 3) = 0.25f + 0.5f * u * v;
        }
    IrImage ir = write("gradient.png", img);
    TextureSettings s;
    s.compress = true;
    struct Case {
        int channels;
        TextureFormat format;
    } cases[] = {{1, TextureFormat::BC4},
                 {2, TextureFormat::BC5},
                 {3, TextureFormat::BC1},
                 {4, TextureFormat::BC3}};
    for (const Case& c : cases) {
        TextureRequest r = requestFor(ir);
        for (int i = 0; i < 4; ++i)
            r.channels[i] = i < c.channels;
        ProcessedTexture t = processOne(r, s);
        ASSERT_EQ(t.desc.format, c.format) << c.channels << " channels";
        ASSERT_EQ(t.desc.mipCount, 6u);
        for (uint32_t l = 0; l < t.desc.mipCount; ++l)
            ASSERT_EQ(t.levels[l].size(),
                      textureLevelSizeBytes(t.desc.format, levelWidth(t.desc, l),
                                            levelHeight(t.desc, l), 1))
                << "level " << l;
        std::printf("    %d channel(s) -> BC%d: PSNR %.2f dB\n", c.channels,
                    c.format == TextureFormat::BC1   ? 1
                    : c.format == TextureFormat::BC3 ? 3
                    : c.format == TextureFormat::BC4 ? 4
                                                     : 5,
                    t.psnrDb);
        EXPECT_GT(t.psnrDb, 30.0);
        // The sampled result stays close to the uncompressed texture everywhere.
        ProcessedTexture plain = processOne(r);
        Sampler a{t, 0}, b{plain, 0};
        int worst = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int ch = 0; ch < 4; ++ch)
                    worst = std::max(worst, std::abs(a(x, y, ch) - b(x, y, ch)));
        EXPECT_LE(worst, 16);
    }
    // Uncompressed textures report no loss.
    EXPECT_EQ(processOne(requestFor(ir)).psnrDb, 0.0);
}

TEST_F(TextureProcessing, SrgbColourCompressesToBc1) {
    TestImage img = makeImage(64, 64, 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            img.at(x, y, 0) = float(x) / 63.0f;
            img.at(x, y, 1) = float(y) / 63.0f;
            img.at(x, y, 2) = 0.3f;
        }
    IrImage ir = write("srgb_bc1.png", img);
    TextureSettings s;
    s.compress = true;
    ProcessedTexture t = processOne(requestFor(ir, ColorSpace::Srgb), s);
    EXPECT_EQ(t.desc.format, TextureFormat::BC1);
    EXPECT_EQ(t.desc.colorSpace, ColorSpace::Srgb);
    EXPECT_EQ(t.desc.swizzle, swz(Sw::R, Sw::G, Sw::B, Sw::One));
    std::printf("    sRGB 64x64 gradient -> BC1: PSNR %.2f dB\n", t.psnrDb);
    EXPECT_GT(t.psnrDb, 30.0);
    // Levels below 4×4 still take a whole block.
    ASSERT_EQ(t.desc.mipCount, 7u);
    EXPECT_EQ(t.levels[5].size(), 8u); // 2×2
    EXPECT_EQ(t.levels[6].size(), 8u); // 1×1
}

// [SECTION] decoding

TEST_F(TextureProcessing, DecodesCommonFormats) {
    TestImage rgb = makeImage(16, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            rgb.at(x, y, 0) = float(x * 16) / 255.0f;
            rgb.at(x, y, 1) = float(y * 32) / 255.0f;
            rgb.at(x, y, 2) = 0.5f;
        }
    TestImage rgba = makeImage(16, 8, 4);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            for (int c = 0; c < 3; ++c)
                rgba.at(x, y, c) = rgb.at(x, y, c);
            rgba.at(x, y, 3) = float(x * 8 + y) / 255.0f;
        }
    struct Case {
        std::string name;
        const TestImage* image;
        int tolerance; // 8-bit steps
    } cases[] = {{"a.png", &rgba, 0}, {"a.tga", &rgba, 0}, {"a.bmp", &rgb, 0}, {"a.jpg", &rgb, 6}};
    for (const Case& c : cases) {
        IrImage ir = write(c.name, *c.image);
        ProcessedTexture t = processOne(requestFor(ir));
        ASSERT_EQ(t.desc.width, 16u) << c.name;
        ASSERT_EQ(t.desc.height, 8u) << c.name;
        EXPECT_EQ(t.sourceChannels, uint32_t(c.image->channels)) << c.name;
        Sampler s{t, 0};
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 16; ++x) {
                ASSERT_NEAR(s(x, y, 0), x * 16, c.tolerance) << c.name << " at " << x << "," << y;
                ASSERT_NEAR(s(x, y, 1), y * 32, c.tolerance) << c.name << " at " << x << "," << y;
                int alpha = c.image->channels == 4 ? x * 8 + y : 255;
                ASSERT_NEAR(s(x, y, 3), alpha, c.tolerance) << c.name; // straight alpha
            }
        // The same bytes embedded (glb buffer view / data URI): found by signature, or by MIME
        // type for TGA, which has none.
        IrImage embedded;
        embedded.name = "embedded " + c.name;
        embedded.encoded = readFile(ir.path);
        if (c.name == "a.tga") embedded.mimeType = "image/x-tga";
        ProcessedTexture e = processOne(requestFor(embedded));
        EXPECT_EQ(e.levels, t.levels) << c.name;
    }
}

TEST_F(TextureProcessing, FloatSourcesStayFloat) {
    TestImage img = makeImage(8, 4, 3);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            img.at(x, y, 0) = float(x) * 0.5f; // up to 3.5: HDR
            img.at(x, y, 1) = float(y) * 0.25f;
            img.at(x, y, 2) = 0.125f;
        }
    TextureSettings s;
    s.compress = true; // ignored for HDR: there is no BC6H here
    for (std::string name : {"a.exr", "a.hdr"}) {
        IrImage ir = write(name, img, OIIO::TypeDesc::FLOAT);
        ProcessedTexture t = processOne(requestFor(ir, ColorSpace::Srgb), s);
        EXPECT_EQ(t.desc.format, TextureFormat::RGBA16F) << name;
        EXPECT_EQ(t.desc.colorSpace, ColorSpace::Linear) << name; // float files are linear
        EXPECT_EQ(t.desc.swizzle, swz(Sw::R, Sw::G, Sw::B, Sw::One)) << name;
        EXPECT_EQ(t.psnrDb, 0.0);
        ASSERT_EQ(t.levels[0].size(), 8u * 4u * 8u);
        auto half = [&](uint32_t x, uint32_t y, int c) {
            size_t at = ((size_t(y) * 8 + x) * 4 + c) * 2;
            return detail::halfToFloat(
                uint16_t(uint8_t(t.levels[0][at]) | uint8_t(t.levels[0][at + 1]) << 8));
        };
        // RGBE shares one exponent per texel: 8 mantissa bits relative to the largest channel.
        float tolerance = name == "a.hdr" ? 0.03f : 0.0f;
        EXPECT_NEAR(half(7, 2, 0), 3.5f, tolerance) << name;
        EXPECT_NEAR(half(7, 2, 1), 0.5f, tolerance) << name;
        EXPECT_NEAR(half(3, 3, 2), 0.125f, tolerance) << name;
    }
    // A grey EXR channel becomes R16F.
    TestImage grey = makeImage(4, 4, 1);
    for (size_t i = 0; i < grey.pixels.size(); ++i)
        grey.pixels[i] = float(i) * 10.0f;
    IrImage greyIr = write("grey.exr", grey, OIIO::TypeDesc::HALF);
    ProcessedTexture g = processOne(requestFor(greyIr));
    EXPECT_EQ(g.desc.format, TextureFormat::R16F);
    EXPECT_EQ(g.desc.swizzle, swz(Sw::R, Sw::R, Sw::R, Sw::One));
}

TEST(TextureQuantize, HalfAndSrgbConversions) {
    for (float v : {0.0f, 1.0f, -2.5f, 0.333f, 65504.0f, 6.1e-5f, 3.0e-7f, 1000.25f}) {
        float back = detail::halfToFloat(detail::floatToHalf(v));
        EXPECT_NEAR(back, v, std::abs(v) * 1e-3f + 6e-8f) << v;
    }
    EXPECT_EQ(detail::floatToHalf(1.0f), 0x3C00);
    EXPECT_EQ(detail::floatToHalf(1e9f), 0x7BFF); // clamped to the largest finite half
    EXPECT_EQ(detail::floatToHalf(std::nanf("")), 0x0000);
    for (int k = 0; k < 256; ++k)
        ASSERT_EQ(detail::quantizeSrgb8(detail::srgbToLinear(float(k) / 255.0f)), k);
    for (int i = 0; i <= 200000; ++i) { // the table-driven encoder against the formula
        float v = float(i) / 200000.0f;
        double exact = detail::linearToSrgb(v) * 255.0;
        if (std::abs(exact - std::floor(exact) - 0.5) < 1e-3) continue; // float ties
        ASSERT_EQ(detail::quantizeSrgb8(v), int(std::floor(exact + 0.5))) << v;
    }
    EXPECT_EQ(detail::quantizeSrgb8(0.5f), 188);
    EXPECT_EQ(detail::quantizeSrgb8(2.0f), 255);
    EXPECT_EQ(detail::quantizeSrgb8(-1.0f), 0);
    EXPECT_EQ(detail::quantizeUnorm8(0.5f), 128);
}

// [SECTION] errors

TEST_F(TextureProcessing, ErrorsNameTheImage) {
    auto expectError = [](const IrImage& ir, const std::string& needle, TextureSettings s = {}) {
        s.jobs = 1; // on this thread, for PNB_IGNORE_OIIO_LEAKS
        PNB_IGNORE_OIIO_LEAKS;
        auto r = processTextures({requestFor(ir)}, s);
        ASSERT_FALSE(r.ok()) << ir.name;
        EXPECT_EQ(r.error().kind, ConvertErrorKind::Input);
        EXPECT_NE(r.error().message.find("'" + ir.name + "'"), std::string::npos)
            << r.error().message;
        EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
    };
    IrImage missing;
    missing.name = "lost_albedo";
    missing.path = (mDir / "does_not_exist.png").string();
    expectError(missing, "not found");

    IrImage garbage;
    garbage.name = "garbage_png";
    garbage.mimeType = "image/png";
    garbage.encoded.assign(300, 0x5A);
    expectError(garbage, "cannot decode");
    garbage.name = "garbage_unknown";
    garbage.mimeType.clear();
    expectError(garbage, "unrecognised");
    IrImage truncated; // a real PNG cut short: the header decodes, the pixels do not
    TestImage big = makeImage(64, 64, 3);
    for (size_t i = 0; i < big.pixels.size(); ++i)
        big.pixels[i] = float((i * 7919) % 256) / 255.0f;
    truncated.encoded = readFile(write("truncated.png", big).path);
    truncated.encoded.resize(truncated.encoded.size() / 2);
    truncated.name = "truncated_png";
    expectError(truncated, "cannot");

    IrImage zero; // an 18-byte TGA header declaring 0×0 texels
    zero.name = "zero.tga";
    zero.encoded.assign(18, 0);
    zero.encoded[2] = 2;   // uncompressed true-colour
    zero.encoded[16] = 32; // bits per pixel
    expectError(zero, "zero size");

    IrImage ok = write("limit.png", big);
    TextureSettings limit;
    limit.maxSourceTexels = 1000;
    expectError(ok, "exceeds the limit", limit);
    limit.maxSourceTexels = 64 * 64;
    EXPECT_TRUE(processTextures({requestFor(ok)}, limit).ok());

    // With several failures, the lowest-indexed request's error is reported, for any jobs.
    for (uint32_t jobs : {1u, 4u}) {
        TextureSettings s;
        s.jobs = jobs;
        auto r = processTextures({requestFor(ok), requestFor(garbage), requestFor(missing)}, s);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().message.find("garbage_unknown"), std::string::npos);
    }
}

// [SECTION] determinism

TEST_F(TextureProcessing, OutputDoesNotDependOnJobs) {
    std::vector<IrImage> images;
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 10; ++i) {
        int w = 20 + i * 7, h = 33 - i * 2;
        TestImage img = makeImage(w, h, i % 2 ? 4 : 3);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < img.channels; ++c)
                    img.at(x, y, c) = 0.5f + 0.4f * std::sin(float(x * (c + 1) + y * i) * 0.2f) *
                                                 (0.8f + 0.2f * u(rng));
        images.push_back(write("det" + std::to_string(i) + ".png", img));
    }
    std::vector<TextureRequest> requests;
    for (size_t i = 0; i < images.size(); ++i) {
        TextureRequest r = requestFor(images[i], i % 3 ? ColorSpace::Srgb : ColorSpace::Linear);
        r.alphaMask = i % 4 == 1;
        requests.push_back(r);
    }
    for (bool compress : {false, true}) {
        TextureSettings s;
        s.compress = compress;
        s.maxSize = 48;
        s.jobs = 1;
        auto one = processTextures(requests, s);
        s.jobs = 8;
        auto eight = processTextures(requests, s);
        ASSERT_TRUE(one.ok() && eight.ok());
        ASSERT_EQ(one->size(), requests.size());
        for (size_t i = 0; i < requests.size(); ++i) {
            EXPECT_EQ(encodeChunk((*one)[i].desc), encodeChunk((*eight)[i].desc)) << i;
            EXPECT_EQ((*one)[i].levels, (*eight)[i].levels) << i;
            EXPECT_EQ((*one)[i].psnrDb, (*eight)[i].psnrDb) << i;
        }
    }
    // No requests: no work, no threads.
    auto none = processTextures({}, {});
    ASSERT_TRUE(none.ok());
    EXPECT_TRUE(none->empty());
}

} // namespace
