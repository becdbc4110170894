// player/math/cascade_splits.h — split distances of cascaded shadow maps (pure CPU, no GL).
//
// Based on: Zhang et al., "Parallel-Split Shadow Maps" (2006), the practical split scheme;
// seeds 000 and 001 (../shared/seeds). Issue 5 builds the rest of the cascade fitting on this.
#pragma once

#include <cstdint>
#include <vector>

namespace pnb::player {

// Far distance of each of `cascades` view-space slices of [nearDistance, farDistance]:
//   C_i = lambda * n * (f/n)^(i/m) + (1 - lambda) * (n + (f - n) * i/m),  i = 1..m
// lambda = 0 gives uniform splits, 1 logarithmic. The last entry is exactly farDistance.
// Preconditions: 0 < nearDistance < farDistance (finite), 1 <= cascades <= 16, lambda in [0, 1];
// violations return an empty vector. Evaluated in double: the (f/n)^(i/m) term stays accurate at
// near/far ratios down to 1e-7. Distances are in view-space units along the view direction.
std::vector<float> practicalSplitDistances(float nearDistance, float farDistance,
                                           uint32_t cascades, float lambda);

} // namespace pnb::player
