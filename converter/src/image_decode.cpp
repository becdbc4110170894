// converter/src/image_decode.cpp — decodeImage (PNG and JPEG in-process, everything else) and
// resizeImage through the OpenImageIO codec module (texture_internal.h, ImageCodec), loaded with
// dlopen the first time it is needed. Why a module: OpenImageIO links some 250 shared libraries, whose loading and
// relocation took ~0.2 s of every pnb-convert process, textures or not (docs/CONVERTER.md,
// "Start-up"). Conversions without images, and --help, no longer load it.
//
// Where the module is looked for, first found wins:
//   1. $PNB_IMAGE_CODEC (a path to the module; for relocated installs and tests), alone when set;
//   2. beside the executable (the build tree keeps pnb-convert and the module together);
//   3. the installed location relative to the executable (<bindir>/PNB_IMAGE_CODEC_FROM_BINDIR);
//   4. where this build tree wrote it (tests live in other directories of the tree).
// A module that cannot be found or loaded makes every image an input error that names what was
// tried and dlerror()'s reason; nothing else of a conversion needs it.
#include <dlfcn.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "texture_internal.h"

namespace pnb::converter::texture_detail {

namespace {

namespace fs = std::filesystem;

constexpr const char* kModuleName = PNB_IMAGE_CODEC_NAME;

std::vector<std::string> candidatePaths() {
    std::vector<std::string> paths;
    // An explicit choice is the only candidate: a wrong path is an error, not a silent fallback.
    if (const char* env = std::getenv("PNB_IMAGE_CODEC"); env && *env) return {env};
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        paths.push_back((exe.parent_path() / kModuleName).string());
        paths.push_back((exe.parent_path() / PNB_IMAGE_CODEC_FROM_BINDIR / kModuleName)
                            .lexically_normal()
                            .string());
    }
    paths.push_back(PNB_IMAGE_CODEC_BUILD_PATH);
    return paths;
}

// PNG or JPEG by its first bytes (a file's are read), which decodeImage decodes in-process.
bool hasNativeSignature(const IrImage& image) {
    uint8_t head[8] = {};
    size_t got = std::min(image.encoded.size(), sizeof head);
    if (got) std::memcpy(head, image.encoded.data(), got); // data() may be null when empty
    if (!image.path.empty()) {
        std::FILE* f = std::fopen(image.path.c_str(), "rb");
        got = f ? std::fread(head, 1, sizeof head, f) : 0;
        if (f) std::fclose(f);
    }
    return (got >= 8 && std::memcmp(head, "\x89PNG\r\n\x1a\n", 8) == 0) ||
           (got >= 3 && std::memcmp(head, "\xFF\xD8\xFF", 3) == 0);
}

// The whole file, or as much as could be read (the decoder reports a short one).
std::vector<uint8_t> readWholeFile(const std::string& path) {
    std::vector<uint8_t> bytes;
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return bytes;
    if (std::fseek(f, 0, SEEK_END) == 0) {
        const long size = std::ftell(f);
        if (size > 0 && std::fseek(f, 0, SEEK_SET) == 0) {
            bytes.resize(size_t(size));
            bytes.resize(std::fread(bytes.data(), 1, bytes.size(), f));
        }
    }
    std::fclose(f);
    return bytes;
}

struct LoadedCodec {
    const ImageCodec* codec = nullptr;
    std::string error; // why there is none
};

const LoadedCodec& loadedCodec() {
    static LoadedCodec loaded;
    static std::once_flag once;
    std::call_once(once, [] {
        std::string tried;
        for (const std::string& path : candidatePaths()) {
            std::error_code ec;
            if (!fs::exists(path, ec)) {
                tried += "\n  " + path + ": not found";
                continue;
            }
            // Lazy binding, as at program start: RTLD_NOW would resolve every PLT entry of the
            // ~250 libraries OpenImageIO brings, which doubled the load time (0.4 s vs 0.2 s).
            // Never closed: OpenImageIO keeps plugins and threads for the life of the process.
            void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
            if (!handle) {
                const char* why = dlerror();
                tried += "\n  " + path + ": " + (why ? why : "cannot load");
                continue;
            }
            using Entry = const ImageCodec* (*)();
            auto entry = reinterpret_cast<Entry>(dlsym(handle, "pnb_image_codec_v1"));
            const ImageCodec* codec = entry ? entry() : nullptr;
            if (!codec || codec->size != sizeof(ImageCodec)) {
                tried += "\n  " + path + ": not a codec module of this build";
                continue;
            }
            loaded.codec = codec;
            return;
        }
        loaded.error = std::string("cannot load the image decoder module ") + kModuleName +
                       " (OpenImageIO); tried:" + tried;
    });
    return loaded;
}

} // namespace

Result<DecodedImage, ConvertError> decodeImageWithModule(const IrImage& image,
                                                         uint64_t maxSourceTexels,
                                                         const AdmitImage& admit) {
    const LoadedCodec& loaded = loadedCodec();
    if (!loaded.codec)
        return ConvertError{ConvertErrorKind::Input, describeImage(image) + ": " + loaded.error};
    return loaded.codec->decode(image, maxSourceTexels, admit);
}

Result<DecodedImage, ConvertError> decodeImage(const IrImage& image, uint64_t maxSourceTexels,
                                               const AdmitImage& admit) {
    // Embedded bytes are at hand; a file is read whole only when its signature is PNG or JPEG
    // (the module opens other files itself, and reports a missing one).
    std::vector<uint8_t> fileBytes;
    std::span<const uint8_t> bytes(image.encoded);
    if (!image.path.empty()) {
        std::error_code ec;
        if (!fs::exists(image.path, ec))
            return ConvertError{ConvertErrorKind::Input, describeImage(image) + ": file not found"};
        if (!fs::is_regular_file(image.path, ec))
            return ConvertError{ConvertErrorKind::Input,
                                describeImage(image) + ": not a regular file"};
        if (hasNativeSignature(image)) fileBytes = readWholeFile(image.path);
        bytes = fileBytes;
    }
    if (auto png = decodePng(image, bytes, maxSourceTexels, admit)) return std::move(*png);
    if (auto jpeg = decodeJpeg(image, bytes, maxSourceTexels, admit)) return std::move(*jpeg);
    return decodeImageWithModule(image, maxSourceTexels, admit);
}

Result<ImageF, ConvertError> resizeImage(const ImageF& src, uint32_t width, uint32_t height) {
    const LoadedCodec& loaded = loadedCodec();
    if (!loaded.codec)
        return ConvertError{ConvertErrorKind::Input,
                            "resizing a " + std::to_string(src.width) + "x" +
                                std::to_string(src.height) + " image: " + loaded.error};
    return loaded.codec->resize(src, width, height);
}

} // namespace pnb::converter::texture_detail

namespace pnb::converter {

void loadImageDecoder() {
    (void)texture_detail::loadedCodec();
}

bool imageNeedsDecoderModule(const IrImage& image) {
    return !texture_detail::hasNativeSignature(image);
}

} // namespace pnb::converter
