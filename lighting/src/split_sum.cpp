// GGX, height-correlated Smith visibility, Hammersley, GGX sampling and the split-sum BRDF table
// (see split_sum.h).
#include "pnb_lighting/split_sum.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pnb::lighting {
namespace {

constexpr double kPi = std::numbers::pi;

double clampOr(double v, double lo, double hi, double ifNan) {
    return std::isnan(v) ? ifNan : std::clamp(v, lo, hi);
}

double radicalInverse(uint32_t bits) {
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return double(bits) * 2.3283064365386963e-10; // / 2^32
}

} // namespace

double ggxAlpha(double roughness) {
    double r = clampOr(roughness, 0.0, 1.0, 1.0);
    return r * r;
}

double ggxD(double nDotH, double alpha) {
    double a = clampOr(alpha, 1e-4, 1.0, 1.0), a2 = a * a;
    double c = clampOr(nDotH, 0.0, 1.0, 0.0);
    double d = c * c * (a2 - 1.0) + 1.0; // in [a2, 1]
    return a2 / (kPi * d * d);
}

double smithGgxCorrelatedV(double nDotV, double nDotL, double alpha) {
    if (!(nDotV > 0.0) || !(nDotL > 0.0)) return 0.0;
    // Cosines below 1e-6 count as 1e-6, so V stays finite at alpha = 0 (where it is 1/(4 v l)).
    double v = std::clamp(nDotV, 1e-6, 1.0), l = std::clamp(nDotL, 1e-6, 1.0);
    double a = clampOr(alpha, 0.0, 1.0, 1.0), a2 = a * a;
    double gv = l * std::sqrt(v * v * (1.0 - a2) + a2), gl = v * std::sqrt(l * l * (1.0 - a2) + a2);
    return 0.5 / (gv + gl); // gv + gl >= 2 v l > 0
}

glm::dvec2 hammersley(uint32_t i, uint32_t n) {
    n = std::max(n, 1u);
    return {double(i % n) / double(n), radicalInverse(i)};
}

glm::dvec3 ggxSampleHalfVector(const glm::dvec2& xi, double alpha) {
    // Karis 2013's assignment: xi.x (i / n for Hammersley) drives phi, xi.y the polar angle.
    double x1 = clampOr(xi.x, 0.0, 1.0, 0.0), x2 = clampOr(xi.y, 0.0, 1.0, 0.0);
    double a = clampOr(alpha, 0.0, 1.0, 1.0);
    double denom = 1.0 + (a * a - 1.0) * x2; // >= a^2; 0 only for a = 0 and x2 = 1
    double cos2 = denom > 0.0 ? (1.0 - x2) / denom : 1.0;
    double cosT = std::sqrt(std::clamp(cos2, 0.0, 1.0)),
           sinT = std::sqrt(std::max(0.0, 1.0 - cosT * cosT));
    double phi = 2.0 * kPi * x1;
    return {sinT * std::cos(phi), sinT * std::sin(phi), cosT};
}

glm::dvec3 ggxSampleHalfVector(const glm::dvec2& xi, double alpha, const glm::dvec3& nIn) {
    glm::dvec3 n(0.0, 0.0, 1.0);
    double len = glm::length(nIn);
    if (len > 0.0 && std::isfinite(len)) n = nIn / len;
    // Orthonormal basis around n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
    double sign = std::copysign(1.0, n.z), a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    glm::dvec3 t(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        bt(b, sign + n.y * n.y * a, -n.y);
    glm::dvec3 h = ggxSampleHalfVector(xi, alpha);
    return t * h.x + bt * h.y + n * h.z;
}

glm::dvec2 splitSumBrdf(double nDotV, double roughness, uint32_t samples) {
    double nv = clampOr(nDotV, 1e-4, 1.0, 1.0), alpha = ggxAlpha(roughness);
    samples = std::max(samples, 1u);
    glm::dvec3 v(std::sqrt(std::max(0.0, 1.0 - nv * nv)), 0.0, nv);
    double a = 0.0, b = 0.0;
    for (uint32_t i = 0; i < samples; ++i) {
        glm::dvec3 h = ggxSampleHalfVector(hammersley(i, samples), alpha);
        double vh = glm::dot(v, h);
        glm::dvec3 l = 2.0 * vh * h - v;
        double nl = l.z, nh = h.z;
        if (!(nl > 0.0) || !(nh > 0.0) || !(vh > 0.0)) continue;
        double gv = 4.0 * smithGgxCorrelatedV(nv, nl, alpha) * nl * vh / nh;
        double fc = std::pow(1.0 - vh, 5.0);
        a += (1.0 - fc) * gv;
        b += fc * gv;
    }
    return {a / samples, b / samples};
}

std::vector<float> splitSumLut(uint32_t width, uint32_t height, uint32_t samples) {
    std::vector<float> lut;
    if (width == 0 || height == 0) return lut;
    lut.resize(size_t(width) * height * 2);
    for (uint32_t j = 0; j < height; ++j) splitSumLutRow(width, height, samples, j, &lut[size_t(j) * width * 2]);
    return lut;
}

void splitSumLutRow(uint32_t width, uint32_t height, uint32_t samples, uint32_t j, float* out) {
    for (uint32_t i = 0; i < width; ++i) {
        glm::dvec2 ab = splitSumBrdf((i + 0.5) / width, (j + 0.5) / height, samples);
        out[size_t(i) * 2] = float(ab.x);
        out[size_t(i) * 2 + 1] = float(ab.y);
    }
}

} // namespace pnb::lighting
