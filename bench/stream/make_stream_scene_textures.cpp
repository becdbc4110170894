// make_stream_scene_textures.cpp — pnb-make-stream-scene's texels: each panel's texture (hue,
// checkers, border, digits on a grid of 8x8-texel cells) and every mip level as the exact box
// filter of level 0, built straight into TMIP payloads. A part of its own: it is the tool's
// bulk of bytes and the only part the producer thread runs (make_stream_scene.h).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "make_stream_scene.h"

namespace stream_scene {

// [SECTION] texels

uint32_t mipCountFor(uint32_t size) {
    uint32_t n = 1;
    while (size > 1) {
        size >>= 1;
        ++n;
    }
    return n;
}

uint64_t tmipFileBytes(uint32_t w, uint32_t h) {
    return alignUp(kChunkHeaderSize + kTmipPrefix + uint64_t(w) * h * 4) + kTocEntryBytes;
}

namespace {

// 3x5 digit glyphs, one row per 3 bits (bit 2 = left column), top row first.
constexpr std::array<std::array<uint8_t, 5>, 10> kDigits = {{
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 2, 2, 2}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
}};

bool glyphPixel(uint32_t digit, int gx, int gy) {
    if (gx < 0 || gx > 2 || gy < 0 || gy > 4) return false;
    return (kDigits[digit % 10][size_t(gy)] >> (2 - gx)) & 1u;
}

struct Rgb {
    float r = 0, g = 0, b = 0;
};

// Linear RGB of hue h (0..1) at saturation s and value v.
Rgb hsv(float h, float s, float v) {
    float h6 = (h - std::floor(h)) * 6.0f;
    int sector = int(h6) % 6;
    float f = h6 - float(int(h6));
    float p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    switch (sector) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
    }
}

// The texture of panel `index`: a grid of cells x cells linear colours, each cell 8x8 level-0
// texels (for textures smaller than 64 texels, fewer texels a cell; the grid is then 8x8).
struct CellGrid {
    uint32_t cells = 0;       // a side
    uint32_t cellTexels = 0;  // level-0 texels a side of one cell
    std::vector<Rgb> colour;  // row-major, row 0 = top of the image
};

CellGrid makeCellGrid(uint32_t index, uint32_t textureSize) {
    CellGrid g;
    g.cellTexels = std::min<uint32_t>(8, textureSize / 8);
    g.cells = textureSize / g.cellTexels;
    const int n = int(g.cells);
    g.colour.resize(size_t(n) * size_t(n));
    // Hue by the golden ratio: neighbouring panels differ clearly.
    const float hue = std::fmod(0.13f + float(index) * 0.6180339887f, 1.0f);
    const Rgb base = hsv(hue, 0.65f, 0.75f);
    const Rgb dark = hsv(hue + 0.5f, 0.5f, 0.12f);
    const Rgb light{0.9f, 0.9f, 0.88f};
    const int block = std::max(1, n / 32);  // 32 checker squares a side (64 texels at 2048)
    // The big number: the panel index in decimal, 3x5 glyphs with one blank column between.
    std::string number = std::to_string(index);
    const int digits = int(number.size());
    const int glyphW = digits * 4 - 1; // in glyph pixels
    const int bigPixel = std::max(1, std::min(n * 3 / 4 / glyphW, n / 2 / 5));
    const int bigX0 = (n - glyphW * bigPixel) / 2, bigY0 = (n - 5 * bigPixel) / 2;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            int bx = x / block, by = y / block;
            float shade = ((bx + by) & 1) ? 1.0f : 0.55f;
            shade *= ((x + y) & 1) ? 1.0f : 0.85f; // the fine checker (one cell)
            Rgb c{base.r * shade, base.g * shade, base.b * shade};
            // Small digit (last digit of the index) in each checker square, 1-cell strokes.
            if (block >= 8 && glyphPixel(index % 10, x % block - 2, y % block - 1)) c = dark;
            // Border, two cells wide.
            if (x < 2 || y < 2 || x >= n - 2 || y >= n - 2) c = dark;
            int gx = x - bigX0, gy = y - bigY0;
            if (gx >= 0 && gy >= 0 && gx < glyphW * bigPixel && gy < 5 * bigPixel) {
                int px = gx / bigPixel, py = gy / bigPixel;
                int d = px / 4;
                if (px % 4 != 3 && glyphPixel(uint32_t(number[size_t(d)] - '0'), px % 4, py))
                    c = light;
            }
            g.colour[size_t(y) * size_t(n) + size_t(x)] = c;
        }
    }
    return g;
}

// Level `level` of a texture of `textureSize` texels: the exact box filter of level 0.
// Levels whose texels are no bigger than a cell repeat cells; coarser ones average cells.
void makeLevel(const CellGrid& g, uint32_t textureSize, uint32_t level, const SrgbEncoder& srgb,
               std::byte* out) {
    const uint32_t size = std::max(1u, textureSize >> level);
    const uint32_t texelSpan = 1u << level; // level-0 texels a side of one texel here
    if (texelSpan <= g.cellTexels) {
        const uint32_t repeat = g.cellTexels / texelSpan; // texels a side of one cell here
        std::vector<uint32_t> row(size);
        for (uint32_t cy = 0; cy < g.cells; ++cy) {
            for (uint32_t cx = 0; cx < g.cells; ++cx) {
                const Rgb& c = g.colour[size_t(cy) * g.cells + cx];
                uint32_t px = uint32_t(srgb(c.r)) | uint32_t(srgb(c.g)) << 8 |
                              uint32_t(srgb(c.b)) << 16 | 0xFF000000u;
                std::fill_n(row.begin() + cx * repeat, repeat, px);
            }
            for (uint32_t r = 0; r < repeat; ++r)
                std::memcpy(out + (size_t(cy) * repeat + r) * size * 4, row.data(), size * 4);
        }
        return;
    }
    const uint32_t k = texelSpan / g.cellTexels; // cells a side averaged into one texel
    const float inv = 1.0f / float(k * k);
    for (uint32_t y = 0; y < size; ++y) {
        for (uint32_t x = 0; x < size; ++x) {
            Rgb sum;
            for (uint32_t j = 0; j < k; ++j)
                for (uint32_t i = 0; i < k; ++i) {
                    const Rgb& c = g.colour[size_t(y * k + j) * g.cells + x * k + i];
                    sum.r += c.r;
                    sum.g += c.g;
                    sum.b += c.b;
                }
            std::byte* p = out + (size_t(y) * size + x) * 4;
            p[0] = std::byte(srgb(sum.r * inv));
            p[1] = std::byte(srgb(sum.g * inv));
            p[2] = std::byte(srgb(sum.b * inv));
            p[3] = std::byte(0xFF);
        }
    }
}

void putU32(std::byte* p, uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = std::byte((v >> (8 * i)) & 0xFF);
}
void putU64(std::byte* p, uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = std::byte((v >> (8 * i)) & 0xFF);
}

} // namespace

void buildMip(MipJob& job, uint32_t textureSize, const SrgbEncoder& srgb) {
    const uint64_t bytes = uint64_t(job.size) * job.size * 4;
    job.payload.resize(kTmipPrefix + bytes); // capacity is reused from job to job
    std::byte* p = job.payload.data();
    putU32(p + 0, job.texture);
    putU32(p + 4, job.level);
    putU32(p + 8, job.size);
    putU32(p + 12, job.size);
    putU64(p + 16, bytes);
    putU64(p + 24, 0); // padding to the 16-byte boundary of the payload
    CellGrid g = makeCellGrid(job.texture, textureSize);
    makeLevel(g, textureSize, job.level, srgb, p + kTmipPrefix);
}

// The hand-made layout must be encodeChunk's.
bool checkPayload(const MipJob& job) {
    TextureMip m{job.texture, job.level, job.size, job.size,
                 Blob(job.payload.data() + kTmipPrefix, job.payload.size() - kTmipPrefix)};
    std::vector<std::byte> reference = encodeChunk(m);
    return reference == job.payload;
}

} // namespace stream_scene
