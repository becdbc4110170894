// Relative MSE, its noise share, error-map summaries and the magma colouring (image_error.h).
#include "pnb_reference/image_error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pnb::reference {

namespace {

bool finite(const glm::vec3& c) {
    return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
}

// matplotlib's magma at t = 0, 1/8, ..., 1 (the same stops as pnb-play's error maps, which the
// floors keep in player/tools/error_maps.cpp).
constexpr std::array<uint8_t, 3> kMagma[9] = {{0, 0, 4},      {28, 16, 68},    {79, 18, 123},
                                              {129, 37, 129}, {181, 54, 122},  {229, 80, 100},
                                              {251, 135, 97}, {254, 194, 135}, {252, 253, 191}};

} // namespace

RelativeMse relativeMse(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                        double epsilon) {
    RelativeMse result;
    if (test.size() != reference.size()) return result;
    result.map.assign(test.size(), std::numeric_limits<float>::quiet_NaN());
    double sum = 0.0;
    for (size_t p = 0; p < test.size(); ++p) {
        if (!finite(test[p]) || !finite(reference[p])) continue;
        double pixel = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double r = reference[p][c], d = double(test[p][c]) - r;
            pixel += d * d / (r * r + epsilon);
        }
        result.map[p] = float(pixel / 3.0);
        sum += pixel;
        ++result.pixels;
    }
    result.mean = result.pixels ? sum / (3.0 * double(result.pixels)) : 0.0;
    return result;
}

double noiseRelativeMse(std::span<const glm::vec3> reference,
                        std::span<const glm::vec3> standardError, double epsilon) {
    if (reference.size() != standardError.size()) return 0.0;
    double sum = 0.0;
    uint64_t pixels = 0;
    for (size_t p = 0; p < reference.size(); ++p) {
        if (!finite(reference[p]) || !finite(standardError[p])) continue;
        for (int c = 0; c < 3; ++c) {
            const double r = reference[p][c], s = standardError[p][c];
            sum += s * s / (r * r + epsilon);
        }
        ++pixels;
    }
    return pixels ? sum / (3.0 * double(pixels)) : 0.0;
}

double weightedQuantile(std::span<const float> map, double q) {
    std::vector<float> values;
    values.reserve(map.size());
    double total = 0.0;
    for (float v : map)
        if (std::isfinite(v)) {
            values.push_back(v);
            total += v;
        }
    if (values.empty() || !(total > 0)) return 0.0;
    std::sort(values.begin(), values.end());
    const double target = std::clamp(q, 0.0, 1.0) * total;
    double running = 0.0;
    for (float v : values) {
        running += v;
        if (running >= target) return v;
    }
    return values.back();
}

ErrorSummary summarizeError(std::span<const float> map) {
    ErrorSummary s;
    double sum = 0.0;
    s.min = std::numeric_limits<double>::infinity();
    s.max = -std::numeric_limits<double>::infinity();
    for (float v : map) {
        if (!std::isfinite(v)) continue;
        ++s.pixels;
        sum += v;
        s.min = std::min(s.min, double(v));
        s.max = std::max(s.max, double(v));
    }
    if (s.pixels == 0) return ErrorSummary{};
    s.mean = sum / double(s.pixels);
    s.weightedMedian = weightedQuantile(map, 0.5);
    s.weightedQuartile1 = weightedQuantile(map, 0.25);
    s.weightedQuartile3 = weightedQuantile(map, 0.75);
    return s;
}

std::array<uint8_t, 3> magma(double t) {
    if (!(t > 0)) return kMagma[0];
    if (t >= 1) return kMagma[8];
    const double s = t * 8.0;
    const int i = std::min(int(s), 7);
    const double f = s - i;
    std::array<uint8_t, 3> out{};
    for (int c = 0; c < 3; ++c)
        out[size_t(c)] = uint8_t(std::lround(
            kMagma[i][size_t(c)] + f * (kMagma[i + 1][size_t(c)] - kMagma[i][size_t(c)])));
    return out;
}

std::vector<uint8_t> magmaImage(std::span<const float> map) {
    std::vector<uint8_t> rgb(map.size() * 3);
    for (size_t p = 0; p < map.size(); ++p) {
        const std::array<uint8_t, 3> c = magma(map[p]);
        std::copy(c.begin(), c.end(), rgb.begin() + std::ptrdiff_t(p * 3));
    }
    return rgb;
}

} // namespace pnb::reference
