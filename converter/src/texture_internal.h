// converter/src/texture_internal.h — private interfaces between the texture processing files
// (texture_processing.cpp drives one request and runs the worker pool; image_decode.cpp picks
// the decoder: image_decode_png.cpp and image_decode_jpeg.cpp in-process, image_decode_oiio.cpp
// — OpenImageIO, also for resizing — in a module loaded on first use; mip_chain.cpp filters mip
// levels and preserves alpha coverage;
// channel_packing.cpp chooses what is stored where and quantises; block_compress.cpp wraps
// libsquish). Not installed, not used outside converter/src.
//
// Images here are float RGBA, 4 floats per texel, rows top to bottom as the image file shows
// them; that is also the order TMIP stores them in (see texture_processing.cpp for why). Colour
// channels of sRGB requests are in linear light from decode onwards: every filter works on light,
// and only quantisation re-encodes.
//
// Thread safety: every function is reentrant (no shared state besides constant tables); the
// pool in texture_processing.cpp calls them from several threads at once.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/error.h"
#include "pnb_converter/scene_ir.h"
#include "pnb_converter/texture_processing.h"

namespace pnb::converter::texture_detail {

struct ImageF {
    uint32_t width = 0, height = 0;
    std::vector<float> texels; // r, g, b, a per texel, width * height * 4 floats

    size_t texelCount() const { return size_t(width) * height; }
};

// [SECTION] decode — image_decode.cpp

struct DecodedImage {
    ImageF image; // grey → r = g = b; no alpha channel → a = 1; no blue → b = 0
    uint32_t sourceChannels = 0;
    bool floatSource = false; // EXR, HDR, float TIFF...: linear light, values may leave [0, 1]
};

// What an image file declares, before any pixel is read.
struct ImageHeader {
    uint32_t width = 0, height = 0, channels = 0;
    uint32_t bytesPerChannel = 0; // of the file's native type (1 for 8-bit PNG, 4 for float EXR)
    bool floatSource = false;

    uint64_t texels() const { return uint64_t(width) * height; }
};

// Decides from the header whether the image may be decoded: nullopt admits it, a message
// refuses it (the decode fails with that message after describeImage(image)).
using AdmitImage = std::function<std::optional<std::string>(const ImageHeader&)>;

// "image 'wood' (textures/wood.png)" or "image 'wood' (embedded, 1234 bytes)", for messages.
// Inline: the image codec module (image_decode_oiio.cpp) uses it too and links nothing of ours.
inline std::string describeImage(const IrImage& image) {
    std::string s = "image '" + image.name + "' (";
    if (!image.path.empty())
        s += image.path;
    else
        s += "embedded, " + std::to_string(image.encoded.size()) + " bytes";
    return s + ")";
}

// The checks every decoder makes on a header before any pixel buffer exists: zero size, more
// than `maxSourceTexels` texels, a refusal by `admit`. Inline: the codec module uses it too.
inline std::optional<ConvertError> checkImageHeader(const IrImage& image, const ImageHeader& h,
                                                    uint64_t maxSourceTexels,
                                                    const AdmitImage& admit) {
    auto fail = [&](const std::string& what) {
        return ConvertError{ConvertErrorKind::Input, describeImage(image) + ": " + what};
    };
    if (h.width == 0 || h.height == 0 || h.channels == 0)
        return fail("zero size (" + std::to_string(h.width) + "x" + std::to_string(h.height) +
                    ", " + std::to_string(h.channels) + " channels)");
    if (h.texels() > maxSourceTexels)
        return fail(std::to_string(h.width) + "x" + std::to_string(h.height) + " = " +
                    std::to_string(h.texels()) + " texels exceeds the limit of " +
                    std::to_string(maxSourceTexels));
    if (admit) {
        if (std::optional<std::string> refusal = admit(h)) return fail(*refusal);
    }
    return std::nullopt;
}

// Fills in RGBA from the first `channels` floats of each texel (already at a 4-float stride),
// keeping what each source channel means: grey fills r, g and b; a grey+alpha image keeps its
// alpha (`secondIsAlpha`; otherwise two channels are red and green); no alpha → 1.
inline void expandToRgba(std::vector<float>& t, uint32_t channels, bool secondIsAlpha) {
    const size_t n = t.size() / 4;
    for (size_t i = 0; i < n; ++i) {
        float* p = &t[i * 4];
        switch (channels) {
        case 1:
            p[1] = p[2] = p[0];
            p[3] = 1.0f;
            break;
        case 2:
            if (secondIsAlpha) {
                p[3] = p[1];
                p[1] = p[2] = p[0];
            } else {
                p[2] = 0.0f;
                p[3] = 1.0f;
            }
            break;
        case 3:
            p[3] = 1.0f;
            break;
        default:
            break;
        }
    }
}

// Decodes the first subimage's full-resolution level to float RGBA with straight (not
// premultiplied) alpha. The header is read and checked before any pixel buffer is allocated:
// zero size, more than `maxSourceTexels` texels, or a refusal by `admit` fail. Pixels are read
// in the file's native type into an uninitialised buffer and widened to float only once the read
// succeeded, so a file whose data is missing fails before the float image exists. Errors (Input)
// start with describeImage(image).
Result<DecodedImage, ConvertError> decodeImage(const IrImage& image, uint64_t maxSourceTexels,
                                               const AdmitImage& admit);

// PNG and JPEG, the formats nearly every model's textures use, are decoded in-process with
// libpng and libjpeg-turbo (image_decode_png.cpp, image_decode_jpeg.cpp): loading the
// OpenImageIO module costs 0.2–0.5 s of a conversion, decoding a small texture about 1 ms. Every
// other format, and the rare PNG/JPEG variants listed there, go to the module. nullopt: not
// handled here (not that format, or a variant left to the module); the same float texels and
// sourceChannels as the module's decode otherwise (tests/converter/image_decode_native_test.cpp).
std::optional<Result<DecodedImage, ConvertError>> decodePng(const IrImage& image,
                                                            std::span<const uint8_t> bytes,
                                                            uint64_t maxSourceTexels,
                                                            const AdmitImage& admit);
std::optional<Result<DecodedImage, ConvertError>> decodeJpeg(const IrImage& image,
                                                             std::span<const uint8_t> bytes,
                                                             uint64_t maxSourceTexels,
                                                             const AdmitImage& admit);

// The decode through the OpenImageIO module alone, for tests that compare it with the native
// decoders; decodeImage picks the decoder.
Result<DecodedImage, ConvertError> decodeImageWithModule(const IrImage& image,
                                                         uint64_t maxSourceTexels,
                                                         const AdmitImage& admit);

// Resamples to width × height (each ≥ 1) with a Lanczos-3 filter (OIIO resize), on the calling
// thread only, so results do not depend on OIIO's thread pool. Values are not clamped.
// Loads the codec module if no image needed it yet; fails only if it cannot be loaded.
Result<ImageF, ConvertError> resizeImage(const ImageF& src, uint32_t width, uint32_t height);

// The OpenImageIO codec behind decodeImage and resizeImage, in the module libpnb_image_oiio.so
// (image_decode_oiio.cpp), loaded by image_decode.cpp on first use. The module and the converter
// come from one build, so C++ types may cross; `size` catches a stale module from another one.
struct ImageCodec {
    size_t size; // sizeof(ImageCodec) where the module was built
    Result<DecodedImage, ConvertError> (*decode)(const IrImage& image, uint64_t maxSourceTexels,
                                                 const AdmitImage& admit);
    ImageF (*resize)(const ImageF& src, uint32_t width, uint32_t height);
};

// [SECTION] mip chain — mip_chain.cpp

// The next mip level: max(1, w >> 1) × max(1, h >> 1), each texel the area-weighted mean of
// the source texels under its footprint (a box filter; exact 2×2 averages for even sizes, a
// 2.5-texel footprint when 5 halves to 2). All four channels are filtered alike.
ImageF downsample(const ImageF& src);

// How alpha is stored, which decides what a shader's `alpha >= cutoff` test sees.
enum class AlphaStorage : uint8_t { Unorm8, Half };

// Fraction of texels whose alpha, scaled by `scale`, clamped to 1 and quantised as `storage`,
// passes `alpha >= cutoff`.
double alphaCoverage(const ImageF& image, float cutoff, float scale, AlphaStorage storage);

// The alpha scale that brings this level's coverage closest to `targetCoverage` (binary search,
// Castaño 2010). Returns 1 when the cutoff makes coverage independent of the scale.
float findAlphaScale(const ImageF& image, float cutoff, double targetCoverage,
                     AlphaStorage storage);

// [SECTION] channel packing — channel_packing.cpp

// How one stored channel is quantised.
enum class Encoding : uint8_t {
    Unorm8, // round(clamp(v, 0, 1) * 255)
    Srgb8,  // linear v → sRGB transfer → 8 bits (sRGB formats; GL decodes when sampling)
    Half,   // IEEE binary16, clamped to ±65504, NaN → 0
};

// What is stored where, and how a shader gets the source channels back.
struct ChannelLayout {
    TextureFormat format = TextureFormat::RGBA8; // uncompressed: R8..RGBA8 or R16F/RG16F/RGBA16F
    uint32_t positions = 4;                      // stored channels per texel, 1..4
    std::array<int8_t, 4> source{0, 1, 2, 3};    // source channel at each position; -1 = unused
    std::array<Encoding, 4> encoding{};          // per position
    ColorSpace colorSpace = ColorSpace::Linear;
    std::array<Swizzle, 4> swizzle{Swizzle::R, Swizzle::G, Swizzle::B, Swizzle::A};

    bool storesAlpha() const {
        for (int8_t s : source)
            if (s == 3) return true;
        return false;
    }
};

// Chooses the layout from level 0 (colour in linear light for sRGB requests). Constant and
// duplicate channels are found on level 0 quantised as they would be stored. `hdr` selects
// 16-bit float storage. The rules are documented in channel_packing.cpp.
ChannelLayout planLayout(const ImageF& level0, const TextureRequest& request, bool hdr);

// Quantises one level into `layout`: positions interleaved per texel, one byte per value
// (8-bit encodings) or two little-endian bytes (Half); unused positions hold 0. Alpha is
// multiplied by `alphaScale` and clamped to 1 first (coverage preservation).
std::vector<std::byte> packLevel(const ImageF& level, const ChannelLayout& layout,
                                 float alphaScale);

// Quantisers, exposed for the coverage search and the tests.
uint8_t quantizeUnorm8(float v);
uint8_t quantizeSrgb8(float linear);
uint16_t floatToHalf(float v); // round to nearest even; clamps to ±65504; NaN → 0
float halfToFloat(uint16_t h);
float srgbToLinear(float encoded);
float linearToSrgb(float linear);

// [SECTION] block compression — block_compress.cpp

// The block format for `positions` stored 8-bit channels: 1 → BC4, 2 → BC5, 3 → BC1, 4 → BC3.
TextureFormat blockFormatFor(uint32_t positions);

// Compresses a level packed by packLevel (8-bit encodings only) into `format`, blocks in row
// order from the top, partial edge blocks padded (their outside texels do not influence the
// fit). Output size is textureLevelSizeBytes(format, width, height, 1).
std::vector<std::byte> compressLevel(const std::vector<std::byte>& packed, uint32_t positions,
                                     uint32_t width, uint32_t height, TextureFormat format);

// Decodes blocks back to `positions` interleaved 8-bit channels (the inverse layout of
// compressLevel's input), for PSNR and tests.
std::vector<uint8_t> decompressLevel(const std::vector<std::byte>& blocks, uint32_t positions,
                                     uint32_t width, uint32_t height, TextureFormat format);

// PSNR in dB of `decoded` against `original` over the positions `used` marks, 255 peak; 0 when
// they are identical (the header's "0 if lossless").
double psnrDb(const std::vector<std::byte>& original, const std::vector<uint8_t>& decoded,
              uint32_t positions, const std::array<bool, 4>& used);

} // namespace pnb::converter::texture_detail
