// crafted_png.h — a PNG that declares a huge size but carries almost no pixel data: a valid IHDR
// and a tiny IDAT (two bytes of a row), 70 bytes whatever the declared size. What a hostile
// or damaged file looks like to an image decoder that believes the header. Header-only; link
// pnb_assets (crc32, adler32).
#pragma once

#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "pnb_assets/png_writer.h"

namespace pnb::test {

inline std::vector<uint8_t> pngDeclaringOnly(uint32_t width, uint32_t height,
                                             uint8_t colourType = 6 /* RGBA */) {
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    auto u32 = [](std::vector<uint8_t>& out, uint32_t v) {
        for (int shift = 24; shift >= 0; shift -= 8)
            out.push_back(uint8_t(v >> shift));
    };
    auto chunk = [&](const char* type, const std::vector<uint8_t>& data) {
        u32(png, uint32_t(data.size()));
        std::vector<uint8_t> body(type, type + 4);
        body.insert(body.end(), data.begin(), data.end());
        png.insert(png.end(), body.begin(), body.end());
        u32(png, assets::crc32(body));
    };
    std::vector<uint8_t> ihdr;
    u32(ihdr, width);
    u32(ihdr, height);
    ihdr.insert(ihdr.end(), {8, colourType, 0, 0, 0}); // 8 bits, deflate, no filter, no interlace
    chunk("IHDR", ihdr);
    // A zlib stream with one stored block of 2 zero bytes: far less than one row.
    const std::vector<uint8_t> raw = {0, 0};
    std::vector<uint8_t> idat = {0x78, 0x01, 0x01, 0x02, 0x00, 0xFD, 0xFF};
    idat.insert(idat.end(), raw.begin(), raw.end());
    u32(idat, assets::adler32(raw));
    chunk("IDAT", idat);
    chunk("IEND", {});
    return png;
}

} // namespace pnb::test
