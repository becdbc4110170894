// converter/src/mip_chain.cpp — mip level filtering and alpha-coverage preservation.
//
// Based on: Castaño, "Computing Alpha Mipmaps" (2010): an alpha-tested texture keeps its
// silhouette across mips when each level's alpha is scaled so that the fraction of texels
// passing the alpha test matches level 0's.
//
// Does NOT do: colour-space handling (callers pass linear light), premultiplied or
// alpha-weighted colour filtering (colour under alpha 0 is filtered like any other texel).
//
// Filter choice: each level is made from the previous one with a box filter over each new
// texel's exact footprint. For power-of-two sizes that is the 2×2 average GL's
// glGenerateMipmap also computes, and a chain of 2×2 averages equals the area average of level 0,
// so nothing is lost by filtering from the previous level instead of from level 0; wider kernels
// (Kaiser) sharpen a little but cost several times more and ring on alpha masks. For odd sizes,
// floor halving (FORMAT.md's TMIP rule, and GL's) makes the footprint 2 < f < 3 texels, so a
// plain 2×2 average would drop the last row or column; the exact footprint keeps every texel's
// weight.
#include <algorithm>
#include <cassert>
#include <cmath>

#include "huge_pages.h"
#include "texture_internal.h"

namespace pnb::converter::texture_detail {

namespace {

// The source texels under one destination texel along one axis, and their weights (sum 1).
struct Footprint {
    uint32_t first = 0, count = 0;
    float weights[4] = {};
};

std::vector<Footprint> footprints(uint32_t srcSize, uint32_t dstSize) {
    std::vector<Footprint> out(dstSize);
    double ratio = double(srcSize) / double(dstSize); // < 3 for floor halving: at most 4 taps
    for (uint32_t i = 0; i < dstSize; ++i) {
        double lo = i * ratio, hi = (i + 1) * ratio;
        uint32_t first = uint32_t(lo);
        uint32_t last = std::min(srcSize - 1, uint32_t(std::ceil(hi)) - 1);
        assert(last - first < 4);
        out[i].first = first;
        out[i].count = last - first + 1;
        for (uint32_t j = first; j <= last; ++j) {
            double overlap = std::min(hi, double(j + 1)) - std::max(lo, double(j));
            out[i].weights[j - first] = float(overlap / ratio);
        }
    }
    return out;
}

uint32_t unorm8Threshold(float cutoff) {
    // The smallest stored code a shader's `alpha >= cutoff` accepts (256: none).
    uint32_t k = 0;
    while (k < 256 && float(k) / 255.0f < cutoff)
        ++k;
    return k;
}

} // namespace

ImageF downsample(const ImageF& src) {
    assert(src.width > 0 && src.height > 0);
    ImageF dst;
    dst.width = std::max(1u, src.width >> 1);
    dst.height = std::max(1u, src.height >> 1);
    std::vector<Footprint> fx = footprints(src.width, dst.width);
    std::vector<Footprint> fy = footprints(src.height, dst.height);

    // Separable: horizontally into `rows` (dst.width × src.height), then vertically.
    std::vector<float> rows(size_t(dst.width) * src.height * 4);
    for (uint32_t y = 0; y < src.height; ++y) {
        const float* in = &src.texels[size_t(y) * src.width * 4];
        float* out = &rows[size_t(y) * dst.width * 4];
        for (uint32_t x = 0; x < dst.width; ++x) {
            const Footprint& f = fx[x];
            float acc[4] = {};
            for (uint32_t t = 0; t < f.count; ++t)
                for (int c = 0; c < 4; ++c)
                    acc[c] += f.weights[t] * in[(f.first + t) * 4 + c];
            std::copy(acc, acc + 4, out + x * 4);
        }
    }
    dst.texels.reserve(dst.texelCount() * 4);
    adviseHugePages(dst.texels.data(), dst.texelCount() * 4 * sizeof(float)); // huge_pages.h
    dst.texels.assign(dst.texelCount() * 4, 0.0f);
    size_t rowFloats = size_t(dst.width) * 4;
    for (uint32_t y = 0; y < dst.height; ++y) {
        const Footprint& f = fy[y];
        float* out = &dst.texels[y * rowFloats];
        for (uint32_t t = 0; t < f.count; ++t) {
            const float* in = &rows[(f.first + t) * rowFloats];
            float w = f.weights[t];
            for (size_t i = 0; i < rowFloats; ++i)
                out[i] += w * in[i];
        }
    }
    return dst;
}

double alphaCoverage(const ImageF& image, float cutoff, float scale, AlphaStorage storage) {
    size_t n = image.texelCount(), covered = 0;
    if (n == 0) return 0;
    if (storage == AlphaStorage::Unorm8) {
        uint32_t threshold = unorm8Threshold(cutoff);
        for (size_t i = 0; i < n; ++i)
            covered += quantizeUnorm8(std::min(1.0f, image.texels[i * 4 + 3] * scale)) >= threshold;
    } else {
        for (size_t i = 0; i < n; ++i) {
            float a = std::min(1.0f, image.texels[i * 4 + 3] * scale);
            covered += halfToFloat(floatToHalf(a)) >= cutoff;
        }
    }
    return double(covered) / double(n);
}

float findAlphaScale(const ImageF& image, float cutoff, double targetCoverage,
                     AlphaStorage storage) {
    // Coverage does not depend on the scale when everything (cutoff ≤ 0) or nothing (> 1)
    // passes; NaN cutoffs fall here too.
    if (!(cutoff > 0.0f && cutoff <= 1.0f)) return 1.0f;
    auto coverage = [&](float s) { return alphaCoverage(image, cutoff, s, storage); };

    // Coverage grows monotonically with the scale: bracket the target, then bisect, keeping the
    // best scale seen (coverage is a step function, so an exact match may not exist).
    float best = 1.0f;
    double bestError = std::abs(coverage(1.0f) - targetCoverage);
    float lo = 0.0f, hi = 1.0f;
    while (hi < 65536.0f && coverage(hi) < targetCoverage) {
        lo = hi;
        hi *= 2.0f;
    }
    for (int i = 0; i < 24 && bestError > 0; ++i) {
        float mid = 0.5f * (lo + hi);
        double c = coverage(mid);
        double error = std::abs(c - targetCoverage);
        if (error < bestError) {
            bestError = error;
            best = mid;
        }
        if (c < targetCoverage)
            lo = mid;
        else
            hi = mid;
    }
    return best;
}

} // namespace pnb::converter::texture_detail
