// frame_random.h — the random numbers of FrameTracer: one stream per (seed, pixel, sample), so
// a sample's path is the same whichever thread traces it and whichever pass it falls in.
// Internal to pnb_reference.
#pragma once

#include <cstdint>

#include "cosine_sampling.h" // splitmix64, unitFloat

namespace pnb::reference::detail {

class FrameRandom {
public:
    FrameRandom(uint64_t seed, uint64_t pixel, uint64_t sample)
        : mState(splitmix64(splitmix64(splitmix64(seed) ^ pixel) ^ (sample * 0xd1342543de82ef95ull))) {}
    // Uniform in [0, 1): a counter through splitmix64 (its output is a good 64-bit hash).
    float next() {
        mState += 0x9e3779b97f4a7c15ull;
        return unitFloat(splitmix64(mState));
    }

private:
    uint64_t mState;
};

} // namespace pnb::reference::detail
