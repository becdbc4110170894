#include "cascade_splits.h"

#include <cmath>

namespace pnb::player {

std::vector<float> practicalSplitDistances(float nearDistance, float farDistance,
                                           uint32_t cascades, float lambda) {
    if (!(nearDistance > 0) || !(farDistance > nearDistance) || !std::isfinite(farDistance) ||
        cascades < 1 || cascades > 16 || !(lambda >= 0 && lambda <= 1))
        return {};
    const double n = nearDistance, f = farDistance, l = lambda;
    std::vector<float> splits(cascades);
    for (uint32_t i = 1; i <= cascades; ++i) {
        double t = double(i) / double(cascades);
        double logarithmic = n * std::pow(f / n, t);
        double uniform = n + (f - n) * t;
        splits[i - 1] = float(l * logarithmic + (1.0 - l) * uniform);
    }
    splits.back() = farDistance; // exact, whatever pow's rounding
    return splits;
}

} // namespace pnb::player
