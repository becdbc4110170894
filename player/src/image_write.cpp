// PNG and OpenEXR writers by hand (see image_write.h for the scope and the specs).

#include "pnb_player/image_write.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <limits>
#include <sys/stat.h>
#include <unistd.h>

#include <zlib.h>

namespace pnb::player {

namespace {

constexpr uint32_t kMaxInt32 = uint32_t(std::numeric_limits<int32_t>::max());

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

// ---------------------------------------------------------------------------------------------
// PNG

void putBe32(std::vector<uint8_t>& out, uint32_t v) {
    out.push_back(uint8_t(v >> 24));
    out.push_back(uint8_t(v >> 16));
    out.push_back(uint8_t(v >> 8));
    out.push_back(uint8_t(v));
}

// length, type, data, CRC-32 of type+data (PNG §5.3).
void putPngChunk(std::vector<uint8_t>& out, const char (&type)[5], const uint8_t* data,
                 size_t size) {
    putBe32(out, uint32_t(size));
    const auto* typeBytes = reinterpret_cast<const uint8_t*>(type);
    out.insert(out.end(), typeBytes, typeBytes + 4);
    if (size > 0) out.insert(out.end(), data, data + size);
    uLong crc = crc32(0L, Z_NULL, 0);
    crc = crc32(crc, typeBytes, 4);
    // crc32 takes a uInt length: feed large chunks in pieces.
    for (size_t done = 0; done < size;) {
        uInt n = uInt(std::min<size_t>(size - done, 1u << 30));
        crc = crc32(crc, data + done, n);
        done += n;
    }
    putBe32(out, uint32_t(crc));
}

uint8_t paeth(int a, int b, int c) {
    int p = a + b - c;
    int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    if (pa <= pb && pa <= pc) return uint8_t(a);
    if (pb <= pc) return uint8_t(b);
    return uint8_t(c);
}

// Filters one row with filter type `type` (PNG §9.2) into out[0..n). prev is the unfiltered
// previous row (all zero for the first row); bpp = bytes per complete pixel.
void filterRow(int type, const uint8_t* row, const uint8_t* prev, size_t n, size_t bpp,
               uint8_t* out) {
    for (size_t i = 0; i < n; ++i) {
        int a = i >= bpp ? row[i - bpp] : 0;
        int b = prev[i];
        int c = i >= bpp ? prev[i - bpp] : 0;
        int predictor = 0;
        switch (type) {
        case 1: predictor = a; break;
        case 2: predictor = b; break;
        case 3: predictor = (a + b) / 2; break;
        case 4: predictor = paeth(a, b, c); break;
        default: break;
        }
        out[i] = uint8_t(row[i] - predictor);
    }
}

// The PNG spec's recommended heuristic (§12.8): the filter whose output, read as signed bytes,
// has the smallest sum of absolute values.
uint64_t filterCost(const uint8_t* bytes, size_t n) {
    uint64_t sum = 0;
    for (size_t i = 0; i < n; ++i) sum += uint64_t(std::abs(int(int8_t(bytes[i]))));
    return sum;
}

Result<std::vector<uint8_t>> encodePngChecked(const ImageView& image) {
    if (Status s = checkPngImage(image); !isOk(s)) return s;
    const size_t bpp = image.channels;
    const size_t rowBytes = size_t(image.width) * bpp;
    const size_t rawSize = (rowBytes + 1) * image.height;

    // Filtered scanlines, each prefixed by its filter type byte.
    std::vector<uint8_t> filtered(rawSize);
    std::vector<uint8_t> zeros(rowBytes, 0), candidate(rowBytes);
    const uint8_t* pixels = image.u8.data();
    for (size_t y = 0; y < image.height; ++y) {
        const uint8_t* row = pixels + y * rowBytes;
        const uint8_t* prev = y > 0 ? row - rowBytes : zeros.data();
        uint8_t* dst = filtered.data() + y * (rowBytes + 1);
        filterRow(0, row, prev, rowBytes, bpp, dst + 1);
        dst[0] = 0;
        uint64_t best = filterCost(dst + 1, rowBytes);
        for (int type = 1; type <= 4; ++type) {
            filterRow(type, row, prev, rowBytes, bpp, candidate.data());
            uint64_t cost = filterCost(candidate.data(), rowBytes);
            if (cost < best) {
                best = cost;
                dst[0] = uint8_t(type);
                std::copy(candidate.begin(), candidate.end(), dst + 1);
            }
        }
    }

    uLongf compressedSize = compressBound(uLong(rawSize));
    std::vector<uint8_t> compressed(compressedSize);
    int zr = compress2(compressed.data(), &compressedSize, filtered.data(), uLong(rawSize), 6);
    if (zr != Z_OK)
        return makeError(FormatError::LimitExceeded, 0,
                         "PNG image: zlib compress2 failed (code %d) on %zu bytes", zr, rawSize);
    compressed.resize(compressedSize);
    filtered = {};

    std::vector<uint8_t> out;
    out.reserve(compressed.size() + 128);
    static constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    out.insert(out.end(), kSignature, kSignature + 8);

    static constexpr uint8_t kColourType[5] = {0, 0 /*grey*/, 4 /*grey+alpha*/, 2 /*RGB*/,
                                               6 /*RGBA*/};
    std::vector<uint8_t> ihdr;
    putBe32(ihdr, image.width);
    putBe32(ihdr, image.height);
    ihdr.push_back(8);                            // bit depth
    ihdr.push_back(kColourType[image.channels]);  // colour type
    ihdr.push_back(0);                            // compression method: deflate
    ihdr.push_back(0);                            // filter method: adaptive, 5 types
    ihdr.push_back(0);                            // no interlace
    putPngChunk(out, "IHDR", ihdr.data(), ihdr.size());

    // IDAT chunks of at most 1 MiB (the zlib stream may be split anywhere between IDATs).
    constexpr size_t kIdatMax = size_t(1) << 20;
    for (size_t done = 0; done < compressed.size();) {
        size_t n = std::min(compressed.size() - done, kIdatMax);
        putPngChunk(out, "IDAT", compressed.data() + done, n);
        done += n;
    }
    putPngChunk(out, "IEND", nullptr, 0);
    return out;
}

// ---------------------------------------------------------------------------------------------
// OpenEXR

void putLe32(std::vector<uint8_t>& out, uint32_t v) {
    out.push_back(uint8_t(v));
    out.push_back(uint8_t(v >> 8));
    out.push_back(uint8_t(v >> 16));
    out.push_back(uint8_t(v >> 24));
}

void putLe64(std::vector<uint8_t>& out, uint64_t v) {
    putLe32(out, uint32_t(v));
    putLe32(out, uint32_t(v >> 32));
}

void putFloat(std::vector<uint8_t>& out, float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    putLe32(out, bits);
}

void putString(std::vector<uint8_t>& out, const char* s) {
    out.insert(out.end(), s, s + std::strlen(s) + 1); // with the terminating null
}

// Attribute: name\0 type\0 int32 size, value bytes.
void putAttribute(std::vector<uint8_t>& out, const char* name, const char* type,
                  const std::vector<uint8_t>& value) {
    putString(out, name);
    putString(out, type);
    putLe32(out, uint32_t(value.size()));
    out.insert(out.end(), value.begin(), value.end());
}

struct ExrChannel {
    const char* name;
    uint32_t source; // index in the interleaved input pixel
};

// Channels sorted by name (OpenEXR requires the chlist, and so the per-line channel order, to
// be in ascending name order).
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
    const std::vector<ExrChannel> channels = exrChannels(image.channels);
    const uint32_t w = image.width, h = image.height, nc = image.channels;
    const uint64_t lineBytes = uint64_t(w) * nc * 4;

    std::vector<uint8_t> out;
    putLe32(out, 20000630); // magic
    putLe32(out, 2);        // version 2; no flags: single-part scanline, names < 32 chars

    std::vector<uint8_t> v;
    for (const ExrChannel& c : channels) {
        putString(v, c.name);
        putLe32(v, 2);                  // pixel type FLOAT
        v.insert(v.end(), {0, 0, 0, 0}); // pLinear = 0, 3 reserved bytes
        putLe32(v, 1);                  // xSampling
        putLe32(v, 1);                  // ySampling
    }
    v.push_back(0); // end of the channel list
    putAttribute(out, "channels", "chlist", v);
    putAttribute(out, "compression", "compression", {0}); // NO_COMPRESSION

    v.clear();
    putLe32(v, 0); // xMin
    putLe32(v, 0); // yMin
    putLe32(v, w - 1);
    putLe32(v, h - 1);
    putAttribute(out, "dataWindow", "box2i", v);
    putAttribute(out, "displayWindow", "box2i", v);
    putAttribute(out, "lineOrder", "lineOrder", {0}); // INCREASING_Y

    v.clear();
    putFloat(v, 1.0f);
    putAttribute(out, "pixelAspectRatio", "float", v);
    v.clear();
    putFloat(v, 0.0f);
    putFloat(v, 0.0f);
    putAttribute(out, "screenWindowCenter", "v2f", v);
    v.clear();
    putFloat(v, 1.0f);
    putAttribute(out, "screenWindowWidth", "float", v);
    out.push_back(0); // end of the header

    // Line offset table: absolute file offsets of each scanline block.
    const uint64_t blockBytes = 8 + lineBytes;
    const uint64_t firstBlock = out.size() + uint64_t(h) * 8;
    out.reserve(size_t(firstBlock + blockBytes * h));
    for (uint32_t y = 0; y < h; ++y) putLe64(out, firstBlock + uint64_t(y) * blockBytes);

    // Blocks: int y, int data size, then each channel's row in chlist order.
    const float* pixels = image.f32.data();
    for (uint32_t y = 0; y < h; ++y) {
        putLe32(out, y);
        putLe32(out, uint32_t(lineBytes));
        const float* row = pixels + size_t(y) * w * nc;
        for (const ExrChannel& c : channels)
            for (uint32_t x = 0; x < w; ++x) putFloat(out, row[size_t(x) * nc + c.source]);
    }
    return out;
}

} // namespace

Status checkPngImage(const ImageView& image) {
    if (Status s = checkView(image, "PNG", false); !isOk(s)) return s;
    if (image.width > kMaxInt32 || image.height > kMaxInt32)
        return makeError(FormatError::LimitExceeded, 0,
                         "PNG image: %ux%u exceeds the format's 2^31-1 limit per dimension",
                         image.width, image.height);
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
