// pnb_assets/png_writer.h — a minimal PNG encoder for the procedural scenes' small textures.
//
// Writes 8-bit RGB or RGBA images as a valid PNG whose zlib stream uses only *stored*
// (uncompressed) deflate blocks, so no compression library is needed. The files are larger than
// a real encoder's, which is fine for the few small checker textures the procedural scenes embed.
//
// Does NOT do: compression, filtering (every scanline uses filter type 0), palettes, 16-bit
// channels, interlacing, ancillary chunks (no gAMA/sRGB/tIME, so no timestamps and the output is
// byte-for-byte deterministic).
//
// Based on: the PNG specification (W3C, 2nd edition), RFC 1950 (zlib) and RFC 1951 (deflate,
// section 3.2.4 for stored blocks).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pnb::assets {

// CRC-32 as PNG and zlib define it (reflected polynomial 0xEDB88320, initial value and final XOR
// 0xFFFFFFFF). `crc` continues a previous call's result; pass 0 to start. Thread-safe.
// Check value: crc32("123456789") == 0xCBF43926.
uint32_t crc32(std::span<const uint8_t> bytes, uint32_t crc = 0);

// Adler-32 as zlib defines it (RFC 1950 section 8.2). `adler` continues a previous call's result;
// pass 1 to start. Thread-safe. Check value: adler32("Wikipedia") == 0x11E60398.
uint32_t adler32(std::span<const uint8_t> bytes, uint32_t adler = 1);

// Encodes a `width` x `height` image with `channels` (3 = RGB, 4 = RGBA) 8-bit samples per
// pixel, rows top to bottom, tightly packed (pixels.size() == width * height * channels).
// Preconditions (asserted): width, height >= 1; channels is 3 or 4; the size matches.
// Returns the complete PNG file. Deterministic: the same pixels give the same bytes.
std::vector<uint8_t> encodePng(uint32_t width, uint32_t height, uint32_t channels,
                               std::span<const uint8_t> pixels);

} // namespace pnb::assets
