// pnb_player/image_write.h — minimal PNG and OpenEXR writers for the player's screenshots and
// golden-image captures, with no image library (only zlib, for PNG's deflate and CRC-32).
//
// Does: 8-bit PNG in grey, grey+alpha, RGB and RGBA (non-interlaced, deflate level 6, one
// adaptive filter per row chosen by the minimum-sum-of-absolute-differences heuristic);
// single-part scanline OpenEXR with NO_COMPRESSION and 32-bit FLOAT channels, one scanline per
// block. Files are written atomically: built under "<dir>/.<name>.tmp.<pid>.<n>", fsync'ed and
// renamed over the target, so an interrupted write leaves any previous file intact and never a
// partial one; the temporary is removed on every error path.
//
// Does NOT do: reading; 16-bit PNG, palettes, interlacing, or any ancillary PNG chunk (no
// sRGB/gAMA/iCCP: samples are stored exactly as given, so 8-bit data is assumed to be sRGB-encoded
// as usual); EXR half or uint channels, compression, tiles, mipmaps, multi-part or deep data,
// metadata beyond the required attributes; colour conversion, premultiplication or clamping (EXR
// floats, including NaN/Inf, are stored bit-exactly).
//
// Specs: PNG — ISO/IEC 15948:2004 / W3C "Portable Network Graphics (PNG) Specification (Second
// Edition)" (chunk layout, IHDR, filter method 0, zlib stream, CRC-32). OpenEXR — "OpenEXR File
// Layout" (openexr.com): magic 20000630, version 2 with no flags (single-part scanline, short
// names), attribute header with the required attributes, chlist sorted by name, line offset
// table, scanline blocks {int y, int size, per-channel rows in chlist order}, all little-endian.
//
// Errors (pnb::Status, see pnb/error.h): an ImageView that breaks its preconditions yields
// BadPayload (zero size, channels outside 1..4, wrong span for the format, sample count not
// width*height*channels) or LimitExceeded (dimensions beyond what the format can store); the
// message names the problem. File system failures yield IoError.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "pnb/atomic_file.h"
#include "pnb/error.h"

namespace pnb::player {

// Interleaved pixels, rows top-to-bottom, tightly packed (row stride = width * channels).
struct ImageView {
    uint32_t width = 0, height = 0, channels = 0; // channels: 1..4
    std::span<const uint8_t> u8;                  // exactly one of u8 / f32 is non-empty
    std::span<const float> f32;
};

// Checks the preconditions of encodePng / encodeExr without encoding anything: success, or the
// error the corresponding write function would return.
Status checkPngImage(const ImageView& image);
Status checkExrImage(const ImageView& image);

// Channel layout: 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA (alpha straight, not premultiplied).
// Returns the complete file, or an empty vector if checkPngImage fails (or zlib runs out of
// memory). Deterministic: the same image always gives the same bytes.
std::vector<uint8_t> encodePng(const ImageView& image);
// Channel names: 1 "Y"; 2 "Y","A"; 3 "R","G","B"; 4 "R","G","B","A" (input channel order), stored
// sorted by name as the format requires. Returns the complete file, or an empty vector if
// checkExrImage fails. Deterministic.
std::vector<uint8_t> encodeExr(const ImageView& image);

// Encode, then atomically place the file at `path`. Requires image.u8 / image.f32 respectively.
Status writePng(const std::string& path, const ImageView& image);
Status writeExr(const std::string& path, const ImageView& image);



} // namespace pnb::player
