// Minimal stored-deflate PNG encoder (see png_writer.h).
//
// Based on: PNG specification 2nd edition (chunk layout, CRC), RFC 1950 (zlib header, Adler-32
// trailer), RFC 1951 section 3.2.4 (non-compressed blocks).

#include "pnb_assets/png_writer.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <string_view>

namespace pnb::assets {

namespace {

constexpr std::array<uint32_t, 256> makeCrcTable() {
    std::array<uint32_t, 256> table{};
    for (uint32_t n = 0; n < 256; ++n) {
        uint32_t c = n;
        for (int k = 0; k < 8; ++k)
            c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        table[n] = c;
    }
    return table;
}
constexpr std::array<uint32_t, 256> kCrcTable = makeCrcTable();

void putU32BE(std::vector<uint8_t>& out, uint32_t v) {
    out.insert(out.end(), {uint8_t(v >> 24), uint8_t(v >> 16), uint8_t(v >> 8), uint8_t(v)});
}

// Appends one PNG chunk: length, type, data, CRC over type + data.
void putChunk(std::vector<uint8_t>& out, std::string_view type, std::span<const uint8_t> data) {
    assert(type.size() == 4);
    putU32BE(out, uint32_t(data.size()));
    size_t typeAt = out.size();
    out.insert(out.end(), type.begin(), type.end());
    out.insert(out.end(), data.begin(), data.end());
    uint32_t crc = crc32(std::span<const uint8_t>(out.data() + typeAt, 4 + data.size()));
    putU32BE(out, crc);
}

} // namespace

uint32_t crc32(std::span<const uint8_t> bytes, uint32_t crc) {
    crc = ~crc;
    for (uint8_t b : bytes)
        crc = kCrcTable[(crc ^ b) & 0xFFu] ^ (crc >> 8);
    return ~crc;
}

uint32_t adler32(std::span<const uint8_t> bytes, uint32_t adler) {
    // 5552 is the largest n for which 255n(n+1)/2 + (n+1)(65521-1) fits in 32 bits, so the
    // modulo can wait that long (the same constant zlib uses).
    constexpr uint32_t kMod = 65521, kBlock = 5552;
    uint32_t a = adler & 0xFFFFu, b = adler >> 16;
    size_t i = 0;
    while (i < bytes.size()) {
        size_t end = std::min(bytes.size(), i + kBlock);
        for (; i < end; ++i) {
            a += bytes[i];
            b += a;
        }
        a %= kMod;
        b %= kMod;
    }
    return (b << 16) | a;
}

std::vector<uint8_t> encodePng(uint32_t width, uint32_t height, uint32_t channels,
                               std::span<const uint8_t> pixels) {
    assert(width >= 1 && height >= 1);
    assert(channels == 3 || channels == 4);
    const size_t rowBytes = size_t(width) * channels;
    assert(pixels.size() == rowBytes * height);

    // Raw image data: each scanline is prefixed by its filter type (0 = None).
    std::vector<uint8_t> raw;
    raw.reserve((rowBytes + 1) * height);
    for (uint32_t y = 0; y < height; ++y) {
        raw.push_back(0);
        auto row = pixels.subspan(y * rowBytes, rowBytes);
        raw.insert(raw.end(), row.begin(), row.end());
    }

    // zlib stream: CMF 0x78 (deflate, 32K window), FLG 0x01 (no dictionary, fastest level;
    // 0x7801 is a multiple of 31 as the FCHECK bits require), stored blocks, Adler-32 of raw.
    std::vector<uint8_t> zlib = {0x78, 0x01};
    constexpr size_t kMaxStored = 65535; // LEN is 16 bits
    size_t at = 0;
    do {
        size_t len = std::min(kMaxStored, raw.size() - at);
        bool last = at + len == raw.size();
        // BFINAL in bit 0, BTYPE = 00 (stored); the rest of the byte is padding to the
        // byte boundary that stored blocks require.
        zlib.push_back(last ? 1 : 0);
        zlib.insert(zlib.end(),
                    {uint8_t(len), uint8_t(len >> 8), uint8_t(~len), uint8_t(~len >> 8)});
        zlib.insert(zlib.end(), raw.begin() + ptrdiff_t(at), raw.begin() + ptrdiff_t(at + len));
        at += len;
    } while (at < raw.size());
    putU32BE(zlib, adler32(raw));

    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::vector<uint8_t> ihdr;
    putU32BE(ihdr, width);
    putU32BE(ihdr, height);
    // Bit depth 8; colour type 2 (RGB) or 6 (RGBA); compression, filter, interlace methods 0.
    ihdr.insert(ihdr.end(), {8, uint8_t(channels == 4 ? 6 : 2), 0, 0, 0});
    putChunk(png, "IHDR", ihdr);
    putChunk(png, "IDAT", zlib);
    putChunk(png, "IEND", {});
    return png;
}

} // namespace pnb::assets
