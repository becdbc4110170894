// converter/src/image_decode_oiio.cpp — source images to float RGBA with OpenImageIO, and
// resizing. Built as the module libpnb_image_oiio.so, which image_decode.cpp loads with dlopen
// the first time an image is decoded: OpenImageIO pulls in some 250 shared libraries whose
// loading and relocation cost every process ~0.2 s, which a conversion without textures (and
// `pnb-convert --help`) should not pay. The module calls nothing of pnb_converter's (it is
// linked with --no-undefined), so it only shares the header-only types of texture_internal.h.
//
// Does NOT do: colour-space conversion (texture_processing.cpp linearises sRGB data), EXIF
// orientation (JPEG rotation tags are ignored, like most glTF viewers do), layers or mip levels
// stored in the file (the first subimage's full-resolution level is used).
//
// Threading: every OIIO object here is told to use the calling thread only (ImageInput::threads,
// the nthreads argument), so the converter's own pool is the only parallelism and OIIO's global
// "threads" attribute stays untouched for the rest of the process.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cassert>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <span>
#include <string_view>

#include "texture_internal.h"

namespace pnb::converter::texture_detail {

namespace {

std::string trimmed(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
        s.pop_back();
    return s.empty() ? std::string("unknown error") : s;
}

bool startsWith(std::span<const uint8_t> bytes, std::string_view magic) {
    return bytes.size() >= magic.size() &&
           std::memcmp(bytes.data(), magic.data(), magic.size()) == 0;
}

std::string lowerExtension(std::string_view name) {
    size_t dot = name.rfind('.');
    size_t slash = name.find_last_of("/\\");
    if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash))
        return {};
    std::string ext(name.substr(dot + 1));
    for (char& c : ext)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

// OIIO chooses its plugin from the file name's extension and, given an IOProxy, does not fall
// back to probing every plugin; embedded bytes therefore need a name whose extension matches
// their content. Magic numbers first (glTF's mimeType is sometimes wrong), then the MIME type,
// then the image name's extension. Empty if nothing identifies the format.
std::string extensionForEmbedded(const IrImage& image) {
    std::span<const uint8_t> b(image.encoded);
    if (startsWith(b, "\x89PNG")) return "png";
    if (startsWith(b, "\xFF\xD8\xFF")) return "jpg";
    if (startsWith(b, "BM")) return "bmp";
    if (startsWith(b, "\x76\x2F\x31\x01")) return "exr";
    if (startsWith(b, "#?RADIANCE") || startsWith(b, "#?RGBE")) return "hdr";
    if (startsWith(b, "II*") || startsWith(b, "MM\0*")) return "tif";
    if (startsWith(b, "GIF8")) return "gif";
    if (startsWith(b, "DDS ")) return "dds";
    if (startsWith(b, "8BPS")) return "psd";
    if (b.size() >= 12 && startsWith(b, "RIFF") && std::memcmp(b.data() + 8, "WEBP", 4) == 0)
        return "webp";
    static constexpr std::pair<std::string_view, std::string_view> kMime[] = {
        {"image/png", "png"},          {"image/jpeg", "jpg"},  {"image/bmp", "bmp"},
        {"image/x-tga", "tga"},        {"image/tga", "tga"},   {"image/x-targa", "tga"},
        {"image/vnd.radiance", "hdr"}, {"image/x-exr", "exr"}, {"image/tiff", "tif"},
        {"image/webp", "webp"},        {"image/gif", "gif"},
    };
    for (const auto& [mime, ext] : kMime)
        if (image.mimeType == mime) return std::string(ext);
    return lowerExtension(image.name);
}

} // namespace

Result<DecodedImage, ConvertError> decodeWithOiio(const IrImage& image, uint64_t maxSourceTexels,
                                                  const AdmitImage& admit) {
    auto fail = [&](const std::string& what) {
        return ConvertError{ConvertErrorKind::Input, describeImage(image) + ": " + what};
    };

    OIIO::ImageSpec config;
    // Straight alpha as stored: OIIO would otherwise premultiply PNG/TGA/TIFF alpha on read,
    // darkening every filtered edge and losing colour under alpha 0.
    config.attribute("oiio:UnassociatedAlpha", 1);

    std::unique_ptr<OIIO::ImageInput> in;
    OIIO::Filesystem::IOMemReader memReader(image.encoded.data(), image.encoded.size());
    if (!image.path.empty()) {
        std::error_code ec;
        if (!std::filesystem::exists(image.path, ec)) return fail("file not found");
        if (!std::filesystem::is_regular_file(image.path, ec)) return fail("not a regular file");
        in = OIIO::ImageInput::open(image.path, &config);
    } else {
        if (image.encoded.empty()) return fail("no image data");
        std::string ext = extensionForEmbedded(image);
        if (ext.empty()) return fail("unrecognised image format (no known signature or MIME type)");
        OIIO::Filesystem::IOProxy* proxy = &memReader;
        // OIIO 2.4's ImageInput::open(name, config, proxy) does not hand the proxy to the
        // plugin when a config is given; the "oiio:ioproxy" config hint does.
        config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
        in = OIIO::ImageInput::open("embedded." + ext, &config, proxy);
    }
    if (!in) return fail("cannot decode: " + trimmed(OIIO::geterror()));
    in->threads(1);

    const OIIO::ImageSpec& spec = in->spec();
    if (spec.depth > 1)
        return ConvertError{ConvertErrorKind::Unsupported,
                            describeImage(image) + ": volume images are not supported"};
    ImageHeader header;
    header.width = uint32_t(std::max(spec.width, 0));
    header.height = uint32_t(std::max(spec.height, 0));
    header.channels = uint32_t(std::max(spec.nchannels, 0));
    header.bytesPerChannel = uint32_t(spec.format.size());
    header.floatSource = spec.format.is_floating_point();
    if (auto refused = checkImageHeader(image, header, maxSourceTexels, admit)) return *refused;
    const uint64_t texels = header.texels();

    // Channel meaning: 1 grey, 2 grey+alpha (or RG without an alpha channel), 3 RGB, 4+ RGB and
    // alpha (OIIO's alpha channel if it names one, else the fourth).
    int nch = spec.nchannels;
    bool secondIsAlpha = nch == 2 && (spec.alpha_channel == 1 || spec.channel_name(1) == "A");
    int alpha = nch >= 4 ? (spec.alpha_channel >= 3 ? spec.alpha_channel : 3) : -1;
    int kept = std::min(nch, 4);

    // The native pixels, `kept` channels per texel. `new[]` without value-initialisation: pages
    // are only touched as rows arrive, so a file that declares a huge size but lacks the data
    // fails without ever committing the memory (a zero-filled vector would touch all of it).
    const OIIO::TypeDesc native = spec.format;
    if (native.size() == 0)
        return fail(std::string("unknown pixel data type '") + native.c_str() + "'");
    const OIIO::stride_t texelBytes = OIIO::stride_t(kept) * OIIO::stride_t(native.size());
    std::unique_ptr<std::byte[]> pixels(new std::byte[size_t(texels) * size_t(texelBytes)]);
    bool ok = in->read_image(0, 0, 0, std::min(nch, alpha == 3 ? 4 : 3), native, pixels.get(),
                             texelBytes);
    if (ok && alpha > 3)
        ok = in->read_image(0, 0, alpha, alpha + 1, native, pixels.get() + 3 * native.size(),
                            texelBytes);
    if (!ok)
        return fail("cannot read the pixels of its declared " + std::to_string(spec.width) + "x" +
                    std::to_string(spec.height) + ": " + trimmed(in->geterror()));
    in.reset(); // the decoder's own buffers go before the float image is allocated

    DecodedImage out;
    out.sourceChannels = header.channels;
    out.floatSource = header.floatSource;
    out.image.width = header.width;
    out.image.height = header.height;
    out.image.texels.assign(size_t(texels) * 4, 0.0f);
    constexpr OIIO::stride_t kStride = 4 * sizeof(float);
    const int width = int(header.width), height = int(header.height); // `spec` died with `in`
    ok = OIIO::convert_image(kept, width, height, 1, pixels.get(), native, texelBytes,
                             OIIO::AutoStride, OIIO::AutoStride, out.image.texels.data(),
                             OIIO::TypeDesc::FLOAT, kStride, kStride * width, OIIO::AutoStride);
    if (!ok) return fail("cannot convert pixels to float: " + trimmed(OIIO::geterror()));
    expandToRgba(out.image.texels, uint32_t(kept), secondIsAlpha);
    return out;
}

ImageF resizeWithOiio(const ImageF& src, uint32_t width, uint32_t height) {
    assert(width > 0 && height > 0 && src.texelCount() > 0);
    ImageF dst;
    dst.width = width;
    dst.height = height;
    dst.texels.assign(dst.texelCount() * 4, 0.0f);
    // Both buffers are wrapped, not copied; OIIO only reads `src`.
    OIIO::ImageBuf srcBuf(
        OIIO::ImageSpec(int(src.width), int(src.height), 4, OIIO::TypeDesc::FLOAT),
        const_cast<float*>(src.texels.data()));
    OIIO::ImageBuf dstBuf(OIIO::ImageSpec(int(width), int(height), 4, OIIO::TypeDesc::FLOAT),
                          dst.texels.data());
    // Lanczos-3: sharp without visible ringing on texture content, OIIO's own choice for
    // downsizing. nthreads = 1: the caller's pool provides the parallelism (and determinism).
    [[maybe_unused]] bool ok =
        OIIO::ImageBufAlgo::resize(dstBuf, srcBuf, "lanczos3", 0.0f, OIIO::ROI::All(), 1);
    assert(ok && "resize of valid float buffers cannot fail");
    return dst;
}

} // namespace pnb::converter::texture_detail

extern "C" __attribute__((visibility("default"))) const pnb::converter::texture_detail::ImageCodec*
pnb_image_codec_v1() {
    using namespace pnb::converter::texture_detail;
    static const ImageCodec codec{sizeof(ImageCodec), &decodeWithOiio, &resizeWithOiio};
    return &codec;
}
