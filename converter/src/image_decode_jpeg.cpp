// converter/src/image_decode_jpeg.cpp — JPEG to float RGBA with libjpeg-turbo, in-process (why
// not through the OpenImageIO module: texture_internal.h, decodeJpeg).
//
// What it reproduces of OpenImageIO's JPEG reader (checked texel for texel against the module by
// tests/converter/image_decode_native_test.cpp): libjpeg's default decompression (accurate
// integer IDCT, fancy upsampling), YCbCr → RGB, greyscale as one channel, v → v / 255, EXIF
// orientation ignored. CMYK and YCCK files go to the module (OIIO inverts Adobe CMYK and converts
// to RGB; rare in textures).
//
// Errors: libjpeg's message. Unlike a viewer we also fail on libjpeg's corrupt-data warnings
// (a truncated file, bad Huffman data): libjpeg would fill the missing part with grey and the
// container would silently hold a damaged texture.
//
// libjpeg reports errors through error_exit, which longjmps back here: each function that calls
// into libjpeg after setjmp holds only trivially destructible locals, and the pixel buffer lives
// in the caller.
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>

#include <jpeglib.h>

#include "texture_internal.h"

namespace pnb::converter::texture_detail {

namespace {

struct JpegErrors {
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void onError(j_common_ptr cinfo) {
    auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, e->message);
    std::longjmp(e->jump, 1);
}

// Level -1 is a corrupt-data warning: an error here (see the header). Trace messages are not.
void onMessage(j_common_ptr cinfo, int level) {
    if (level < 0) onError(cinfo);
}

// Owns the decompressor.
struct JpegReader {
    jpeg_decompress_struct cinfo{};
    JpegErrors errors{};
    bool created = false;
    ~JpegReader() {
        if (created) jpeg_destroy_decompress(&cinfo);
    }
};

enum class HeaderResult { Ok, Failed, NotHandled };

HeaderResult readHeader(JpegReader& r, std::span<const uint8_t> bytes) {
    if (setjmp(r.errors.jump)) return HeaderResult::Failed;
    jpeg_create_decompress(&r.cinfo);
    r.created = true;
    jpeg_mem_src(&r.cinfo, bytes.data(), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&r.cinfo, TRUE);
    if (r.cinfo.jpeg_color_space == JCS_CMYK || r.cinfo.jpeg_color_space == JCS_YCCK)
        return HeaderResult::NotHandled;
    r.cinfo.out_color_space = r.cinfo.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_calc_output_dimensions(&r.cinfo);
    return HeaderResult::Ok;
}

bool readScanlines(JpegReader& r, uint8_t* pixels, size_t rowBytes) {
    if (setjmp(r.errors.jump)) return false;
    jpeg_start_decompress(&r.cinfo);
    while (r.cinfo.output_scanline < r.cinfo.output_height) {
        JSAMPROW row = pixels + size_t(r.cinfo.output_scanline) * rowBytes;
        jpeg_read_scanlines(&r.cinfo, &row, 1);
    }
    jpeg_finish_decompress(&r.cinfo);
    return true;
}

} // namespace

std::optional<Result<DecodedImage, ConvertError>> decodeJpeg(const IrImage& image,
                                                             std::span<const uint8_t> bytes,
                                                             uint64_t maxSourceTexels,
                                                             const AdmitImage& admit) {
    if (bytes.size() < 3 || std::memcmp(bytes.data(), "\xFF\xD8\xFF", 3) != 0) return std::nullopt;
    auto fail = [&](const std::string& what) {
        return ConvertError{ConvertErrorKind::Input, describeImage(image) + ": " + what};
    };

    JpegReader r;
    r.cinfo.err = jpeg_std_error(&r.errors.mgr);
    r.errors.mgr.error_exit = onError;
    r.errors.mgr.emit_message = onMessage;
    switch (readHeader(r, bytes)) {
    case HeaderResult::Ok:
        break;
    case HeaderResult::Failed:
        return fail(std::string("cannot decode: ") + r.errors.message);
    case HeaderResult::NotHandled:
        return std::nullopt;
    }

    ImageHeader header;
    header.width = r.cinfo.output_width;
    header.height = r.cinfo.output_height;
    header.channels = uint32_t(r.cinfo.output_components);
    header.bytesPerChannel = 1;
    if (auto refused = checkImageHeader(image, header, maxSourceTexels, admit)) return *refused;

    const size_t texels = size_t(header.texels());
    const size_t rowBytes = size_t(header.width) * header.channels;
    std::unique_ptr<uint8_t[]> pixels(new uint8_t[rowBytes * header.height]);
    if (!readScanlines(r, pixels.get(), rowBytes))
        return fail("cannot read the pixels of its declared " + std::to_string(header.width) +
                    "x" + std::to_string(header.height) + ": " + r.errors.message);

    DecodedImage out;
    out.sourceChannels = header.channels;
    out.image.width = header.width;
    out.image.height = header.height;
    out.image.texels.assign(texels * 4, 0.0f);
    float* dst = out.image.texels.data();
    for (size_t i = 0; i < texels; ++i)
        for (uint32_t c = 0; c < header.channels; ++c)
            dst[i * 4 + c] = float(pixels[i * header.channels + c]) * (1.0f / 255.0f);
    pixels.reset();
    expandToRgba(out.image.texels, header.channels, false);
    return Result<DecodedImage, ConvertError>(std::move(out));
}

} // namespace pnb::converter::texture_detail
