// pnb-reference's PNG error maps: the colours of each verdict (8-bit sRGB-encoded), shared by
// the visibility (reference_run.cpp) and colour visibility (reference_color.cpp) maps.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pnb::reference_tool {

struct Rgb8 {
    uint8_t r, g, b;
};
constexpr Rgb8 kLit{255, 255, 255}, kShadow{0, 0, 0}, kNoGeometry{0, 0, 96};
constexpr Rgb8 kAgreeLit{200, 200, 200}, kAgreeShadow{96, 96, 96};
constexpr Rgb8 kAgreeTranslucent{110, 150, 210}; // pale blue: both see light through glass alike
constexpr Rgb8 kFalseShadow{230, 30, 30}; // red: player shadowed, truly lit
constexpr Rgb8 kFalseLit{30, 200, 30};    // green: player lit, truly shadowed
constexpr Rgb8 kCoverage{230, 0, 230};    // magenta: only one of the two has geometry
constexpr Rgb8 kNotReached{64, 48, 80}; // dim violet: a local light does not reach it (not judged)

inline void put(std::vector<uint8_t>& rgb, size_t pixel, Rgb8 c) {
    rgb[pixel * 3 + 0] = c.r;
    rgb[pixel * 3 + 1] = c.g;
    rgb[pixel * 3 + 2] = c.b;
}

} // namespace pnb::reference_tool
