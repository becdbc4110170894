// PNG through stb_image_write with zlib as its deflate, OpenEXR through tinyexr (see
// image_write.h for the scope; image_write_tinyexr.cpp holds tinyexr's implementation).

#include "pnb_player/image_write.h"

#include <climits>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include <zlib.h>

namespace pnb::player {
namespace {

// The deflate level stb_image_write's PNGs get: zlib's default. On 1280x720 screenshots level 6
// came within 3 % of level 9's size in about a fifth of the time, and gave the old hand-written
// writer's bytes exactly; stb's own deflate wrote 1.4-6x larger files (docs/PLAYER.md,
// "Screenshots and dumps: the image writers").
constexpr int kZlibLevel = 6;

// Why the last compression on this thread failed (stb only sees a null pointer).
thread_local int tZlibStatus = Z_OK;

// STBIW_ZLIB_COMPRESS: the complete zlib stream of data[0..size), malloc'ed (stb frees it with
// free()), or null. stb passes its own level (stbi_write_png_compression_level); kZlibLevel wins.
unsigned char* zlibCompress(unsigned char* data, int size, int* outSize, int /*stbLevel*/) {
    uLongf bound = compressBound(uLong(size));
    // stb adds its chunk framing (57 bytes) to the stream's length in an int.
    if (bound > uLongf(INT_MAX - 64)) {
        tZlibStatus = Z_BUF_ERROR;
        return nullptr;
    }
    auto* out = static_cast<unsigned char*>(std::malloc(bound));
    if (out == nullptr) {
        tZlibStatus = Z_MEM_ERROR;
        return nullptr;
    }
    int r = compress2(out, &bound, data, uLong(size), kZlibLevel);
    if (r != Z_OK) {
        std::free(out);
        tZlibStatus = r;
        return nullptr;
    }
    tZlibStatus = Z_OK;
    *outSize = int(bound);
    return out;
}

} // namespace
} // namespace pnb::player

// Debian's libstb-dev, header-only: the implementation is compiled into this file, every
// function static (no clash with the libstb.so that Dear ImGui links), without stdio, and with
// zlib instead of stb's own deflate. Only the PNG writer is used; the other writers' statics are
// dropped by the compiler.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STBI_WRITE_NO_STDIO
#define STBIW_ZLIB_COMPRESS(data, size, outSize, level)                                        \
    pnb::player::zlibCompress(data, size, outSize, level)
#include <stb_image_write.h>

#include <tinyexr.h>

namespace pnb::player {
namespace {

constexpr uint32_t kMaxInt32 = uint32_t(std::numeric_limits<int32_t>::max());
// stb_image_write sizes everything in int: a row's filter estimate sums up to 128 per byte,
// and the filtered scanlines plus their zlib stream (compressBound adds ~0.03 %) must fit.
constexpr uint64_t kMaxPngRowBytes = (uint64_t(1) << 24) - 1;
constexpr uint64_t kMaxPngFilteredBytes = (uint64_t(1) << 31) - (uint64_t(1) << 24);

// Shared preconditions: non-zero size, 1..4 channels, exactly the span the format needs, and a
// sample count of width*height*channels (computed without overflow).
Status checkView(const ImageView& image, const char* format, bool wantF32) {
    if (image.width == 0 || image.height == 0)
        return makeError(FormatError::BadPayload, 0,
                         "%s image: width and height must be non-zero (got %ux%u)", format,
                         image.width, image.height);
    if (image.channels < 1 || image.channels > 4)
        return makeError(FormatError::BadPayload, 0, "%s image: channels must be 1..4 (got %u)",
                         format, image.channels);
    if (!image.u8.empty() && !image.f32.empty())
        return makeError(FormatError::BadPayload, 0,
                         "%s image: both u8 and f32 samples are given; exactly one must be",
                         format);
    const char* want = wantF32 ? "f32" : "u8";
    size_t have = wantF32 ? image.f32.size() : image.u8.size();
    if (have == 0) {
        bool other = wantF32 ? !image.u8.empty() : !image.f32.empty();
        return makeError(FormatError::BadPayload, 0, "%s image: needs %s samples, %s", format,
                         want, other ? (wantF32 ? "got u8" : "got f32") : "got none");
    }
    uint64_t perRow = uint64_t(image.width) * image.channels; // < 2^35, no overflow
    if (perRow > std::numeric_limits<uint64_t>::max() / image.height)
        return makeError(FormatError::LimitExceeded, 0, "%s image: %ux%ux%u samples overflow",
                         format, image.width, image.height, image.channels);
    uint64_t expected = perRow * image.height;
    if (have != expected)
        return makeError(FormatError::BadPayload, 0,
                         "%s image: %s has %zu samples, expected %ux%ux%u = %llu", format, want,
                         have, image.width, image.height, image.channels,
                         static_cast<unsigned long long>(expected));
    return {};
}

// Frees what stb and tinyexr return (both allocate with malloc).
struct FreeDeleter {
    void operator()(void* p) const { std::free(p); }
};
using MallocBytes = std::unique_ptr<unsigned char, FreeDeleter>;

Result<std::vector<uint8_t>> encodePngChecked(const ImageView& image) {
    if (Status s = checkPngImage(image); !isOk(s)) return s;
    const int w = int(image.width), h = int(image.height), n = int(image.channels);
    int size = 0;
    tZlibStatus = Z_OK;
    MallocBytes png(stbi_write_png_to_mem(image.u8.data(), w * n, w, h, n, &size));
    if (png == nullptr) {
        if (tZlibStatus != Z_OK)
            return makeError(FormatError::LimitExceeded, 0,
                             "PNG image: zlib compress2 failed (code %d) on %ux%ux%u", tZlibStatus,
                             image.width, image.height, image.channels);
        return makeError(FormatError::LimitExceeded, 0,
                         "PNG image: out of memory encoding %ux%ux%u", image.width, image.height,
                         image.channels);
    }
    try {
        return std::vector<uint8_t>(png.get(), png.get() + size);
    } catch (const std::bad_alloc&) {
        return makeError(FormatError::LimitExceeded, 0,
                         "PNG image: out of memory copying %d encoded bytes", size);
    }
}

// Channels sorted by name (OpenEXR requires the chlist, and so the per-line channel order, to
// be in ascending name order); source = index in the interleaved input pixel.
struct ExrChannel {
    const char* name;
    uint32_t source;
};

std::vector<ExrChannel> exrChannels(uint32_t channels) {
    switch (channels) {
    case 1: return {{"Y", 0}};
    case 2: return {{"A", 1}, {"Y", 0}};
    case 3: return {{"B", 2}, {"G", 1}, {"R", 0}};
    default: return {{"A", 3}, {"B", 2}, {"G", 1}, {"R", 0}};
    }
}

Result<std::vector<uint8_t>> encodeExrChecked(const ImageView& image) {
    if (Status s = checkExrImage(image); !isOk(s)) return s;
    const std::vector<ExrChannel> order = exrChannels(image.channels);
    const size_t nc = image.channels, pixels = size_t(image.width) * image.height;
    try {
        // tinyexr takes one plane per channel, in the header's (sorted) channel order.
        std::vector<std::vector<float>> planes(nc, std::vector<float>(pixels));
        std::vector<unsigned char*> planePointers(nc);
        std::vector<EXRChannelInfo> infos(nc);
        std::vector<int> types(nc, TINYEXR_PIXELTYPE_FLOAT);
        const float* in = image.f32.data();
        for (size_t c = 0; c < nc; ++c) {
            float* plane = planes[c].data();
            const size_t source = order[c].source;
            for (size_t p = 0; p < pixels; ++p) plane[p] = in[p * nc + source];
            planePointers[c] = reinterpret_cast<unsigned char*>(plane);
            infos[c] = EXRChannelInfo{};
            infos[c].name[0] = order[c].name[0];
            infos[c].name[1] = '\0';
        }

        EXRHeader header;
        InitEXRHeader(&header);
        header.num_channels = int(nc);
        header.channels = infos.data();
        header.pixel_types = types.data();           // the type of the planes' samples
        header.requested_pixel_types = types.data(); // the type stored: FLOAT, bit-exact
        header.compression_type = TINYEXR_COMPRESSIONTYPE_NONE; // one scanline per block
        EXRImage exr;
        InitEXRImage(&exr);
        exr.num_channels = int(nc);
        exr.width = int(image.width);
        exr.height = int(image.height);
        exr.images = planePointers.data();

        unsigned char* memory = nullptr;
        const char* err = nullptr;
        const size_t size = SaveEXRImageToMemory(&exr, &header, &memory, &err);
        MallocBytes owned(memory);
        if (size == 0 || memory == nullptr) {
            std::string why = err != nullptr ? err : "no reason given";
            if (err != nullptr) FreeEXRErrorMessage(err);
            while (!why.empty() && why.back() == '\n') why.pop_back();
            return makeError(FormatError::LimitExceeded, 0,
                             "EXR image: tinyexr failed on %ux%ux%u: %s", image.width,
                             image.height, image.channels, why.c_str());
        }
        return std::vector<uint8_t>(memory, memory + size);
    } catch (const std::bad_alloc&) {
        return makeError(FormatError::LimitExceeded, 0, "EXR image: out of memory encoding %ux%ux%u",
                         image.width, image.height, image.channels);
    }
}

} // namespace

Status checkPngImage(const ImageView& image) {
    if (Status s = checkView(image, "PNG", false); !isOk(s)) return s;
    if (image.width > kMaxInt32 || image.height > kMaxInt32)
        return makeError(FormatError::LimitExceeded, 0,
                         "PNG image: %ux%u exceeds the format's 2^31-1 limit per dimension",
                         image.width, image.height);
    const uint64_t rowBytes = uint64_t(image.width) * image.channels;
    if (rowBytes > kMaxPngRowBytes)
        return makeError(FormatError::LimitExceeded, 0,
                         "PNG image: a %u-pixel row of %u channels is %llu bytes, over the "
                         "encoder's limit of %llu bytes per row",
                         image.width, image.channels, static_cast<unsigned long long>(rowBytes),
                         static_cast<unsigned long long>(kMaxPngRowBytes));
    const uint64_t filtered = (rowBytes + 1) * image.height; // < 2^24 * 2^31: no overflow
    if (filtered > kMaxPngFilteredBytes)
        return makeError(FormatError::LimitExceeded, 0,
                         "PNG image: %ux%ux%u is %llu bytes of scanlines, over the encoder's "
                         "limit of %llu (2 GiB - 16 MiB)",
                         image.width, image.height, image.channels,
                         static_cast<unsigned long long>(filtered),
                         static_cast<unsigned long long>(kMaxPngFilteredBytes));
    return {};
}

Status checkExrImage(const ImageView& image) {
    if (Status s = checkView(image, "EXR", true); !isOk(s)) return s;
    // dataWindow holds int32 maxima, and a block's data size is an int32.
    if (image.width > kMaxInt32 || image.height > kMaxInt32)
        return makeError(FormatError::LimitExceeded, 0,
                         "EXR image: %ux%u exceeds the format's 2^31-1 limit per dimension",
                         image.width, image.height);
    if (uint64_t(image.width) * image.channels * 4 > kMaxInt32)
        return makeError(FormatError::LimitExceeded, 0,
                         "EXR image: a %u-pixel scanline of %u float channels exceeds the "
                         "2^31-1 byte block limit",
                         image.width, image.channels);
    return {};
}

std::vector<uint8_t> encodePng(const ImageView& image) {
    auto r = encodePngChecked(image);
    return r.ok() ? std::move(r).value() : std::vector<uint8_t>{};
}

std::vector<uint8_t> encodeExr(const ImageView& image) {
    auto r = encodeExrChecked(image);
    return r.ok() ? std::move(r).value() : std::vector<uint8_t>{};
}

Status writePng(const std::string& path, const ImageView& image) {
    auto bytes = encodePngChecked(image);
    if (!bytes.ok()) return bytes.error();
    return writeFileAtomic(path, *bytes);
}

Status writeExr(const std::string& path, const ImageView& image) {
    auto bytes = encodeExrChecked(image);
    if (!bytes.ok()) return bytes.error();
    return writeFileAtomic(path, *bytes);
}

} // namespace pnb::player
