// The separable correlation of FLIP's filters (flip_filter.h). Two passes, each a weighted sum of
// whole rows so that the inner loop runs along memory: the CSF and feature kernels are up to
// 21 taps at 67 ppd, so a 480x270 plane costs ~5 M multiply-adds per pass.
#include "flip_filter.h"

#include <algorithm>

namespace pnb::reference::flip_detail {

Plane correlateSeparable(const Plane& in, std::span<const float> kx, std::span<const float> ky) {
    const int w = int(in.width), h = int(in.height);
    const int rx = int(kx.size() / 2), ry = int(ky.size() / 2);
    Plane horizontal(in.width, in.height);
    std::vector<float> padded(size_t(w + 2 * rx));
    for (int y = 0; y < h; ++y) {
        const float* row = in.v.data() + size_t(y) * size_t(w);
        // The row with its end pixels repeated rx times each side: no clamping in the inner loop.
        for (int x = 0; x < w + 2 * rx; ++x)
            padded[size_t(x)] = row[std::clamp(x - rx, 0, w - 1)];
        float* out = horizontal.v.data() + size_t(y) * size_t(w);
        for (int x = 0; x < w; ++x) {
            float sum = 0.0f;
            for (size_t i = 0; i < kx.size(); ++i)
                sum += kx[i] * padded[size_t(x) + i];
            out[x] = sum;
        }
    }
    Plane result(in.width, in.height);
    for (int y = 0; y < h; ++y) {
        float* out = result.v.data() + size_t(y) * size_t(w);
        for (size_t j = 0; j < ky.size(); ++j) {
            const int sy = std::clamp(y + int(j) - ry, 0, h - 1);
            const float* src = horizontal.v.data() + size_t(sy) * size_t(w);
            const float weight = ky[j];
            for (int x = 0; x < w; ++x)
                out[x] += weight * src[x];
        }
    }
    return result;
}

} // namespace pnb::reference::flip_detail
