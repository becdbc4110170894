// PNG and JPEG are decoded in-process (converter/src/image_decode_png.cpp, image_decode_jpeg.cpp)
// instead of through the OpenImageIO module. They must give exactly what the module gives —
// width, height, source channels and every float texel bit for bit — so that a container does
// not change with the decoder: checked on every PNG and JPEG of Debian's assimp test models and
// on generated files covering each PNG colour type and bit depth, tRNS, interlacing, and JPEG
// greyscale, chroma subsampling and progressive coding. Malformed files fail with an error naming
// the image, and a file whose header declares too much is refused before its pixels are read.

#include <gtest/gtest.h>

#include <jpeglib.h>
#include <png.h>
#include <zlib.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "texture_internal.h"

#include "oiio_leak_guard.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;
namespace detail = pnb::converter::texture_detail;

constexpr uint64_t kNoLimit = uint64_t(1) << 40;

// [SECTION] writers for the generated files

struct PngSpec {
    int colorType, bitDepth;
    bool interlaced = false;
    bool trns = false;
    uint32_t width = 13, height = 7;
};

std::vector<uint8_t> writePng(const PngSpec& spec) {
    std::vector<uint8_t> out;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        ADD_FAILURE() << "libpng could not write the test image";
        return {};
    }
    png_set_write_fn(
        png, &out,
        [](png_structp p, png_bytep data, size_t n) {
            auto* v = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(p));
            v->insert(v->end(), data, data + n);
        },
        nullptr);
    png_set_IHDR(png, info, spec.width, spec.height, spec.bitDepth, spec.colorType,
                 spec.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    const int entries = 1 << std::min(spec.bitDepth, 8);
    std::vector<png_color> palette(size_t(std::min(entries, 256)));
    for (size_t i = 0; i < palette.size(); ++i)
        palette[i] = {png_byte(i * 37), png_byte(255 - i * 11), png_byte(i * 101)};
    if (spec.colorType == PNG_COLOR_TYPE_PALETTE)
        png_set_PLTE(png, info, palette.data(), int(palette.size()));
    std::vector<png_byte> alphas(palette.size());
    for (size_t i = 0; i < alphas.size(); ++i)
        alphas[i] = png_byte(i * 53);
    png_color_16 key{};
    key.gray = 1;
    key.red = 2;
    key.green = 3;
    key.blue = 4;
    if (spec.trns)
        png_set_tRNS(png, info, alphas.data(),
                     spec.colorType == PNG_COLOR_TYPE_PALETTE ? int(alphas.size()) : 0, &key);
    png_write_info(png, info);
    if (spec.bitDepth == 16) png_set_swap(png);
    const int channels = spec.colorType == PNG_COLOR_TYPE_GRAY         ? 1
                         : spec.colorType == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                         : spec.colorType == PNG_COLOR_TYPE_RGB        ? 3
                         : spec.colorType == PNG_COLOR_TYPE_RGBA       ? 4
                                                                       : 1;
    const size_t rowBytes = (size_t(spec.width) * channels * spec.bitDepth + 7) / 8;
    std::vector<std::vector<png_byte>> rows(spec.height, std::vector<png_byte>(rowBytes));
    uint32_t seed = 12345;
    for (auto& row : rows)
        for (auto& b : row) {
            seed = seed * 1664525u + 1013904223u;
            b = png_byte(seed >> 24);
        }
    // Keep palette indices inside the palette.
    if (spec.colorType == PNG_COLOR_TYPE_PALETTE && spec.bitDepth == 8)
        for (auto& row : rows)
            for (auto& b : row)
                b = png_byte(b % palette.size());
    std::vector<png_bytep> pointers;
    for (auto& row : rows)
        pointers.push_back(row.data());
    png_write_image(png, pointers.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return out;
}

struct JpegSpec {
    int components;
    int hSampling = 1, vSampling = 1; // of the first (luma) component
    bool progressive = false;
    uint32_t width = 37, height = 19;
};

std::vector<uint8_t> writeJpeg(const JpegSpec& spec) {
    jpeg_compress_struct cinfo{};
    jpeg_error_mgr err{};
    cinfo.err = jpeg_std_error(&err);
    jpeg_create_compress(&cinfo);
    unsigned char* buffer = nullptr;
    unsigned long size = 0;
    jpeg_mem_dest(&cinfo, &buffer, &size);
    cinfo.image_width = spec.width;
    cinfo.image_height = spec.height;
    cinfo.input_components = spec.components;
    cinfo.in_color_space = spec.components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(&cinfo);
    jpeg_set_quality(&cinfo, 85, TRUE);
    if (spec.components == 3) {
        cinfo.comp_info[0].h_samp_factor = spec.hSampling;
        cinfo.comp_info[0].v_samp_factor = spec.vSampling;
    }
    if (spec.progressive) jpeg_simple_progression(&cinfo);
    jpeg_start_compress(&cinfo, TRUE);
    std::vector<uint8_t> row(size_t(spec.width) * spec.components);
    while (cinfo.next_scanline < cinfo.image_height) {
        for (size_t i = 0; i < row.size(); ++i)
            row[i] = uint8_t((i * 7 + cinfo.next_scanline * 13) ^ (i / 3));
        JSAMPROW r = row.data();
        jpeg_write_scanlines(&cinfo, &r, 1);
    }
    jpeg_finish_compress(&cinfo);
    std::vector<uint8_t> out(buffer, buffer + size);
    jpeg_destroy_compress(&cinfo);
    std::free(buffer);
    return out;
}

// [SECTION] comparison

IrImage embedded(const std::string& name, std::vector<uint8_t> bytes) {
    IrImage image;
    image.name = name;
    image.encoded = std::move(bytes);
    return image;
}

// The native decoder took the image (decodeImage never reached the module) and matched it.
void expectSameAsModule(const IrImage& image) {
    SCOPED_TRACE(detail::describeImage(image));
    std::vector<uint8_t> bytes = image.encoded;
    if (!image.path.empty()) {
        std::FILE* f = std::fopen(image.path.c_str(), "rb");
        ASSERT_TRUE(f);
        int c;
        while ((c = std::fgetc(f)) != EOF)
            bytes.push_back(uint8_t(c));
        std::fclose(f);
    }
    auto png = detail::decodePng(image, bytes, kNoLimit, {});
    auto native = png ? std::move(png) : detail::decodeJpeg(image, bytes, kNoLimit, {});
    ASSERT_TRUE(native.has_value()) << "not taken by a native decoder";
    PNB_IGNORE_OIIO_LEAKS;
    auto module = detail::decodeImageWithModule(image, kNoLimit, {});
    ASSERT_TRUE(module.ok()) << module.error().message;
    ASSERT_TRUE(native->ok()) << native->error().message;
    const detail::DecodedImage& a = **native;
    const detail::DecodedImage& b = *module;
    EXPECT_EQ(a.image.width, b.image.width);
    EXPECT_EQ(a.image.height, b.image.height);
    EXPECT_EQ(a.sourceChannels, b.sourceChannels);
    EXPECT_EQ(a.floatSource, b.floatSource);
    ASSERT_EQ(a.image.texels.size(), b.image.texels.size());
    size_t differing = 0, first = 0;
    for (size_t i = 0; i < a.image.texels.size(); ++i)
        if (std::memcmp(&a.image.texels[i], &b.image.texels[i], sizeof(float)) != 0 &&
            differing++ == 0)
            first = i;
    EXPECT_EQ(differing, 0u) << "first at float " << first << ": " << a.image.texels[first]
                             << " vs the module's " << b.image.texels[first];
}

TEST(ImageDecodeNative, EveryPngAndJpegOfTheAssimpTestModelsMatchesTheModule) {
    const fs::path corpus = "/usr/share/assimp/models";
    if (!fs::exists(corpus)) GTEST_SKIP() << corpus << " missing (assimp-testmodels)";
    int checked = 0;
    for (const auto& entry : fs::recursive_directory_iterator(corpus)) {
        if (!entry.is_regular_file()) continue;
        std::string ext = entry.path().extension().string();
        for (char& c : ext)
            c = char(std::tolower(static_cast<unsigned char>(c)));
        if (ext != ".png" && ext != ".jpg" && ext != ".jpeg") continue;
        IrImage image;
        image.name = entry.path().filename().string();
        image.path = entry.path().string();
        // Files the module cannot read either (the corpus has deliberately broken ones) must
        // fail natively too.
        PNB_IGNORE_OIIO_LEAKS;
        auto module = detail::decodeImageWithModule(image, kNoLimit, {});
        if (!module.ok()) {
            EXPECT_FALSE(detail::decodeImage(image, kNoLimit, {}).ok()) << image.path;
            continue;
        }
        expectSameAsModule(image);
        ++checked;
    }
    EXPECT_GE(checked, 20) << "the corpus should hold at least 20 PNG/JPEG textures";
}

TEST(ImageDecodeNative, EveryPngColourTypeAndBitDepthMatchesTheModule) {
    const std::vector<PngSpec> specs = {
        {PNG_COLOR_TYPE_GRAY, 1},        {PNG_COLOR_TYPE_GRAY, 2},
        {PNG_COLOR_TYPE_GRAY, 4},        {PNG_COLOR_TYPE_GRAY, 8},
        {PNG_COLOR_TYPE_GRAY, 16},       {PNG_COLOR_TYPE_GRAY, 8, false, true},
        {PNG_COLOR_TYPE_GRAY_ALPHA, 8},  {PNG_COLOR_TYPE_GRAY_ALPHA, 16},
        {PNG_COLOR_TYPE_RGB, 8},         {PNG_COLOR_TYPE_RGB, 16},
        {PNG_COLOR_TYPE_RGB, 8, false, true},
        {PNG_COLOR_TYPE_RGBA, 8},        {PNG_COLOR_TYPE_RGBA, 16},
        {PNG_COLOR_TYPE_PALETTE, 1},     {PNG_COLOR_TYPE_PALETTE, 4},
        {PNG_COLOR_TYPE_PALETTE, 8},     {PNG_COLOR_TYPE_PALETTE, 8, false, true},
        {PNG_COLOR_TYPE_RGB, 8, true},   {PNG_COLOR_TYPE_RGBA, 16, true},
        {PNG_COLOR_TYPE_GRAY, 8, false, false, 1, 1},
    };
    for (const PngSpec& s : specs) {
        std::string name = "png-type" + std::to_string(s.colorType) + "-" +
                           std::to_string(s.bitDepth) + (s.interlaced ? "-adam7" : "") +
                           (s.trns ? "-trns" : "") + "-" + std::to_string(s.width) + "x" +
                           std::to_string(s.height);
        expectSameAsModule(embedded(name, writePng(s)));
    }
}

TEST(ImageDecodeNative, JpegGreyscaleSubsampledAndProgressiveMatchTheModule) {
    const std::vector<JpegSpec> specs = {
        {1}, {3, 1, 1}, {3, 2, 1}, {3, 2, 2}, {3, 2, 2, true}, {1, 1, 1, true}, {3, 1, 1, false, 1, 1},
    };
    for (const JpegSpec& s : specs) {
        std::string name = "jpeg-" + std::to_string(s.components) + "c-" +
                           std::to_string(s.hSampling) + "x" + std::to_string(s.vSampling) +
                           (s.progressive ? "-progressive" : "");
        expectSameAsModule(embedded(name, writeJpeg(s)));
    }
}

// [SECTION] errors and limits

TEST(ImageDecodeNative, MalformedFilesFailWithAnErrorNamingTheImage) {
    auto expectError = [](IrImage image, const std::string& needle) {
        auto r = detail::decodeImage(image, kNoLimit, {});
        ASSERT_FALSE(r.ok()) << image.name;
        EXPECT_EQ(r.error().kind, ConvertErrorKind::Input);
        EXPECT_NE(r.error().message.find("'" + image.name + "'"), std::string::npos)
            << r.error().message;
        EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
    };
    std::vector<uint8_t> png = writePng({PNG_COLOR_TYPE_RGB, 8, false, false, 64, 64});
    std::vector<uint8_t> cut(png.begin(), png.begin() + long(png.size() / 2));
    expectError(embedded("half-png", cut), "cannot read the pixels of its declared 64x64");
    std::vector<uint8_t> headerOnly(png.begin(), png.begin() + 20);
    expectError(embedded("png-header-cut", headerOnly), "cannot decode");
    std::vector<uint8_t> crc = png;
    crc[40] ^= 0xFF; // inside the first IDAT chunk: its CRC no longer matches
    expectError(embedded("png-bad-crc", crc), "cannot");
    std::vector<uint8_t> signatureOnly(png.begin(), png.begin() + 8);
    expectError(embedded("png-signature-only", signatureOnly), "cannot decode");

    std::vector<uint8_t> jpeg = writeJpeg({3, 2, 2, false, 64, 64});
    std::vector<uint8_t> jpegCut(jpeg.begin(), jpeg.begin() + long(jpeg.size() / 2));
    expectError(embedded("half-jpeg", jpegCut), "cannot read the pixels of its declared 64x64");
    std::vector<uint8_t> jpegGarbage = {0xFF, 0xD8, 0xFF, 0x00, 0x12, 0x34};
    expectError(embedded("jpeg-garbage", jpegGarbage), "cannot decode");
}

TEST(ImageDecodeNative, LimitsAndAdmissionAreCheckedBeforeThePixels) {
    std::vector<uint8_t> png = writePng({PNG_COLOR_TYPE_RGBA, 8, false, false, 40, 30});
    std::vector<uint8_t> jpeg = writeJpeg({3, 2, 2, false, 40, 30});
    for (const auto& bytes : {png, jpeg}) {
        IrImage image = embedded(bytes == png ? "limited-png" : "limited-jpeg", bytes);
        auto limited = detail::decodeImage(image, 40 * 30 - 1, {});
        ASSERT_FALSE(limited.ok());
        EXPECT_NE(limited.error().message.find("40x30 = 1200 texels exceeds the limit of 1199"),
                  std::string::npos)
            << limited.error().message;
        detail::ImageHeader seen;
        auto refused = detail::decodeImage(image, kNoLimit, [&](const detail::ImageHeader& h) {
            seen = h;
            return std::optional<std::string>("refused by the test");
        });
        ASSERT_FALSE(refused.ok());
        EXPECT_NE(refused.error().message.find("refused by the test"), std::string::npos);
        EXPECT_EQ(seen.width, 40u);
        EXPECT_EQ(seen.height, 30u);
        EXPECT_EQ(seen.channels, bytes == png ? 4u : 3u);
        EXPECT_EQ(seen.bytesPerChannel, 1u);
    }
    // A 70-byte PNG whose (valid) header declares 16000 x 16000 RGBA, 1 GB of pixels: it fails
    // on its missing data, with a message naming the declared size.
    std::vector<uint8_t> tiny = writePng({PNG_COLOR_TYPE_RGBA, 8, false, false, 1, 1});
    for (int at : {16, 20}) { // IHDR width and height, big-endian
        tiny[size_t(at)] = 0;
        tiny[size_t(at) + 1] = 0;
        tiny[size_t(at) + 2] = 16000 >> 8;
        tiny[size_t(at) + 3] = 16000 & 0xFF;
    }
    const uLong crc = crc32(0, tiny.data() + 12, 17); // "IHDR" and its 13 bytes
    for (int i = 0; i < 4; ++i)
        tiny[size_t(29 + i)] = uint8_t(crc >> (24 - 8 * i));
    auto huge = detail::decodeImage(embedded("huge-png", tiny), kNoLimit, {});
    ASSERT_FALSE(huge.ok());
    EXPECT_NE(huge.error().message.find("declared 16000x16000"), std::string::npos)
        << huge.error().message;
}

// Byte flips, truncations and insertions in a PNG and a JPEG: every decode returns (an image or
// an error naming it); under the sanitizers (CI) no out-of-bounds access or leak.
TEST(ImageDecodeNative, MutatedFilesDecodeOrFailCleanly) {
    const std::vector<std::vector<uint8_t>> seeds = {
        writePng({PNG_COLOR_TYPE_PALETTE, 4, true, true, 21, 9}),
        writePng({PNG_COLOR_TYPE_RGBA, 16, false, false, 9, 5}),
        writeJpeg({3, 2, 2, true, 23, 17}),
        writeJpeg({1, 1, 1, false, 16, 8}),
    };
    uint32_t seed = 2026;
    auto next = [&] { return seed = seed * 1664525u + 1013904223u, seed >> 8; };
    int ok = 0, failed = 0;
    for (const auto& original : seeds)
        for (int round = 0; round < 400; ++round) {
            std::vector<uint8_t> bytes = original;
            const int edits = 1 + int(next() % 4);
            for (int e = 0; e < edits && bytes.size() > 8; ++e) {
                const size_t at = 8 + next() % (bytes.size() - 8); // keep the signature
                switch (next() % 3) {
                case 0: bytes[at] = uint8_t(next()); break;
                case 1: bytes.resize(at); break;
                default: bytes.insert(bytes.begin() + long(at), uint8_t(next())); break;
                }
            }
            // The native decoders only: the module (OpenImageIO) leaks on corrupt PNGs
            // (oiio_leak_guard.h).
            const IrImage image = embedded("mutant", bytes);
            auto native = detail::decodePng(image, bytes, uint64_t(1) << 24, {});
            if (!native) native = detail::decodeJpeg(image, bytes, uint64_t(1) << 24, {});
            if (!native) continue; // a JPEG header turned CMYK: the module's
            const auto& r = *native;
            if (r.ok()) {
                ++ok;
                EXPECT_EQ(r->image.texels.size(), r->image.texelCount() * 4);
            } else {
                ++failed;
                EXPECT_NE(r.error().message.find("'mutant'"), std::string::npos);
            }
        }
    EXPECT_GT(failed, 0);
    std::printf("mutants: %d decoded, %d refused\n", ok, failed);
}

TEST(ImageDecodeNative, OnlyOtherFormatsNeedTheModule) {
    EXPECT_FALSE(imageNeedsDecoderModule(embedded("p", writePng({PNG_COLOR_TYPE_RGB, 8}))));
    EXPECT_FALSE(imageNeedsDecoderModule(embedded("j", writeJpeg({3}))));
    std::vector<uint8_t> tga(18, 0);
    tga[2] = 2;
    EXPECT_TRUE(imageNeedsDecoderModule(embedded("t", tga)));
}

} // namespace
