// pnb_image_write: every PNG and EXR is read back with OpenImageIO (libpng / OpenEXR underneath,
// which check CRCs, zlib checksums and the EXR header) and compared sample by sample.

#include "pnb_player/image_write.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;
using pnb::FormatError;
using pnb::player::ImageView;

namespace {

// A fresh directory per test, removed afterwards.
class ImageWrite : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_image_write_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    std::string path(const std::string& name) const { return (dir / name).string(); }

    // Names of the entries in the test directory (to spot leftover temporaries).
    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
        return names;
    }

    fs::path dir;
};

std::vector<uint8_t> noise(size_t n, uint32_t seed) {
    std::vector<uint8_t> v(n);
    uint32_t s = seed * 2654435761u + 1;
    for (auto& b : v) {
        s = s * 1664525u + 1013904223u;
        b = uint8_t(s >> 24);
    }
    return v;
}

struct Pixels8 {
    uint32_t width = 0, height = 0, channels = 0;
    std::vector<uint8_t> samples;
};

Pixels8 readU8(const std::string& file) {
    Pixels8 p;
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1); // alpha exactly as stored, not premultiplied
    auto in = OIIO::ImageInput::open(file, &config);
    if (!in) {
        ADD_FAILURE() << "OpenImageIO cannot open " << file << ": " << OIIO::geterror();
        return p;
    }
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_STREQ(in->format_name(), "png");
    EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
    p.width = uint32_t(spec.width);
    p.height = uint32_t(spec.height);
    p.channels = uint32_t(spec.nchannels);
    p.samples.resize(size_t(spec.width) * spec.height * spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, p.samples.data()))
        << in->geterror();
    return p;
}

struct PixelsF {
    uint32_t width = 0, height = 0;
    std::vector<std::string> names; // as OpenImageIO reports them
    std::vector<float> samples;
    std::string compression;
};

PixelsF readF32(const std::string& file) {
    PixelsF p;
    auto in = OIIO::ImageInput::open(file);
    if (!in) {
        ADD_FAILURE() << "OpenImageIO cannot open " << file << ": " << OIIO::geterror();
        return p;
    }
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_STREQ(in->format_name(), "openexr");
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    for (int c = 0; c < spec.nchannels; ++c)
        EXPECT_EQ(spec.channelformat(c), OIIO::TypeDesc::FLOAT) << c;
    p.width = uint32_t(spec.width);
    p.height = uint32_t(spec.height);
    p.names = spec.channelnames;
    p.compression = spec.get_string_attribute("compression");
    p.samples.resize(size_t(spec.width) * spec.height * spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, p.samples.data()))
        << in->geterror();
    EXPECT_EQ(spec.x, 0);
    EXPECT_EQ(spec.y, 0);
    EXPECT_EQ(spec.full_width, spec.width);
    EXPECT_EQ(spec.full_height, spec.height);
    return p;
}

void expectPngRoundTrip(const std::string& file, uint32_t w, uint32_t h, uint32_t c,
                        const std::vector<uint8_t>& samples) {
    ImageView view{w, h, c, samples, {}};
    pnb::Status s = pnb::player::writePng(file, view);
    ASSERT_TRUE(pnb::isOk(s)) << s.describe();
    Pixels8 back = readU8(file);
    ASSERT_EQ(back.width, w);
    ASSERT_EQ(back.height, h);
    ASSERT_EQ(back.channels, c);
    ASSERT_EQ(back.samples.size(), samples.size());
    for (size_t i = 0; i < samples.size(); ++i)
        ASSERT_EQ(back.samples[i], samples[i]) << file << " sample " << i;
}

uint32_t bits(float f) {
    uint32_t b;
    std::memcpy(&b, &f, 4);
    return b;
}

const std::vector<std::string> kExrNames[5] = {
    {}, {"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};

void expectExrRoundTrip(const std::string& file, uint32_t w, uint32_t h, uint32_t c,
                        const std::vector<float>& samples) {
    ImageView view{w, h, c, {}, samples};
    pnb::Status s = pnb::player::writeExr(file, view);
    ASSERT_TRUE(pnb::isOk(s)) << s.describe();
    PixelsF back = readF32(file);
    ASSERT_EQ(back.width, w);
    ASSERT_EQ(back.height, h);
    ASSERT_EQ(back.names.size(), c);
    EXPECT_EQ(back.compression, "none");
    // OpenImageIO may present the channels in another order: match them by name.
    std::vector<std::string> sorted = back.names, expected = kExrNames[c];
    std::sort(sorted.begin(), sorted.end());
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(sorted, expected);
    for (uint32_t ic = 0; ic < c; ++ic) {
        const std::string& name = kExrNames[c][ic];
        size_t bc = size_t(std::find(back.names.begin(), back.names.end(), name) -
                           back.names.begin());
        for (size_t px = 0; px < size_t(w) * h; ++px) {
            float want = samples[px * c + ic], got = back.samples[px * c + bc];
            ASSERT_EQ(bits(got), bits(want))
                << file << " channel " << name << " pixel " << px << ": " << got << " vs " << want;
        }
    }
}

// Channel names in file order, parsed from the encoded header's chlist.
std::vector<std::string> chlistNames(const std::vector<uint8_t>& exr) {
    std::vector<std::string> names;
    const std::string key("channels\0chlist\0", 16);
    auto it = std::search(exr.begin(), exr.end(), key.begin(), key.end());
    if (it == exr.end()) return names;
    size_t pos = size_t(it - exr.begin()) + key.size() + 4; // skip the attribute size
    while (pos < exr.size() && exr[pos] != 0) {
        std::string name(reinterpret_cast<const char*>(&exr[pos]));
        names.push_back(name);
        pos += name.size() + 1 + 16; // name, type, pLinear + reserved, x/y sampling
    }
    return names;
}

TEST_F(ImageWrite, PngAllChannelCountsOddSizes) {
    for (uint32_t c = 1; c <= 4; ++c) {
        for (auto [w, h] : {std::pair<uint32_t, uint32_t>{7, 5}, {1, 1}, {1, 9}, {13, 1}}) {
            SCOPED_TRACE(testing::Message() << w << "x" << h << "x" << c);
            auto samples = noise(size_t(w) * h * c, w * 100 + h * 10 + c);
            expectPngRoundTrip(path("noise_" + std::to_string(c) + ".png"), w, h, c, samples);
        }
    }
}

TEST_F(ImageWrite, PngGradient300x200) {
    const uint32_t w = 300, h = 200;
    for (uint32_t c = 1; c <= 4; ++c) {
        SCOPED_TRACE(c);
        std::vector<uint8_t> samples(size_t(w) * h * c);
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                uint8_t* p = &samples[(size_t(y) * w + x) * c];
                const uint8_t v[4] = {uint8_t(x * 255 / (w - 1)), uint8_t(y * 255 / (h - 1)),
                                      uint8_t((x + 2 * y) & 255), uint8_t(255 - (x ^ y))};
                for (uint32_t k = 0; k < c; ++k) p[k] = v[k];
            }
        expectPngRoundTrip(path("gradient.png"), w, h, c, samples);
    }
}

TEST_F(ImageWrite, PngScreenshotSized) {
    // 1280 x 720 RGBA, a smooth picture with noisy patches (rows pick different filters), and
    // one very wide row (500 000 RGB pixels; libpng reads at most 1 000 000 per row).
    const uint32_t w = 1280, h = 720;
    std::vector<uint8_t> samples(size_t(w) * h * 4);
    auto grain = noise(samples.size(), 7);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            uint8_t* p = &samples[(size_t(y) * w + x) * 4];
            const size_t i = size_t(y) * w + x;
            const bool noisy = ((x / 160) + (y / 90)) % 3 == 0;
            p[0] = noisy ? grain[i * 4] : uint8_t(x * 255 / (w - 1));
            p[1] = noisy ? grain[i * 4 + 1] : uint8_t(y * 255 / (h - 1));
            p[2] = uint8_t((x + y) / 8);
            p[3] = 255;
        }
    expectPngRoundTrip(path("screenshot.png"), w, h, 4, samples);
    auto wide = noise(size_t(500000) * 3, 9);
    expectPngRoundTrip(path("wide.png"), 500000, 1, 3, wide);
}

TEST_F(ImageWrite, PngOfFlatImageIsSmall) {
    const uint32_t w = 512, h = 256, c = 4;
    std::vector<uint8_t> samples(size_t(w) * h * c);
    for (size_t i = 0; i < samples.size(); i += 4) {
        samples[i] = 40;
        samples[i + 1] = 90;
        samples[i + 2] = 200;
        samples[i + 3] = 255;
    }
    auto png = pnb::player::encodePng({w, h, c, samples, {}});
    ASSERT_FALSE(png.empty());
    EXPECT_LT(png.size(), samples.size() / 200) << png.size() << " bytes for a flat image";
    expectPngRoundTrip(path("flat.png"), w, h, c, samples);
}

TEST_F(ImageWrite, PngStartsWithSignatureAndIsDeterministic) {
    auto samples = noise(7 * 5 * 3, 42);
    ImageView view{7, 5, 3, samples, {}};
    auto a = pnb::player::encodePng(view), b = pnb::player::encodePng(view);
    ASSERT_GE(a.size(), 8u);
    const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    EXPECT_EQ(std::memcmp(a.data(), signature, 8), 0);
    EXPECT_EQ(a, b);
    // The file is exactly what the encoder produces.
    ASSERT_TRUE(pnb::isOk(pnb::player::writePng(path("a.png"), view)));
    std::ifstream f(path("a.png"), std::ios::binary);
    std::vector<uint8_t> onDisk((std::istreambuf_iterator<char>(f)), {});
    EXPECT_EQ(onDisk, a);
}

std::vector<float> specialFloats(size_t n, uint32_t seed) {
    static const float kValues[] = {0.0f,   -0.0f,   1.0f,    -1.0f,  0.5f,     -0.25f,
                                    1e-8f,  -1e-8f,  65504.f, -65504.f, 1e30f,  -1e30f,
                                    3.14159265f,     1e-40f /*denormal*/,
                                    std::numeric_limits<float>::max(),
                                    std::numeric_limits<float>::lowest(),
                                    std::numeric_limits<float>::infinity(),
                                    -std::numeric_limits<float>::infinity()};
    constexpr size_t kCount = sizeof(kValues) / sizeof(kValues[0]);
    std::vector<float> v(n);
    auto mix = noise(n, seed);
    for (size_t i = 0; i < n; ++i)
        v[i] = i < kCount ? kValues[i] : kValues[mix[i] % kCount] * float(1 + mix[i] % 7);
    return v;
}

TEST_F(ImageWrite, ExrRoundTripExactFloats) {
    for (uint32_t c : {1u, 2u, 3u, 4u}) {
        for (auto [w, h] : {std::pair<uint32_t, uint32_t>{7, 5}, {1, 1}, {64, 3}, {3, 64}}) {
            SCOPED_TRACE(testing::Message() << w << "x" << h << "x" << c);
            auto samples = specialFloats(size_t(w) * h * c, w + h + c);
            expectExrRoundTrip(path("img_" + std::to_string(c) + ".exr"), w, h, c, samples);
        }
    }
}

TEST_F(ImageWrite, ExrRoundTripNaN) {
    // NaN is stored bit-exactly too (OpenEXR passes float channels through), payload and sign
    // included: an error, not a crash, is never the answer to a NaN.
    auto fromBits = [](uint32_t b) {
        float f;
        std::memcpy(&f, &b, 4);
        return f;
    };
    std::vector<float> samples = {std::numeric_limits<float>::quiet_NaN(), 1.0f, 2.0f,
                                  fromBits(0x7fc12345u), fromBits(0xffc00001u),
                                  -std::numeric_limits<float>::quiet_NaN()};
    expectExrRoundTrip(path("nan.exr"), 2, 1, 3, samples);
}

TEST_F(ImageWrite, ExrChannelsAreAlphabeticalInTheFile) {
    const std::vector<std::string> expected[5] = {
        {}, {"Y"}, {"A", "Y"}, {"B", "G", "R"}, {"A", "B", "G", "R"}};
    for (uint32_t c = 1; c <= 4; ++c) {
        std::vector<float> samples(2 * 2 * c, 0.5f);
        auto exr = pnb::player::encodeExr({2, 2, c, {}, samples});
        ASSERT_FALSE(exr.empty());
        EXPECT_EQ(chlistNames(exr), expected[c]) << c << " channels";
        // Magic and version 2 with no flags (single-part scanline).
        const uint8_t head[8] = {0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0};
        EXPECT_EQ(std::memcmp(exr.data(), head, 8), 0);
    }
    // And an RGBA image reads back with each value under its own name.
    std::vector<float> rgba = {1.0f, 2.0f, 3.0f, 4.0f};
    ASSERT_TRUE(pnb::isOk(pnb::player::writeExr(path("rgba.exr"), {1, 1, 4, {}, rgba})));
    PixelsF back = readF32(path("rgba.exr"));
    ASSERT_EQ(back.names.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
        float want = back.names[i] == "R"   ? 1.0f
                     : back.names[i] == "G" ? 2.0f
                     : back.names[i] == "B" ? 3.0f
                                            : 4.0f;
        EXPECT_EQ(back.samples[i], want) << back.names[i];
    }
}

// The header's attributes in file order: name, type, and value bytes.
struct ExrAttribute {
    std::string name, type;
    std::vector<uint8_t> value;
};

std::vector<ExrAttribute> exrHeader(const std::vector<uint8_t>& exr, size_t& end) {
    std::vector<ExrAttribute> attributes;
    size_t pos = 8; // magic, version
    auto cstring = [&](std::string& out) {
        size_t zero = pos;
        while (zero < exr.size() && exr[zero] != 0) ++zero;
        if (zero >= exr.size()) return false;
        out.assign(reinterpret_cast<const char*>(&exr[pos]), zero - pos);
        pos = zero + 1;
        return true;
    };
    while (pos < exr.size() && exr[pos] != 0) {
        ExrAttribute a;
        if (!cstring(a.name) || !cstring(a.type) || exr.size() - pos < 4) break;
        uint32_t size = uint32_t(exr[pos]) | uint32_t(exr[pos + 1]) << 8 |
                        uint32_t(exr[pos + 2]) << 16 | uint32_t(exr[pos + 3]) << 24;
        pos += 4;
        if (exr.size() - pos < size) break;
        a.value.assign(exr.begin() + long(pos), exr.begin() + long(pos + size));
        pos += size;
        attributes.push_back(std::move(a));
    }
    end = pos + 1; // past the header's terminating null
    return attributes;
}

TEST_F(ImageWrite, ExrHeaderHoldsExactlyTheRequiredAttributes) {
    // What pnb-reference, the sweep scripts and the tests were written against: the eight
    // required attributes, no compression, increasing Y, FLOAT channels, windows = the image.
    std::vector<float> samples(5 * 3 * 4, 0.25f);
    auto exr = pnb::player::encodeExr({5, 3, 4, {}, samples});
    ASSERT_FALSE(exr.empty());
    size_t end = 0;
    auto attributes = exrHeader(exr, end);
    std::vector<std::string> names;
    for (const auto& a : attributes) names.push_back(a.name + ":" + a.type);
    EXPECT_EQ(names, (std::vector<std::string>{
                         "channels:chlist", "compression:compression", "dataWindow:box2i",
                         "displayWindow:box2i", "lineOrder:lineOrder", "pixelAspectRatio:float",
                         "screenWindowCenter:v2f", "screenWindowWidth:float"}));
    ASSERT_EQ(attributes.size(), 8u);
    // chlist: per channel name\0, int pixel type 2 (FLOAT), pLinear 0 + 3 reserved, x/y sampling 1.
    std::vector<uint8_t> chlist;
    for (const char* name : {"A", "B", "G", "R"}) {
        chlist.insert(chlist.end(), {uint8_t(name[0]), 0, 2, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    }
    chlist.push_back(0);
    EXPECT_EQ(attributes[0].value, chlist);
    EXPECT_EQ(attributes[1].value, std::vector<uint8_t>{0}) << "NO_COMPRESSION";
    const std::vector<uint8_t> window = {0, 0, 0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 2, 0, 0, 0};
    EXPECT_EQ(attributes[2].value, window);
    EXPECT_EQ(attributes[3].value, window);
    EXPECT_EQ(attributes[4].value, std::vector<uint8_t>{0}) << "INCREASING_Y";
    // Then 3 line offsets and 3 blocks of 8 + 4 channels * 5 px * 4 bytes: nothing else.
    EXPECT_EQ(exr.size(), end + 3 * 8 + 3 * (8 + 80));
}

TEST_F(ImageWrite, ExrLayoutIsExactlyAsSpecified) {
    // 3x2 RGB: header, 2 offsets, 2 blocks of (4 + 4 + 3 channels * 3 px * 4 bytes).
    std::vector<float> samples(3 * 2 * 3);
    for (size_t i = 0; i < samples.size(); ++i) samples[i] = float(i);
    auto exr = pnb::player::encodeExr({3, 2, 3, {}, samples});
    ASSERT_GT(exr.size(), 2 * (8 + 36u));
    const size_t blocks = 2 * (8 + 36);
    const size_t table = exr.size() - blocks - 16;
    auto le32 = [&](size_t at) {
        return uint32_t(exr[at]) | uint32_t(exr[at + 1]) << 8 | uint32_t(exr[at + 2]) << 16 |
               uint32_t(exr[at + 3]) << 24;
    };
    EXPECT_EQ(exr[table - 1], 0) << "header ends with a null byte";
    EXPECT_EQ(le32(table), table + 16);
    EXPECT_EQ(le32(table + 8), table + 16 + 44);
    for (uint32_t y = 0; y < 2; ++y) {
        size_t block = table + 16 + y * 44;
        EXPECT_EQ(le32(block), y);
        EXPECT_EQ(le32(block + 4), 36u);
        // B row, G row, R row.
        for (uint32_t ch = 0; ch < 3; ++ch)
            for (uint32_t x = 0; x < 3; ++x) {
                float v;
                uint32_t b = le32(block + 8 + (ch * 3 + x) * 4);
                std::memcpy(&v, &b, 4);
                EXPECT_EQ(v, samples[(y * 3 + x) * 3 + (2 - ch)]) << y << " " << ch << " " << x;
            }
    }
}

TEST_F(ImageWrite, BadViewsAreErrors) {
    std::vector<uint8_t> u8(7 * 5 * 3, 1);
    std::vector<float> f32(7 * 5 * 3, 1.0f);
    struct Case {
        const char* what;
        ImageView view;
        bool exr;
        const char* mentions;
    };
    const Case cases[] = {
        {"zero width", {0, 5, 3, u8, {}}, false, "non-zero"},
        {"zero height", {7, 0, 3, u8, {}}, false, "non-zero"},
        {"zero channels", {7, 5, 0, u8, {}}, false, "channels"},
        {"five channels", {7, 5, 5, u8, {}}, false, "channels"},
        {"too few samples", {7, 5, 4, u8, {}}, false, "expected"},
        {"too many samples", {7, 4, 3, u8, {}}, false, "expected"},
        {"f32 for PNG", {7, 5, 3, {}, f32}, false, "u8"},
        {"no samples", {7, 5, 3, {}, {}}, false, "none"},
        {"both spans", {7, 5, 3, u8, f32}, false, "both"},
        {"huge", {0xffffffffu, 0xffffffffu, 4, u8, {}}, false, "overflow"},
        {"zero width", {0, 5, 3, {}, f32}, true, "non-zero"},
        {"zero channels", {7, 5, 0, {}, f32}, true, "channels"},
        {"five channels", {7, 5, 5, {}, f32}, true, "channels"},
        {"wrong count", {5, 5, 3, {}, f32}, true, "expected"},
        {"u8 for EXR", {7, 5, 3, u8, {}}, true, "f32"},
        {"both spans", {7, 5, 3, u8, f32}, true, "both"},
        {"wide", {0x80000000u, 1, 1, {}, f32}, true, "expected"},
        // Sizes beyond the formats' limits. The spans claim more samples than exist; the checks
        // reject them from the dimensions alone and never read the samples.
        {"PNG width", {0x80000000u, 1, 1, {u8.data(), 0x80000000u}, {}}, false, "2^31-1"},
        {"EXR width", {0x80000000u, 1, 1, {}, {f32.data(), 0x80000000u}}, true, "2^31-1"},
        {"EXR scanline", {0x20000000u, 1, 4, {}, {f32.data(), 0x80000000u}}, true, "block"},
        // stb_image_write counts in int: rows up to 16 MiB, scanlines up to 2 GiB - 16 MiB.
        {"PNG row", {0x01000000u, 1, 1, {u8.data(), 0x01000000u}, {}}, false, "per row"},
        {"PNG scanlines", {0x4000u, 0x20000u, 1, {u8.data(), size_t(0x4000u) * 0x20000u}, {}},
         false, "2 GiB"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        std::string file = path(c.exr ? "bad.exr" : "bad.png");
        pnb::Status s = c.exr ? pnb::player::writeExr(file, c.view)
                              : pnb::player::writePng(file, c.view);
        EXPECT_FALSE(pnb::isOk(s));
        EXPECT_TRUE(s.code == FormatError::BadPayload || s.code == FormatError::LimitExceeded)
            << pnb::toString(s.code);
        EXPECT_NE(s.message.find(c.mentions), std::string::npos) << s.message;
        EXPECT_NE(s.message.find(c.exr ? "EXR" : "PNG"), std::string::npos) << s.message;
        pnb::Status check = c.exr ? pnb::player::checkExrImage(c.view)
                                  : pnb::player::checkPngImage(c.view);
        EXPECT_EQ(check.message, s.message);
        auto bytes = c.exr ? pnb::player::encodeExr(c.view) : pnb::player::encodePng(c.view);
        EXPECT_TRUE(bytes.empty());
        EXPECT_FALSE(fs::exists(file));
    }
    EXPECT_TRUE(entries().empty());
}

TEST_F(ImageWrite, MissingDirectoryIsAnErrorAndLeavesNothing) {
    std::vector<uint8_t> u8(4 * 4 * 3, 7);
    std::vector<float> f32(4 * 4 * 3, 0.5f);
    pnb::Status s = pnb::player::writePng(path("no_such_dir/out.png"), {4, 4, 3, u8, {}});
    EXPECT_EQ(s.code, FormatError::IoError) << s.describe();
    EXPECT_NE(s.message.find("no_such_dir/out.png"), std::string::npos) << s.message;
    s = pnb::player::writeExr(path("no_such_dir/out.exr"), {4, 4, 3, {}, f32});
    EXPECT_EQ(s.code, FormatError::IoError) << s.describe();
    s = pnb::player::writePng("", {4, 4, 3, u8, {}});
    EXPECT_EQ(s.code, FormatError::IoError) << s.describe();
    EXPECT_TRUE(entries().empty());
    EXPECT_FALSE(fs::exists(dir / "no_such_dir"));
}

TEST_F(ImageWrite, FailedRenameRemovesTheTemporary) {
    // The target is a non-empty directory: the temporary is written, the rename fails, and the
    // temporary must be gone afterwards.
    fs::create_directories(dir / "target.png" / "child");
    std::vector<uint8_t> u8(4 * 4 * 3, 7);
    pnb::Status s = pnb::player::writePng(path("target.png"), {4, 4, 3, u8, {}});
    EXPECT_EQ(s.code, FormatError::IoError) << s.describe();
    EXPECT_EQ(entries(), std::vector<std::string>{"target.png"});
    EXPECT_TRUE(fs::is_directory(dir / "target.png" / "child"));
}

TEST_F(ImageWrite, ReplacesAnExistingFileAtomically) {
    {
        std::ofstream old(path("out.png"));
        old << "previous contents";
    }
    fs::permissions(path("out.png"), fs::perms::owner_read | fs::perms::owner_write);
    auto samples = noise(5 * 3 * 4, 3);
    expectPngRoundTrip(path("out.png"), 5, 3, 4, samples);
    EXPECT_EQ(entries(), std::vector<std::string>{"out.png"});
    // Permissions of the replaced file are kept.
    EXPECT_EQ(fs::status(path("out.png")).permissions() & fs::perms::all,
              fs::perms::owner_read | fs::perms::owner_write);
}

TEST_F(ImageWrite, WriteFileAtomicWritesBytes) {
    const std::vector<uint8_t> bytes = {1, 2, 3, 0, 255};
    ASSERT_TRUE(pnb::isOk(pnb::writeFileAtomic(path("raw.bin"), bytes)));
    std::ifstream f(path("raw.bin"), std::ios::binary);
    std::vector<uint8_t> back((std::istreambuf_iterator<char>(f)), {});
    EXPECT_EQ(back, bytes);
    ASSERT_TRUE(pnb::isOk(pnb::writeFileAtomic(path("empty.bin"), {})));
    EXPECT_EQ(fs::file_size(path("empty.bin")), 0u);
}

} // namespace
