// The headless frame check (pnb_player/renderer.h nonFinitePixels): a pixel counts once when any
// channel is NaN or infinite; 8-bit captures have none. The end-to-end run is
// frame_check_test.py (on llvmpipe an RGBA16F overflow is clamped, so no NaN reaches a capture
// there; the count is what catches it on a GPU that stores infinities).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pnb_player/renderer.h"

namespace {

using pnb::player::CapturedImage;
using pnb::player::nonFinitePixels;

TEST(FrameCheck, CountsEachPixelWithANanOrAnInfiniteChannelOnce) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    CapturedImage img;
    img.width = 4;
    img.height = 1;
    img.channels = 4;
    img.f32 = {1, 2, 3, 1,  nan, 0, 0, 1,  inf, -inf, 0, 1,  65504, 0, 1e30f, 1};
    EXPECT_EQ(nonFinitePixels(img), 2u);
    img.channels = 1;
    img.width = 16;
    EXPECT_EQ(nonFinitePixels(img), 3u);
    CapturedImage bytes;
    bytes.channels = 4;
    bytes.u8.assign(16, 255);
    EXPECT_EQ(nonFinitePixels(bytes), 0u);
}

} // namespace
