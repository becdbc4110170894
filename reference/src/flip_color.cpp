// LDR-FLIP's colour pipeline (HPG 2020 §4): linear RGB -> YCxCz (the linearised CIELab opponent
// space of Zhang and Wandell's S-CIELAB) -> each channel blurred by its contrast sensitivity
// function (CSF) -> linear RGB clamped to the unit cube -> CIELab -> Hunt adjustment -> HyAB
// distance -> q_c power -> compressed into [0, 1] by c_max.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include "flip_filter.h"
#include "pnb_reference/flip.h"

namespace pnb::reference {

namespace {

using flip_detail::Plane;

// sRGB (IEC 61966-2-1) linear RGB -> CIE XYZ, derived from its primaries and D65 white point
// rather than typed in, so that the white point below is exactly M (1, 1, 1).
glm::dmat3 rgbToXyz() {
    auto xyz = [](double x, double y) { return glm::dvec3(x / y, 1.0, (1.0 - x - y) / y); };
    const glm::dmat3 primaries(xyz(0.64, 0.33), xyz(0.30, 0.60),
                               xyz(0.15, 0.06)); // columns R, G, B
    const glm::dvec3 white = xyz(0.3127, 0.3290);
    const glm::dvec3 scale = glm::inverse(primaries) * white;
    return glm::dmat3(primaries[0] * scale.x, primaries[1] * scale.y, primaries[2] * scale.z);
}

struct ColorSpaces {
    glm::dmat3 toXyz = rgbToXyz();
    glm::dmat3 toRgb = glm::inverse(toXyz);
    glm::dvec3 white = toXyz * glm::dvec3(1.0);
};
const ColorSpaces& spaces() {
    static const ColorSpaces s;
    return s;
}

// An input pixel as FLIP reads it: clamped to [0, 1], NaN as 0 (a NaN would spread through
// every filter it touches).
glm::dvec3 displayValue(const glm::vec3& c) {
    glm::dvec3 v;
    for (int i = 0; i < 3; ++i)
        v[i] = std::isnan(c[i]) ? 0.0 : std::clamp(double(c[i]), 0.0, 1.0);
    return v;
}

// YCxCz: Y_y = 116 y - 16, C_x = 500 (x - y), C_z = 200 (y - z) of the white-normalised XYZ.
glm::dvec3 linearRgbToYcxcz(const glm::dvec3& rgb) {
    const glm::dvec3 n = spaces().toXyz * rgb / spaces().white;
    return {116.0 * n.y - 16.0, 500.0 * (n.x - n.y), 200.0 * (n.y - n.z)};
}
glm::dvec3 ycxczToLinearRgb(const glm::dvec3& ycc) {
    const double y = (ycc.x + 16.0) / 116.0;
    const glm::dvec3 n(y + ycc.y / 500.0, y, y - ycc.z / 200.0);
    return spaces().toRgb * (n * spaces().white);
}

// CIELab of linear RGB (D65), then the Hunt adjustment: chroma scaled by L/100, since colours
// look less colourful the darker they are (HPG 2020 §4.2).
glm::dvec3 huntLab(const glm::dvec3& rgb) {
    constexpr double delta = 6.0 / 29.0;
    auto f = [](double t) {
        return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
    };
    const glm::dvec3 n = spaces().toXyz * rgb / spaces().white;
    const double L = 116.0 * f(n.y) - 16.0;
    const double a = 500.0 * (f(n.x) - f(n.y)), b = 200.0 * (f(n.y) - f(n.z));
    return {L, 0.01 * L * a, 0.01 * L * b};
}

// HyAB (Abasi et al. 2020): city-block in lightness, Euclidean in chroma.
double hyab(const glm::dvec3& p, const glm::dvec3& q) {
    return std::abs(p.x - q.x) + std::hypot(p.y - q.y, p.z - q.z);
}

// The CSFs of HPG 2020 §4.1, each a sum of Gaussians in frequency, a_i exp(-b_i f^2), whose
// spatial form a_i sqrt(pi / b_i) exp(-pi^2 r^2 / b_i) (r in degrees) is what blurs a channel.
// Achromatic and red-green are one Gaussian, blue-yellow two.
struct CsfTerm {
    double a, b;
};
constexpr CsfTerm kAchromatic[] = {{1.0, 0.0047}};
constexpr CsfTerm kRedGreen[] = {{1.0, 0.0053}};
constexpr CsfTerm kBlueYellow[] = {{34.1, 0.04}, {13.5, 0.025}};
// Every filter spans 3 standard deviations of the widest Gaussian (b = 0.04), as in the paper.
constexpr double kWidestB = 0.04;

int csfRadius(double ppd) {
    const double sigmaDegrees = std::sqrt(kWidestB / (2.0 * std::numbers::pi * std::numbers::pi));
    return int(std::ceil(3.0 * sigmaDegrees * ppd));
}

// One channel blurred by its CSF. The 2D kernel sum_i a_i sqrt(pi/b_i) g_i(x) g_i(y), normalised
// to unit sum, is a weighted sum of separable normalised Gaussians: weight_i = a_i sqrt(pi/b_i)
// (sum_k g_i(k))^2 over the sampled square, so the result equals the 2D kernel's exactly.
Plane csfFilter(const Plane& in, std::span<const CsfTerm> terms, double ppd) {
    const int r = csfRadius(ppd);
    Plane out(in.width, in.height);
    double totalWeight = 0.0;
    std::vector<Plane> parts;
    std::vector<double> weights;
    for (const CsfTerm& t : terms) {
        std::vector<float> taps(size_t(2 * r + 1));
        double sum = 0.0;
        for (int k = -r; k <= r; ++k) {
            const double x = k / ppd;
            const double g = std::exp(-std::numbers::pi * std::numbers::pi * x * x / t.b);
            taps[size_t(k + r)] = float(g);
            sum += g;
        }
        for (float& tap : taps)
            tap = float(tap / sum);
        weights.push_back(t.a * std::sqrt(std::numbers::pi / t.b) * sum * sum);
        totalWeight += weights.back();
        parts.push_back(flip_detail::correlateSeparable(in, taps, taps));
    }
    for (size_t i = 0; i < parts.size(); ++i) {
        const float w = float(weights[i] / totalWeight);
        for (size_t p = 0; p < out.v.size(); ++p)
            out.v[p] += w * parts[i].v[p];
    }
    return out;
}

// An image through the pipeline up to Hunt-adjusted CIELab, one vec3 per pixel.
std::vector<glm::dvec3> perceptualLab(std::span<const glm::vec3> image, uint32_t width,
                                      uint32_t height, double ppd) {
    Plane y(width, height), cx(width, height), cz(width, height);
    for (size_t p = 0; p < image.size(); ++p) {
        const glm::dvec3 ycc = linearRgbToYcxcz(displayValue(image[p]));
        y.v[p] = float(ycc.x);
        cx.v[p] = float(ycc.y);
        cz.v[p] = float(ycc.z);
    }
    const Plane fy = csfFilter(y, kAchromatic, ppd), fcx = csfFilter(cx, kRedGreen, ppd),
                fcz = csfFilter(cz, kBlueYellow, ppd);
    std::vector<glm::dvec3> lab(image.size());
    for (size_t p = 0; p < image.size(); ++p) {
        const glm::dvec3 rgb = ycxczToLinearRgb({fy.v[p], fcx.v[p], fcz.v[p]});
        lab[p] = huntLab(glm::clamp(rgb, 0.0, 1.0));
    }
    return lab;
}

} // namespace

double flipColorMax() {
    static const double cmax = std::pow(hyab(huntLab({0.0, 1.0, 0.0}), huntLab({0.0, 0.0, 1.0})),
                                        flip_constants::kColorExponent);
    return cmax;
}

double flipCompressColor(double powered) {
    using namespace flip_constants;
    const double cmax = flipColorMax(), knee = kCompressionPoint * cmax;
    if (powered < knee) return kCompressionTarget / knee * powered;
    return kCompressionTarget + (powered - knee) / (cmax - knee) * (1.0 - kCompressionTarget);
}

namespace flip_detail {

std::vector<float> colorError(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                              uint32_t width, uint32_t height, double ppd) {
    const std::vector<glm::dvec3> t = perceptualLab(test, width, height, ppd);
    const std::vector<glm::dvec3> r = perceptualLab(reference, width, height, ppd);
    std::vector<float> error(t.size());
    for (size_t p = 0; p < t.size(); ++p)
        error[p] =
            float(flipCompressColor(std::pow(hyab(t[p], r[p]), flip_constants::kColorExponent)));
    return error;
}

Plane normalizedLuminance(std::span<const glm::vec3> image, uint32_t width, uint32_t height) {
    Plane y(width, height);
    const glm::dvec3 row(spaces().toXyz[0][1], spaces().toXyz[1][1], spaces().toXyz[2][1]);
    for (size_t p = 0; p < image.size(); ++p)
        y.v[p] = float(glm::dot(row, displayValue(image[p])) / spaces().white.y);
    return y;
}

} // namespace flip_detail

} // namespace pnb::reference
