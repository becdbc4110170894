// HDR-FLIP (EG 2021; flip.h): LDR-FLIP at every exposure from the one that just keeps the
// reference's brightest pixel off white to the one that shows its median at the same tone, and
// per pixel the worst of them — the error a viewer finds by sweeping the exposure of both images.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

#include <glm/common.hpp>

#include "pnb_reference/flip.h"

namespace pnb::reference {

namespace {

// Narkowicz's ACES fit of 0.6 x as the rational polynomial (k0 x^2 + k1 x + k2) / (k3 x^2 + k4 x +
// k5): the paper writes its tone maps in this form to invert them in closed form.
constexpr double kAces[6] = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};

// The linear-interpolated 50th percentile of `values` (sorted in place).
double median(std::vector<double>& values) {
    std::sort(values.begin(), values.end());
    const double at = 0.5 * double(values.size() - 1);
    const size_t below = size_t(at);
    const size_t above = std::min(below + 1, values.size() - 1);
    return values[below] + (at - double(below)) * (values[above] - values[below]);
}

} // namespace

double hdrFlipAces(double x) {
    if (std::isnan(x) || x <= 0) return 0.0;
    if (std::isinf(x)) return 1.0; // inf / inf: the limit is 2.51 / 2.43 > 1, so white
    const double y =
        (kAces[0] * x * x + kAces[1] * x + kAces[2]) / (kAces[3] * x * x + kAces[4] * x + kAces[5]);
    return std::clamp(y, 0.0, 1.0);
}

double hdrFlipAcesInverse(double target) {
    // t(x) = target <=> (k0 - t k3) x^2 + (k1 - t k4) x + (k2 - t k5) = 0; the positive root.
    const double a = kAces[0] - target * kAces[3], b = kAces[1] - target * kAces[4],
                 c = kAces[2] - target * kAces[5];
    const double c0 = b / a, c1 = c / a;
    return -0.5 * c0 + std::sqrt(0.25 * c0 * c0 - c1);
}

ExposureRange hdrFlipExposureRange(std::span<const glm::vec3> reference) {
    std::vector<double> luminance, positive;
    luminance.reserve(reference.size());
    for (const glm::vec3& c : reference) {
        const glm::dvec3 v = glm::max(glm::dvec3(c), 0.0);
        double y = 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z;
        if (std::isnan(y)) y = 0.0;
        luminance.push_back(y);
        if (y > 0 && std::isfinite(y)) positive.push_back(y);
    }
    ExposureRange range;
    if (positive.empty()) return range;
    const double brightest = *std::max_element(positive.begin(), positive.end());
    double middle = median(luminance);
    if (!(middle > 0)) middle = median(positive);
    const double xMax = hdrFlipAcesInverse(flip_constants::kExposureToneTarget);
    range.start = std::log2(xMax / brightest);
    range.stop = std::log2(xMax / middle);
    range.count = range.start == range.stop
                      ? 1u
                      : uint32_t(std::max(2.0, std::ceil(range.stop - range.start)));
    return range;
}

HdrFlipResult hdrFlip(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                      uint32_t width, uint32_t height, double ppd) {
    return hdrFlip(test, reference, width, height, hdrFlipExposureRange(reference), ppd);
}

HdrFlipResult hdrFlip(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                      uint32_t width, uint32_t height, const ExposureRange& range, double ppd) {
    HdrFlipResult result;
    result.exposures = range;
    const size_t pixels = size_t(width) * height;
    if (pixels == 0 || test.size() != pixels || reference.size() != pixels || range.count == 0)
        return result;
    const double step =
        range.count > 1 ? (range.stop - range.start) / double(range.count - 1) : 0.0;
    // The exposures are independent LDR-FLIPs: one per thread, then the maximum in exposure order
    // (so the result, ties included, does not depend on the thread count).
    std::vector<std::vector<float>> maps(range.count);
    std::atomic<uint32_t> next{0};
    auto work = [&] {
        for (uint32_t i = next++; i < range.count; i = next++) {
            const double scale = std::exp2(range.start + step * double(i));
            const ToneMap toneMap = [scale](const glm::vec3& c) {
                return glm::vec3(float(hdrFlipAces(scale * c.x)), float(hdrFlipAces(scale * c.y)),
                                 float(hdrFlipAces(scale * c.z)));
            };
            maps[i] = toneMappedLdrFlip(test, reference, width, height, toneMap, ppd);
        }
    };
    const uint32_t threads = std::clamp(std::thread::hardware_concurrency(), 1u, range.count);
    std::vector<std::thread> pool;
    for (uint32_t t = 1; t < threads; ++t)
        pool.emplace_back(work);
    work();
    for (std::thread& t : pool)
        t.join();

    result.error = std::move(maps[0]);
    result.exposureIndex.assign(pixels, 0);
    for (uint32_t i = 1; i < range.count; ++i)
        for (size_t p = 0; p < pixels; ++p)
            if (maps[i][p] > result.error[p]) {
                result.error[p] = maps[i][p];
                result.exposureIndex[p] =
                    uint16_t(std::min<uint32_t>(i, std::numeric_limits<uint16_t>::max()));
            }
    return result;
}

} // namespace pnb::reference
