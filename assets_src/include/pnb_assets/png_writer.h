// pnb_assets/png_writer.h — the procedural scenes' PNG textures, and the checksums tests use to
// craft PNG and zlib streams by hand.
//
// encodePng is pnb::player::encodePng (pnb_player/image_write.h, library pnb_image_write:
// stb_image_write with zlib) under the signature the scene generator calls: one PNG encoder for
// the player's screenshots and the generated textures. 8-bit grey, grey+alpha, RGB or RGBA,
// adaptive filters, deflate level 6, no ancillary chunks (no timestamps: the output is
// byte-for-byte deterministic for one zlib version).
//
// crc32 and adler32 are zlib's, with spans and a continuation argument.
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

// Encodes a `width` x `height` image with `channels` (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA) 8-bit
// samples per pixel, rows top to bottom, tightly packed (pixels.size() == width * height *
// channels). Preconditions (checked; a violation aborts with pnb_image_write's message): width,
// height >= 1; channels 1..4; the size matches; within pnb_image_write's PNG limits.
// Returns the complete PNG file. Deterministic: the same pixels give the same bytes.
std::vector<uint8_t> encodePng(uint32_t width, uint32_t height, uint32_t channels,
                               std::span<const uint8_t> pixels);

} // namespace pnb::assets
