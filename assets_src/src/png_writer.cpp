// The generated textures' PNG encoder is pnb_image_write's; the checksums are zlib's (see
// png_writer.h).

#include "pnb_assets/png_writer.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include <zlib.h>

#include "pnb_player/image_write.h"

namespace pnb::assets {

uint32_t crc32(std::span<const uint8_t> bytes, uint32_t crc) {
    uLong c = crc;
    // zlib takes a uInt length: feed large spans in pieces.
    for (size_t done = 0; done < bytes.size();) {
        uInt n = uInt(std::min<size_t>(bytes.size() - done, size_t(1) << 30));
        c = ::crc32(c, bytes.data() + done, n);
        done += n;
    }
    return uint32_t(c);
}

uint32_t adler32(std::span<const uint8_t> bytes, uint32_t adler) {
    uLong a = adler;
    for (size_t done = 0; done < bytes.size();) {
        uInt n = uInt(std::min<size_t>(bytes.size() - done, size_t(1) << 30));
        a = ::adler32(a, bytes.data() + done, n);
        done += n;
    }
    return uint32_t(a);
}

std::vector<uint8_t> encodePng(uint32_t width, uint32_t height, uint32_t channels,
                               std::span<const uint8_t> pixels) {
    const player::ImageView image{width, height, channels, pixels, {}};
    if (Status s = player::checkPngImage(image); !isOk(s)) {
        std::fprintf(stderr, "pnb::assets::encodePng: %s\n", s.describe().c_str());
        std::abort();
    }
    std::vector<uint8_t> png = player::encodePng(image);
    if (png.empty()) {
        std::fprintf(stderr, "pnb::assets::encodePng: out of memory encoding %ux%ux%u\n", width,
                     height, channels);
        std::abort();
    }
    return png;
}

} // namespace pnb::assets
