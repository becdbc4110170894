// cosine_sampling.h — the cosine-weighted hemisphere directions of the Monte-Carlo tracers
// (IndirectTracer, SkyTracer): a pure function of (seed, point index, sample index), so an
// estimate does not depend on which thread traced which point. Internal to pnb_reference.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace pnb::reference::detail {

inline uint64_t splitmix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}
// The top 24 bits as a float in [0, 1): exactly representable, never 1.
inline float unitFloat(uint64_t x) { return float(x >> 40) * (1.0f / 16777216.0f); }

// A tangent frame around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited": no branch-free singularity except the one it handles with copysign).
struct CosineFrame {
    glm::vec3 n, t, b;
    explicit CosineFrame(const glm::vec3& unitNormal) : n(unitNormal) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z);
        const float c = n.x * n.y * a;
        t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
        b = {c, sign + n.y * n.y * a, -n.y};
    }
    // Sample s of point `point`: pdf cos(theta) / pi (Malley: a uniform disc point lifted onto
    // the hemisphere), so an irradiance estimate is pi x the mean radiance seen.
    glm::vec3 direction(uint64_t seed, uint64_t point, uint32_t s) const {
        const uint64_t h = splitmix64(splitmix64(seed ^ (point << 20)) ^ s);
        const float u1 = unitFloat(h), u2 = unitFloat(splitmix64(h));
        const float r = std::sqrt(u1), phi = 6.28318530717958648f * u2;
        return glm::normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(std::max(0.0f, 1.0f - u1)));
    }
};

} // namespace pnb::reference::detail
