// A captured buffer written to an image file (pnb_player/save_capture.h).
#include "pnb_player/save_capture.h"

#include <algorithm>
#include <vector>

#include "pnb_player/image_write.h"

namespace pnb::player {

PlayResult<Done> saveCapture(const std::string& path, const CapturedImage& image) {
    ImageView view{image.width, image.height, image.channels, {}, {}};
    size_t row = size_t(image.width) * image.channels;
    Status s;
    if (!image.u8.empty()) {
        std::vector<uint8_t> flipped(image.u8.size());
        for (uint32_t y = 0; y < image.height; ++y)
            std::copy_n(image.u8.data() + size_t(image.height - 1 - y) * row, row, flipped.data() + y * row);
        view.u8 = flipped;
        s = writePng(path, view);
    } else {
        std::vector<float> flipped(image.f32.size());
        for (uint32_t y = 0; y < image.height; ++y)
            std::copy_n(image.f32.data() + size_t(image.height - 1 - y) * row, row, flipped.data() + y * row);
        view.f32 = flipped;
        s = writeExr(path, view);
    }
    if (!isOk(s)) return PlayError{PlayErrorKind::Io, s.describe()};
    return Done{};
}

} // namespace pnb::player
