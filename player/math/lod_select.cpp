// LOD selection by projected screen-space error (see lod_select.h for the rule and its units).
#include "lod_select.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace pnb::player {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

} // namespace

double lodPixelScale(double yfovRadians, uint32_t viewportHeight) {
    if (!(yfovRadians > 0) || !std::isfinite(yfovRadians)) return kInf; // NaN lands here too
    if (yfovRadians >= std::numbers::pi) return 0.0;
    const double t = std::tan(0.5 * yfovRadians);
    if (!(t > 0)) return kInf;
    return double(viewportHeight) / (2.0 * t);
}

double lodPixelScaleOrthographic(double ymag, uint32_t viewportHeight) {
    if (!(ymag > 0) || !std::isfinite(ymag)) return kInf;
    return double(viewportHeight) / (2.0 * ymag);
}

double lodDistance(bool orthographic, const glm::dvec3& eye, const glm::dvec3& lo, const glm::dvec3& hi) {
    return orthographic ? 1.0 : distanceToBox(eye, lo, hi);
}

double distanceToBox(const glm::dvec3& eye, const glm::dvec3& lo, const glm::dvec3& hi) {
    glm::dvec3 d = glm::max(glm::max(lo - eye, eye - hi), glm::dvec3(0.0));
    double len = glm::length(d);
    return std::isnan(len) ? 0.0 : len; // glm::max of NaN is unspecified: NaN means "unknown"
}

double maxStretch(const glm::dmat3& m) {
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!std::isfinite(m[c][r])) return kInf;
    // Largest singular value = sqrt of the largest eigenvalue of the symmetric A = M^T M, by the
    // closed form for symmetric 3x3 matrices (trigonometric solution of the characteristic cubic).
    const glm::dmat3 a = glm::transpose(m) * m;
    const double p1 = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    const double p2 = (a[0][0] - q) * (a[0][0] - q) + (a[1][1] - q) * (a[1][1] - q) +
                      (a[2][2] - q) * (a[2][2] - q) + 2.0 * p1;
    double lambda = q;
    if (p2 > 0 && std::isfinite(p2)) {
        const double p = std::sqrt(p2 / 6.0);
        const glm::dmat3 b = (a - q * glm::dmat3(1.0)) / p;
        const double r = std::clamp(glm::determinant(b) / 2.0, -1.0, 1.0);
        lambda = q + 2.0 * p * std::cos(std::acos(r) / 3.0);
    } else if (!std::isfinite(p2)) {
        return kInf; // entries near DBL_MAX overflow the squares
    }
    // Rounding can leave the largest eigenvalue an ulp under the largest column length squared.
    for (int c = 0; c < 3; ++c) lambda = std::max(lambda, glm::dot(m[c], m[c]));
    return std::sqrt(std::max(lambda, 0.0));
}

uint32_t selectLod(std::span<const float> errors, double worldScale, double distance,
                   double pixelScale, const LodRule& rule, uint32_t current) {
    const uint32_t levels = uint32_t(std::min<size_t>(errors.size(), 256));
    if (levels <= 1) return 0;
    current = std::min(current, levels - 1);
    // Projected error of `error` compared with `limit` pixels, without dividing: error * scale *
    // pixelScale <= limit * distance. Any NaN makes the comparison false (not acceptable), so
    // unknown distances or scales keep full detail; an exact level (error 0) always passes.
    const double reach = std::max(worldScale, 0.0) * std::max(pixelScale, 0.0);
    const double dist = distance > 0 ? distance : 0.0;
    const float hysteresis = std::clamp(std::isnan(rule.hysteresis) ? 0.0f : rule.hysteresis, 0.0f, 0.99f);
    auto acceptable = [&](double error, double limitPx) {
        if (error <= 0) return true;
        return error * reach <= limitPx * dist; // NaN (inf * 0, ...) -> false
    };
    const double threshold = std::isnan(rule.thresholdPx) ? 0.0 : std::max(double(rule.thresholdPx), 0.0);
    // Errors taken as nondecreasing (running maximum; NaN counts as unbounded).
    auto errorAt = [&](uint32_t l, double finer) {
        return std::max(finer, std::isnan(errors[l]) ? kInf : double(errors[l]));
    };
    // Coarsest level within the threshold.
    uint32_t target = 0;
    double running = errorAt(0, 0.0);
    while (target + 1 < levels) {
        double next = errorAt(target + 1, running);
        if (!acceptable(next, threshold)) break;
        running = next;
        ++target;
    }
    if (target <= current) return target; // finer (the current one is over the threshold) or same
    // Coarser: only as far as the hysteresis band allows.
    const double strict = threshold * (1.0 - double(hysteresis));
    running = 0;
    for (uint32_t l = 0; l <= current; ++l) running = errorAt(l, running);
    uint32_t level = current;
    while (level < target) {
        double next = errorAt(level + 1, running);
        if (!acceptable(next, strict)) break;
        running = next;
        ++level;
    }
    return level;
}

uint32_t applyLodOverrides(uint32_t selected, uint32_t levelCount, int bias, int force) {
    if (levelCount == 0) return 0;
    const int64_t last = int64_t(levelCount) - 1;
    if (force >= 0) return uint32_t(std::min<int64_t>(force, last));
    return uint32_t(std::clamp<int64_t>(int64_t(selected) + bias, 0, last));
}

} // namespace pnb::player
