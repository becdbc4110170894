// pnb_player/image_write.h — the PNG and OpenEXR writers of the player's screenshots, dumps and
// golden-image captures, and of pnb_assets' generated textures.
//
// Encoders: Debian's header-only libraries, compiled into pnb_image_write — stb_image_write for
// PNG, with zlib (level 6) as its deflate instead of stb's own, and tinyexr for OpenEXR. Nothing
// of them is in this header; the library links pnb_format and zlib only.
//
// Does: 8-bit PNG in grey, grey+alpha, RGB and RGBA (non-interlaced, one adaptive filter per row
// chosen by stb's minimum-sum-of-absolute-differences heuristic, one IDAT); single-part scanline
// OpenEXR with NO_COMPRESSION and 32-bit FLOAT channels, one scanline per block, increasing Y
// (the layout pnb-reference, the sweep scripts and the tests read). Files are written
// atomically: built under "<dir>/.<name>.tmp.<pid>.<n>", fsync'ed and renamed over the target,
// so an interrupted write leaves any previous file intact and never a partial one; the temporary
// is removed on every error path.
//
// Does NOT do: reading; 16-bit PNG (stb_image_write writes 8-bit only), palettes, interlacing,
// or any ancillary PNG chunk (no sRGB/gAMA/iCCP: samples are stored exactly as given, so 8-bit
// data is assumed to be sRGB-encoded as usual); EXR half or uint channels, compression, tiles,
// mipmaps, multi-part or deep data, metadata beyond the required attributes; colour conversion,
// premultiplication or clamping (EXR floats, including NaN/Inf, are stored bit-exactly).
// Memory: a PNG needs about its scanlines twice over; an EXR about three times its float
// samples (planar copy, tinyexr's blocks, the file).
//
// Specs: PNG — ISO/IEC 15948:2004 / W3C "Portable Network Graphics (PNG) Specification (Second
// Edition)". OpenEXR — "OpenEXR File Layout" (openexr.com): magic 20000630, version 2 with no
// flags (single-part scanline, short names), the required attributes, chlist sorted by name,
// line offset table, scanline blocks {int y, int size, per-channel rows in chlist order}.
//
// Errors (pnb::Status, see pnb/error.h): an ImageView that breaks its preconditions yields
// BadPayload (zero size, channels outside 1..4, wrong span for the format, sample count not
// width*height*channels) or LimitExceeded (dimensions beyond what the format or the encoder can
// store: PNG rows over 16 MiB or scanlines over 2 GiB - 16 MiB, since stb counts in int; EXR
// scanlines over 2^31-1 bytes), and an encoder that fails (out of memory) LimitExceeded; the
// message names the problem. File system failures yield IoError naming the file.
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
// Returns the complete file, or an empty vector if checkPngImage fails (or the encoder runs out
// of memory). Deterministic: the same image always gives the same bytes (for one zlib version).
std::vector<uint8_t> encodePng(const ImageView& image);
// Channel names: 1 "Y"; 2 "Y","A"; 3 "R","G","B"; 4 "R","G","B","A" (input channel order), stored
// sorted by name as the format requires. Returns the complete file, or an empty vector if
// checkExrImage fails (or the encoder runs out of memory). Deterministic.
std::vector<uint8_t> encodeExr(const ImageView& image);

// Encode, then atomically place the file at `path`. Requires image.u8 / image.f32 respectively.
Status writePng(const std::string& path, const ImageView& image);
Status writeExr(const std::string& path, const ImageView& image);

} // namespace pnb::player
