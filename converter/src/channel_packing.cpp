// converter/src/channel_packing.cpp — which channels a texture stores, where, and how they are
// quantised; plus the sRGB and half-float conversions.
//
// Does NOT do: block compression (block_compress.cpp), filtering (mip_chain.cpp).
//
// Layout rules (planLayout), in order:
// 1. Unrequested channels are not stored; they sample as Zero (r, g, b) or One (a).
// 2. A requested channel whose level 0, quantised as it would be stored, is all 0 or all 1 is
//    not stored either: Swizzle::Zero / Swizzle::One. (The mips of a constant are that constant;
//    coverage scaling keeps 0 at 0 and clamps 1 at 1.)
// 3. A channel identical (same stored codes on level 0) to an earlier stored channel is not
//    stored; its swizzle reads that channel. Alpha is only merged with a colour channel when it
//    is filtered and encoded the same way: not for alpha-masked textures (coverage scaling
//    changes alpha's mips) and not next to sRGB colour (alpha is always linear).
// 4. Storage. HDR (float sources, or values outside [0, 1]): R16F / RG16F / RGBA16F (there is no
//    RGB16F; three channels pad to four), Linear. Otherwise 8-bit:
//    - sRGB request with ≥ 2 distinct colour channels: RGB8 / RGBA8 with colour at positions
//      R, G, B (one unused when only two differ) and alpha at A, because GL's SRGB8 and
//      SRGB8_ALPHA8 decode exactly R, G, B and leave A linear. colorSpace Srgb.
//    - sRGB request with at most one colour channel (greyscale albedo, an emissive mask, or only
//      alpha): GL has no core single- or two-channel sRGB format, so the colour channel is stored
//      linearised and the texture is Linear. Cost: 8-bit linear steps are coarse in the darks
//      (the 13 darkest sRGB codes collapse into 0 and 1); bright values lose nothing. The
//      alternative, an sRGB R8 the player decodes in its shader, would make colorSpace mean two
//      things.
//    - otherwise: channels densely in source order, R8 / RG8 / RGB8 / RGBA8, Linear.
// 5. The swizzle maps each sampled channel back to its stored position, so shaders read the
//    source's channel positions (greyscale RGBA → R8 with swizzle R, R, R, One).
#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <span>

#include "texture_internal.h"

namespace pnb::converter::texture_detail {

// [SECTION] conversions

float srgbToLinear(float v) {
    // Exact 8-bit values (almost every source) come from a table: this runs per texel of every
    // sRGB source, and std::pow dominates otherwise.
    static const std::array<float, 256> kTable = [] {
        std::array<float, 256> t{};
        for (int k = 0; k < 256; ++k) {
            double x = k / 255.0;
            t[k] = float(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
        }
        return t;
    }();
    float scaled = v * 255.0f;
    if (scaled >= 0.0f && scaled <= 255.0f) {
        float nearest = std::floor(scaled + 0.5f);
        if (std::abs(scaled - nearest) < 1e-4f) return kTable[size_t(nearest)];
    }
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float v) {
    return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

uint8_t quantizeUnorm8(float v) {
    if (!(v > 0.0f)) return 0; // also NaN
    if (v >= 1.0f) return 255;
    return uint8_t(v * 255.0f + 0.5f);
}

uint8_t quantizeSrgb8(float linear) {
    // round(linearToSrgb(v) * 255) without a pow per value: code k covers the linear interval
    // [decode((k - 0.5) / 255), decode((k + 0.5) / 255)), so the code is the number of upper
    // bounds ≤ v. A 4096-bucket table gives the code at each bucket's start; the sRGB curve is
    // steepest at 0 (0.8 codes per bucket), so at most one step forward remains.
    struct Tables {
        std::array<float, 256> bounds{}; // bounds[255] = +inf: no code above 255
        std::array<uint8_t, 4097> bucketStart{};
    };
    static const Tables kT = [] {
        Tables t;
        for (int k = 0; k < 255; ++k) {
            double x = (k + 0.5) / 255.0;
            t.bounds[k] = float(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
        }
        t.bounds[255] = std::numeric_limits<float>::infinity();
        for (int b = 0; b <= 4096; ++b) {
            float start = float(b) / 4096.0f;
            t.bucketStart[b] =
                uint8_t(std::upper_bound(t.bounds.begin(), t.bounds.begin() + 255, start) -
                        t.bounds.begin());
        }
        return t;
    }();
    if (!(linear > 0.0f)) return 0;
    if (linear >= 1.0f) return 255;
    uint32_t code = kT.bucketStart[uint32_t(linear * 4096.0f)];
    while (linear >= kT.bounds[code])
        ++code;
    return uint8_t(code);
}

uint16_t floatToHalf(float v) {
    // Based on: Fabian Giesen, "float_to_half_fast3_rtne" (public domain); round to nearest even.
    if (std::isnan(v)) v = 0.0f;
    v = std::clamp(v, -65504.0f, 65504.0f);
    uint32_t u = std::bit_cast<uint32_t>(v);
    uint32_t sign = u & 0x80000000u;
    u ^= sign;
    uint16_t h;
    if (u < (113u << 23)) { // below the smallest normal half: subnormal or zero
        constexpr uint32_t kDenormMagic = ((127 - 15) + (23 - 10) + 1) << 23;
        float t = std::bit_cast<float>(u) + std::bit_cast<float>(kDenormMagic);
        h = uint16_t(std::bit_cast<uint32_t>(t) - kDenormMagic);
    } else {
        uint32_t mantissaOdd = (u >> 13) & 1;
        u += (uint32_t(15 - 127) << 23) + 0xFFF;
        u += mantissaOdd;
        h = uint16_t(u >> 13);
    }
    return uint16_t(h | (sign >> 16));
}

float halfToFloat(uint16_t h) {
    uint32_t sign = uint32_t(h & 0x8000) << 16;
    uint32_t exponent = (h >> 10) & 0x1F, mantissa = h & 0x3FF;
    if (exponent == 0) { // zero or subnormal: mantissa × 2^-24
        float m = std::ldexp(float(mantissa), -24);
        return sign ? -m : m;
    }
    if (exponent == 31) return std::bit_cast<float>(sign | 0x7F800000u | (mantissa << 13));
    return std::bit_cast<float>(sign | ((exponent + 112) << 23) | (mantissa << 13));
}

// [SECTION] layout

namespace {

uint16_t code(float v, Encoding e) {
    switch (e) {
    case Encoding::Unorm8:
        return quantizeUnorm8(v);
    case Encoding::Srgb8:
        return quantizeSrgb8(v);
    case Encoding::Half:
        return floatToHalf(v);
    }
    return 0;
}

bool allCodesEqual(const ImageF& img, int channel, Encoding e, uint16_t expected) {
    for (size_t i = 0, n = img.texelCount(); i < n; ++i)
        if (code(img.texels[i * 4 + channel], e) != expected) return false;
    return true;
}

bool sameCodes(const ImageF& img, int a, int b, Encoding e) {
    for (size_t i = 0, n = img.texelCount(); i < n; ++i)
        if (code(img.texels[i * 4 + a], e) != code(img.texels[i * 4 + b], e)) return false;
    return true;
}

// What becomes of one source channel.
enum class Fate : uint8_t { Unrequested, Zero, One, Duplicate, Stored };

struct ChannelPlan {
    Fate fate = Fate::Unrequested;
    int duplicateOf = -1; // for Duplicate: the stored source channel it equals
};

// Rules 2 and 3 for one channel against the already stored `candidates`.
ChannelPlan classify(const ImageF& img, int c, Encoding e, std::span<const int> candidates) {
    if (allCodesEqual(img, c, e, code(0.0f, e))) return {Fate::Zero};
    if (allCodesEqual(img, c, e, code(1.0f, e))) return {Fate::One};
    for (int s : candidates)
        if (sameCodes(img, c, s, e)) return {Fate::Duplicate, s};
    return {Fate::Stored};
}

TextureFormat plainFormat(uint32_t positions, bool hdr) {
    static constexpr TextureFormat kUnorm[] = {TextureFormat::R8, TextureFormat::RG8,
                                               TextureFormat::RGB8, TextureFormat::RGBA8};
    static constexpr TextureFormat kHalf[] = {TextureFormat::R16F, TextureFormat::RG16F,
                                              TextureFormat::RGBA16F, TextureFormat::RGBA16F};
    assert(positions >= 1 && positions <= 4);
    return (hdr ? kHalf : kUnorm)[positions - 1];
}

} // namespace

ChannelLayout planLayout(const ImageF& level0, const TextureRequest& request, bool hdr) {
    bool srgb = request.colorSpace == ColorSpace::Srgb && !hdr;
    Encoding linearEnc = hdr ? Encoding::Half : Encoding::Unorm8;

    // Colour first, judged in the encoding an sRGB texture would store; a single remaining
    // colour channel is then stored linear (rule 4), which changes no Zero/One/Duplicate verdict
    // that matters: with one stored colour channel every duplicate refers to it.
    ChannelPlan plan[4];
    std::vector<int> storedColour;
    Encoding colourEnc = srgb ? Encoding::Srgb8 : linearEnc;
    for (int c = 0; c < 3; ++c) {
        if (!request.channels[c]) continue;
        plan[c] = classify(level0, c, colourEnc, storedColour);
        if (plan[c].fate == Fate::Stored) storedColour.push_back(c);
    }
    bool srgbStorage = srgb && storedColour.size() >= 2;
    if (!srgbStorage) colourEnc = linearEnc;

    if (request.channels[3]) {
        bool mayMerge = !request.alphaMask && !srgbStorage;
        std::span<const int> candidates =
            mayMerge ? std::span<const int>(storedColour) : std::span<const int>();
        plan[3] = classify(level0, 3, linearEnc, candidates);
    }

    ChannelLayout layout;
    layout.source = {-1, -1, -1, -1};
    layout.encoding.fill(linearEnc);
    int position[4] = {-1, -1, -1, -1}; // stored position of each source channel
    uint32_t count = 0;
    if (srgbStorage) {
        for (int c : storedColour) {
            position[c] = int(count);
            layout.encoding[count++] = Encoding::Srgb8;
        }
        count = 3;
        if (plan[3].fate == Fate::Stored) {
            position[3] = 3;
            count = 4;
        }
        layout.colorSpace = ColorSpace::Srgb;
    } else {
        for (int c = 0; c < 4; ++c)
            if (plan[c].fate == Fate::Stored) position[c] = int(count++);
        count = std::max(count, 1u); // everything constant: one unused channel keeps the shape
        if (hdr && count == 3) count = 4;
        layout.colorSpace = ColorSpace::Linear;
    }
    for (int c = 0; c < 4; ++c)
        if (position[c] >= 0) layout.source[size_t(position[c])] = int8_t(c);
    layout.positions = count;
    layout.format = plainFormat(count, hdr);

    static constexpr Swizzle kPosition[] = {Swizzle::R, Swizzle::G, Swizzle::B, Swizzle::A};
    for (int c = 0; c < 4; ++c) {
        Swizzle& s = layout.swizzle[size_t(c)];
        switch (plan[c].fate) {
        case Fate::Unrequested:
            s = c == 3 ? Swizzle::One : Swizzle::Zero;
            break;
        case Fate::Zero:
            s = Swizzle::Zero;
            break;
        case Fate::One:
            s = Swizzle::One;
            break;
        case Fate::Duplicate:
            s = kPosition[position[plan[c].duplicateOf]];
            break;
        case Fate::Stored:
            s = kPosition[position[c]];
            break;
        }
    }
    return layout;
}

std::vector<std::byte> packLevel(const ImageF& level, const ChannelLayout& layout,
                                 float alphaScale) {
    size_t n = level.texelCount();
    uint32_t positions = layout.positions;
    bool half = layout.encoding[0] == Encoding::Half;
    std::vector<std::byte> out(n * positions * (half ? 2 : 1));
    for (size_t i = 0; i < n; ++i) {
        const float* texel = &level.texels[i * 4];
        for (uint32_t p = 0; p < positions; ++p) {
            int src = layout.source[p];
            float v = src >= 0 ? texel[src] : 0.0f;
            if (src == 3 && alphaScale != 1.0f) v = std::min(1.0f, v * alphaScale);
            size_t at = i * positions + p;
            uint16_t q = code(v, layout.encoding[p]);
            if (half) {
                out[at * 2] = std::byte(q & 0xFF); // little-endian, as the whole container
                out[at * 2 + 1] = std::byte(q >> 8);
            } else {
                out[at] = std::byte(q);
            }
        }
    }
    return out;
}

} // namespace pnb::converter::texture_detail
