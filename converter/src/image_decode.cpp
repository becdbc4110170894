// converter/src/image_decode.cpp — decodeImage and resizeImage through the OpenImageIO codec
// module (texture_internal.h, ImageCodec), loaded with dlopen the first time an image is
// decoded. Why a module: OpenImageIO links some 250 shared libraries, whose loading and
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

#include <cassert>
#include <cstdlib>
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

Result<DecodedImage, ConvertError> decodeImage(const IrImage& image, uint64_t maxSourceTexels,
                                               const AdmitImage& admit) {
    const LoadedCodec& loaded = loadedCodec();
    if (!loaded.codec)
        return ConvertError{ConvertErrorKind::Input, describeImage(image) + ": " + loaded.error};
    return loaded.codec->decode(image, maxSourceTexels, admit);
}

ImageF resizeImage(const ImageF& src, uint32_t width, uint32_t height) {
    const LoadedCodec& loaded = loadedCodec();
    assert(loaded.codec && "resizeImage before any image was decoded");
    if (!loaded.codec) return {}; // unreachable: every resized image was decoded first
    return loaded.codec->resize(src, width, height);
}

} // namespace pnb::converter::texture_detail

namespace pnb::converter {

void loadImageDecoder() {
    (void)texture_detail::loadedCodec();
}

} // namespace pnb::converter
