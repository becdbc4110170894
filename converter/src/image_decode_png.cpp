// converter/src/image_decode_png.cpp — PNG to float RGBA with libpng, in-process (why not
// through the OpenImageIO module: texture_internal.h, decodePng).
//
// What it reproduces of OpenImageIO's PNG reader (checked texel for texel against the module by
// tests/converter/image_decode_native_test.cpp): palette, grey below 8 bits and tRNS expanded
// (palette → RGB, tRNS → an alpha channel), 16-bit samples kept at 16 bits, interlaced images
// de-interlaced, alpha straight as stored, no gamma or colour-space conversion (gAMA, cHRM,
// iCCP and sRGB chunks are ignored; texture_processing.cpp linearises sRGB requests), integer
// samples v → v / (2^bits − 1). sourceChannels counts the channels after expansion.
//
// Errors: libpng's message for a malformed or truncated stream ("cannot decode: ..."); CRC
// errors are errors. Warnings (unknown chunks, a bad ancillary chunk) are ignored, as OIIO does.
//
// libpng reports errors with longjmp: each function that calls into libpng after setjmp holds
// only trivially destructible locals, and the pixel buffer lives in the caller.
#include <png.h>

#include <csetjmp>
#include <cstring>
#include <memory>

#include "huge_pages.h"
#include "texture_internal.h"

namespace pnb::converter::texture_detail {

namespace {

struct PngStream {
    const uint8_t* data;
    size_t size;
    size_t offset;
    char error[256];
};

void readBytes(png_structp png, png_bytep out, size_t count) {
    auto* s = static_cast<PngStream*>(png_get_io_ptr(png));
    if (count > s->size - s->offset) png_error(png, "unexpected end of data");
    std::memcpy(out, s->data + s->offset, count);
    s->offset += count;
}

[[noreturn]] void onError(png_structp png, png_const_charp message) {
    auto* s = static_cast<PngStream*>(png_get_error_ptr(png));
    std::snprintf(s->error, sizeof s->error, "%s", message ? message : "unknown error");
    png_longjmp(png, 1);
}

void onWarning(png_structp, png_const_charp) {}

// Owns libpng's read and info structs.
struct PngReader {
    png_structp png = nullptr;
    png_infop info = nullptr;
    ~PngReader() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

struct PngLayout {
    uint32_t width, height, channels, bitDepth;
};

// Reads the header and sets up the transforms; false with stream.error set on failure.
bool readHeader(PngReader& r, PngLayout& out) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_read_info(r.png, r.info);
    const int colorType = png_get_color_type(r.png, r.info);
    const int bitDepth = png_get_bit_depth(r.png, r.info);
    if (colorType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(r.png);
    if (colorType == PNG_COLOR_TYPE_GRAY && bitDepth < 8) png_set_expand_gray_1_2_4_to_8(r.png);
    if (png_get_valid(r.png, r.info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(r.png);
    if (bitDepth == 16) png_set_swap(r.png); // samples in host order (little-endian hosts)
    png_set_interlace_handling(r.png);
    png_read_update_info(r.png, r.info);
    out.width = png_get_image_width(r.png, r.info);
    out.height = png_get_image_height(r.png, r.info);
    out.channels = png_get_channels(r.png, r.info);
    out.bitDepth = png_get_bit_depth(r.png, r.info);
    return true;
}

bool readRows(PngReader& r, png_bytep* rows) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_read_image(r.png, rows);
    png_read_end(r.png, nullptr);
    return true;
}

template <class Sample>
void widen(const Sample* src, size_t texels, uint32_t channels, float scale, float* dst) {
    for (size_t i = 0; i < texels; ++i)
        for (uint32_t c = 0; c < channels; ++c)
            dst[i * 4 + c] = float(src[i * channels + c]) * scale;
}

} // namespace

std::optional<Result<DecodedImage, ConvertError>> decodePng(const IrImage& image,
                                                            std::span<const uint8_t> bytes,
                                                            uint64_t maxSourceTexels,
                                                            const AdmitImage& admit) {
    if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0) return std::nullopt;
    PngStream stream{bytes.data(), bytes.size(), 0, {}};
    auto fail = [&](const std::string& what) {
        return ConvertError{ConvertErrorKind::Input, describeImage(image) + ": " + what};
    };
    auto failDecode = [&] { return fail(std::string("cannot decode: ") + stream.error); };

    PngReader r;
    r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &stream, onError, onWarning);
    if (r.png) r.info = png_create_info_struct(r.png);
    if (!r.png || !r.info) return fail("cannot decode: out of memory");
    png_set_read_fn(r.png, &stream, readBytes);
    // No per-chunk size limit beyond libpng's own: the image size is checked below.
    png_set_user_limits(r.png, 0x7fffffff, 0x7fffffff);

    PngLayout layout{};
    if (!readHeader(r, layout)) return failDecode();
    ImageHeader header;
    header.width = layout.width;
    header.height = layout.height;
    header.channels = layout.channels;
    header.bytesPerChannel = layout.bitDepth / 8;
    if (auto refused = checkImageHeader(image, header, maxSourceTexels, admit)) return *refused;
    if (layout.channels > 4 || (layout.bitDepth != 8 && layout.bitDepth != 16))
        return fail("cannot decode: unexpected PNG layout after expansion");

    // Uninitialised, as in the module: a file that declares more rows than it holds fails before
    // the float image is allocated, with only the rows that arrived touched.
    const size_t texels = size_t(header.texels());
    const size_t rowBytes = size_t(layout.width) * layout.channels * header.bytesPerChannel;
    std::unique_ptr<uint8_t[]> pixels(new uint8_t[rowBytes * layout.height]);
    std::unique_ptr<png_bytep[]> rows(new png_bytep[layout.height]);
    for (uint32_t y = 0; y < layout.height; ++y)
        rows[y] = pixels.get() + size_t(y) * rowBytes;
    if (!readRows(r, rows.get()))
        return fail("cannot read the pixels of its declared " + std::to_string(layout.width) +
                    "x" + std::to_string(layout.height) + ": " + stream.error);
    rows.reset();

    DecodedImage out;
    out.sourceChannels = layout.channels;
    out.image.width = layout.width;
    out.image.height = layout.height;
    // Float RGBA: 16 MB for a 1024² texture, in huge pages (huge_pages.h: page faults are dear).
    out.image.texels.reserve(texels * 4);
    adviseHugePages(out.image.texels.data(), texels * 4 * sizeof(float));
    out.image.texels.assign(texels * 4, 0.0f);
    if (layout.bitDepth == 8)
        widen(pixels.get(), texels, layout.channels, 1.0f / 255.0f, out.image.texels.data());
    else
        widen(reinterpret_cast<const uint16_t*>(pixels.get()), texels, layout.channels,
              1.0f / 65535.0f, out.image.texels.data());
    pixels.reset();
    // PNG's two-channel colour type is always grey + alpha.
    expandToRgba(out.image.texels, layout.channels, true);
    return Result<DecodedImage, ConvertError>(std::move(out));
}

} // namespace pnb::converter::texture_detail
