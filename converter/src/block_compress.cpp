// converter/src/block_compress.cpp — BC1/BC3/BC4/BC5 with libsquish 1.15, and the PSNR it costs.
//
// Does NOT do: BC6H/BC7 (libsquish has neither; HDR textures stay 16-bit float), choosing what
// is stored where (channel_packing.cpp has already put the channels at the positions these
// formats read: BC4 R, BC5 R G, BC1 R G B, BC3 R G B A).
//
// Notes:
// - Blocks are compressed one by one with squish::CompressMasked, which is exactly what
//   squish::CompressImage does internally, minus its OpenMP loop: Debian builds libsquish with
//   OpenMP, and every pool worker entering an OpenMP region starts its own team of
//   hardware_concurrency threads (jobs² threads in all), ignoring --jobs. Texture-level
//   parallelism in texture_processing.cpp keeps the cores busy instead.
// - Colour fit: kColourClusterFit, libsquish's default. Measured with Debian's libsquish on the
//   2-core development machine: cluster fit ~33 µs per block, range fit ~0.7 µs, for about 1 dB
//   more PSNR on gradients and photo-like content (BC1 on the tests' 62×46 gradient: 37.8 vs
//   36.7 dB; 256² gradient 45.9 vs 44.7 dB); iterative cluster fit costs 1.5–2× cluster fit for
//   under 0.3 dB. A 2048² BC1/BC3 level 0 therefore takes ~9 s of CPU, once per conversion,
//   which is where ARCHITECTURE.md puts the expensive work; range fit is the switch to flip if
//   conversion time ever matters more than the last dB. Uniform channel weights: sRGB data is
//   already perceptually spaced, and linear data is not colour.
// - libsquish 1.15 compresses BC4/BC5 (from R and R, G) but its Decompress does not decode them
//   (it falls back to BC1); a BC4 block is bit-for-bit a BC3 alpha block, so decoding goes
//   through the BC3 alpha decoder.
#include <squish.h>

#include <cassert>
#include <cmath>
#include <cstring>

#include "texture_internal.h"

namespace pnb::converter::texture_detail {

namespace {

constexpr int kColourFit = squish::kColourClusterFit;

size_t blockBytes(TextureFormat f) {
    return f == TextureFormat::BC1 || f == TextureFormat::BC4 ? 8 : 16;
}

int squishFlags(TextureFormat f) {
    switch (f) {
    case TextureFormat::BC1:
        return squish::kDxt1 | kColourFit;
    case TextureFormat::BC3:
        return squish::kDxt5 | kColourFit;
    case TextureFormat::BC4:
        return squish::kBc4;
    case TextureFormat::BC5:
        return squish::kBc5;
    default:
        assert(false && "not a libsquish format");
        return 0;
    }
}

// Decodes a BC4 block (8 bytes) into channel `channel` of 16 RGBA texels.
void decodeBc4(const std::byte* block, uint8_t* rgba, int channel) {
    uint8_t bc3[16] = {}; // alpha block + an all-zero colour block
    std::memcpy(bc3, block, 8);
    uint8_t decoded[64];
    squish::Decompress(decoded, bc3, squish::kDxt5);
    for (int i = 0; i < 16; ++i)
        rgba[i * 4 + channel] = decoded[i * 4 + 3];
}

} // namespace

TextureFormat blockFormatFor(uint32_t positions) {
    static constexpr TextureFormat kFormats[] = {TextureFormat::BC4, TextureFormat::BC5,
                                                 TextureFormat::BC1, TextureFormat::BC3};
    assert(positions >= 1 && positions <= 4);
    return kFormats[positions - 1];
}

std::vector<std::byte> compressLevel(const std::vector<std::byte>& packed, uint32_t positions,
                                     uint32_t width, uint32_t height, TextureFormat format) {
    assert(packed.size() == size_t(width) * height * positions);
    uint32_t blocksX = (width + 3) / 4, blocksY = (height + 3) / 4;
    size_t bytes = blockBytes(format);
    std::vector<std::byte> out(size_t(blocksX) * blocksY * bytes);
    int flags = squishFlags(format);
    for (uint32_t by = 0; by < blocksY; ++by) {
        for (uint32_t bx = 0; bx < blocksX; ++bx) {
            // Texels outside the level are masked out: they take no part in the endpoint fit.
            uint8_t rgba[64] = {};
            int mask = 0;
            for (uint32_t py = 0; py < 4; ++py) {
                for (uint32_t px = 0; px < 4; ++px) {
                    uint32_t x = bx * 4 + px, y = by * 4 + py;
                    if (x >= width || y >= height) continue;
                    uint32_t k = py * 4 + px;
                    mask |= 1 << k;
                    const std::byte* src = &packed[(size_t(y) * width + x) * positions];
                    for (uint32_t p = 0; p < positions; ++p)
                        rgba[k * 4 + p] = uint8_t(src[p]);
                    // BC1 input has no alpha: opaque, or squish would pick the punch-through
                    // mode for texels below 128.
                    if (positions < 4) rgba[k * 4 + 3] = 255;
                }
            }
            void* block = &out[(size_t(by) * blocksX + bx) * bytes];
            squish::CompressMasked(rgba, mask, block, flags);
        }
    }
    return out;
}

std::vector<uint8_t> decompressLevel(const std::vector<std::byte>& blocks, uint32_t positions,
                                     uint32_t width, uint32_t height, TextureFormat format) {
    uint32_t blocksX = (width + 3) / 4, blocksY = (height + 3) / 4;
    size_t bytes = blockBytes(format);
    assert(blocks.size() == size_t(blocksX) * blocksY * bytes);
    std::vector<uint8_t> out(size_t(width) * height * positions);
    for (uint32_t by = 0; by < blocksY; ++by) {
        for (uint32_t bx = 0; bx < blocksX; ++bx) {
            const std::byte* block = &blocks[(size_t(by) * blocksX + bx) * bytes];
            uint8_t rgba[64] = {};
            switch (format) {
            case TextureFormat::BC1:
                squish::Decompress(rgba, block, squish::kDxt1);
                break;
            case TextureFormat::BC3:
                squish::Decompress(rgba, block, squish::kDxt5);
                break;
            case TextureFormat::BC4:
                decodeBc4(block, rgba, 0);
                break;
            case TextureFormat::BC5:
                decodeBc4(block, rgba, 0);
                decodeBc4(block + 8, rgba, 1);
                break;
            default:
                assert(false && "not a libsquish format");
                break;
            }
            for (uint32_t py = 0; py < 4; ++py) {
                for (uint32_t px = 0; px < 4; ++px) {
                    uint32_t x = bx * 4 + px, y = by * 4 + py;
                    if (x >= width || y >= height) continue;
                    uint8_t* dst = &out[(size_t(y) * width + x) * positions];
                    for (uint32_t p = 0; p < positions; ++p)
                        dst[p] = rgba[(py * 4 + px) * 4 + p];
                }
            }
        }
    }
    return out;
}

double psnrDb(const std::vector<std::byte>& original, const std::vector<uint8_t>& decoded,
              uint32_t positions, const std::array<bool, 4>& used) {
    assert(original.size() == decoded.size());
    double sum = 0;
    size_t count = 0;
    for (size_t i = 0; i < original.size(); ++i) {
        if (!used[i % positions]) continue;
        double d = double(uint8_t(original[i])) - double(decoded[i]);
        sum += d * d;
        ++count;
    }
    if (count == 0 || sum == 0) return 0;
    return 10.0 * std::log10(255.0 * 255.0 / (sum / double(count)));
}

} // namespace pnb::converter::texture_detail
