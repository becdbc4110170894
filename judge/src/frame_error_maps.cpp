// The whole frame's error maps (frame_error_maps.h).
#include "frame_error_maps.h"

#include "pnb_lighting/tonemap.h"
#include "pnb_reference/image_error.h"

namespace pnb::player {

namespace {

bool complete(const FrameQuality::Frame& f) {
    const size_t pixels = size_t(f.width) * f.height;
    return pixels > 0 && f.player.size() == pixels && f.truth.size() == pixels && f.flipLdr.size() == pixels;
}

// A frame's rows are top-down, as the maps' are: pixel i goes to row i / width of panel `panel`.
void put(ErrorMap& m, uint32_t frameWidth, uint32_t panels, size_t i, uint32_t panel, Rgb8 c) {
    const size_t x = i % frameWidth, y = i / frameWidth;
    const size_t o = (y * size_t(panels * frameWidth) + panel * frameWidth + x) * 3;
    m.rgb[o] = c.r;
    m.rgb[o + 1] = c.g;
    m.rgb[o + 2] = c.b;
}

// What the player's tonemap.frag shows for `hdr`, as 8-bit sRGB.
Rgb8 displayed(const glm::vec3& hdr, double exposure) {
    const glm::vec3 d = lighting::displayColor(hdr, float(exposure));
    return {toByte(255.0 * d.r), toByte(255.0 * d.g), toByte(255.0 * d.b)};
}

const char* kFlipEncoding = "per pixel, LDR-FLIP of the player's displayed frame against the path-traced truth's "
                            "through the same tone map (0 identical, 1 the largest difference), through the ramp";

} // namespace

ErrorMap frameErrorMap(const FrameQuality::Frame& frame) {
    if (!complete(frame)) return {};
    ErrorMap m = blankErrorMap("frame", frame.width, frame.height);
    for (size_t i = 0; i < frame.flipLdr.size(); ++i) put(m, frame.width, 1, i, 0, rampColour(frame.flipLdr[i]));
    const reference::ErrorSummary s = reference::summarizeError(frame.flipLdr);
    m.encoding = kFlipEncoding;
    m.legend = {{"ramp", kRampName},
                {colourName(rampColour(0.0)), "no perceived difference"},
                {colourName(rampColour(0.5)), "FLIP 0.5"},
                {colourName(rampColour(1.0)), "FLIP 1: the largest difference (green against blue)"}};
    m.clamp = 1.0;
    m.clampMeaning = "FLIP 1";
    m.stats = {{"mean_flip_ldr", s.mean},
               {"weighted_median_flip_ldr", s.weightedMedian},
               {"max_flip_ldr", s.max},
               {"exposure", frame.exposure}};
    return m;
}

ErrorMap frameSideBySide(const FrameQuality::Frame& frame) {
    if (!complete(frame)) return {};
    ErrorMap m = blankErrorMap("frame", 3 * frame.width, frame.height);
    m.file = "compare_frame.png";
    for (size_t i = 0; i < frame.flipLdr.size(); ++i) {
        put(m, frame.width, 3, i, 0, displayed(frame.player[i], frame.exposure));
        put(m, frame.width, 3, i, 1, displayed(frame.truth[i], frame.exposure));
        put(m, frame.width, 3, i, 2, rampColour(frame.flipLdr[i]));
    }
    m.encoding = std::string("three panels: the player's frame | the path-traced truth, both through the player's "
                             "tone map at its exposure | ") + kFlipEncoding;
    m.legend = {{"panels 1-2", "the displayed images (sRGB)"}, {"panel 3", kRampName + ", 0 .. FLIP 1"}};
    m.clamp = 1.0;
    m.clampMeaning = "panel 3: FLIP 1";
    m.stats = {{"exposure", frame.exposure}};
    return m;
}

} // namespace pnb::player
