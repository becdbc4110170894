// Bands 0..2 real SH: basis, exact equirect projection, quadrature projection, irradiance,
// window and rotation about +Y (see sh9.h).
#include "pnb_lighting/sh9.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace pnb::lighting {
namespace {

constexpr double kPi = std::numbers::pi;

// Unit direction, or +Y for zero / non-finite input (scaled first so 1e300 components do not
// overflow the length).
glm::dvec3 unitOrUp(const glm::dvec3& w) {
    double m = std::max({std::abs(w.x), std::abs(w.y), std::abs(w.z)});
    if (!(m > 0.0) || !std::isfinite(m)) return {0.0, 1.0, 0.0};
    glm::dvec3 s = w / m;
    return s / std::sqrt(glm::dot(s, s));
}

double radianceOrZero(double v) {
    return (std::isfinite(v) && v > 0.0) ? v : 0.0;
}
glm::dvec3 radianceOrZero(const glm::dvec3& v) {
    return {radianceOrZero(v.x), radianceOrZero(v.y), radianceOrZero(v.z)};
}

// Antiderivatives in mu = cos(theta) of the polar factors, by band l and |m|:
//   (0,0): 1   (1,0): mu   (1,1): sqrt(1-mu^2)   (2,0): 3mu^2-1   (2,1): mu sqrt(1-mu^2)   (2,2):
//   1-mu^2
struct Polar {
    double p00, p10, p11, p20, p21, p22;
};
Polar polarAntiderivative(double mu) {
    double s2 = std::max(0.0, 1.0 - mu * mu), s = std::sqrt(s2);
    return {mu,
            0.5 * mu * mu,
            0.5 * (mu * s + std::asin(std::clamp(mu, -1.0, 1.0))),
            mu * mu * mu - mu,
            -s2 * s / 3.0,
            mu - mu * mu * mu / 3.0};
}

} // namespace

Sh9 sh9Basis(const glm::dvec3& wIn) {
    glm::dvec3 w = unitOrUp(wIn);
    double x = w.x, y = w.y, z = w.z;
    return {kSh9K0,
            kSh9K1 * z,
            kSh9K1 * y,
            kSh9K1 * x,
            kSh9K2 * x * z,
            kSh9K2 * y * z,
            kSh9K20 * (3.0 * y * y - 1.0),
            kSh9K2 * x * y,
            kSh9K22 * (x * x - z * z)};
}

glm::dvec3 sh9Evaluate(const Sh9Rgb& sh, const glm::dvec3& w) {
    Sh9 y = sh9Basis(w);
    glm::dvec3 r(0.0);
    for (size_t k = 0; k < 9; ++k)
        r += sh.c[k] * y[k];
    return r;
}

glm::dvec3 equirectDirection(double u, double v) {
    if (!std::isfinite(u) || !std::isfinite(v)) return {0.0, 1.0, 0.0};
    double theta = kPi * std::clamp(v, 0.0, 1.0);
    double phi = 2.0 * kPi * (u - std::floor(u) - 0.5);
    double s = std::sin(theta);
    return {s * std::cos(phi), std::cos(theta), s * std::sin(phi)};
}

glm::dvec2 equirectUv(const glm::dvec3& wIn) {
    glm::dvec3 w = unitOrUp(wIn);
    double v = std::acos(std::clamp(w.y, -1.0, 1.0)) / kPi;
    double u = std::atan2(w.z, w.x) / (2.0 * kPi) + 0.5;
    if (!(u < 1.0)) u = 0.0;
    return {std::clamp(u, 0.0, 1.0), std::clamp(v, 0.0, 1.0)};
}

Sh9Rgb sh9ProjectEquirect(std::span<const float> rgb, uint32_t width, uint32_t height) {
    Sh9Rgb out;
    if (width == 0 || height == 0 || rgb.size() / 3 / width < height) return out;

    // Azimuthal integrals per column: dphi, int cos(m phi), int sin(m phi) for m = 1, 2.
    struct Azimuth {
        double d, c1, s1, c2, s2;
    };
    std::vector<Azimuth> az(width);
    for (uint32_t i = 0; i < width; ++i) {
        double a = 2.0 * kPi * (double(i) / width - 0.5),
               b = 2.0 * kPi * (double(i + 1) / width - 0.5);
        az[i] = {b - a, std::sin(b) - std::sin(a), std::cos(a) - std::cos(b),
                 0.5 * (std::sin(2.0 * b) - std::sin(2.0 * a)),
                 0.5 * (std::cos(2.0 * a) - std::cos(2.0 * b))};
    }
    Polar top = polarAntiderivative(1.0);
    for (uint32_t j = 0; j < height; ++j) {
        // Row j spans theta in [pi j / H, pi (j+1) / H]; mu runs from cos(theta0) down to
        // cos(theta1).
        double mu1 = (j + 1 == height) ? -1.0 : std::cos(kPi * double(j + 1) / height);
        Polar bottom = polarAntiderivative(mu1);
        Polar p{top.p00 - bottom.p00, top.p10 - bottom.p10, top.p11 - bottom.p11,
                top.p20 - bottom.p20, top.p21 - bottom.p21, top.p22 - bottom.p22};
        top = bottom;

        glm::dvec3 sd(0.0), sc1(0.0), ss1(0.0), sc2(0.0), ss2(0.0);
        const float* row = rgb.data() + size_t(j) * width * 3;
        for (uint32_t i = 0; i < width; ++i) {
            glm::dvec3 L = radianceOrZero(glm::dvec3(row[3 * i], row[3 * i + 1], row[3 * i + 2]));
            sd += L * az[i].d;
            sc1 += L * az[i].c1;
            ss1 += L * az[i].s1;
            sc2 += L * az[i].c2;
            ss2 += L * az[i].s2;
        }
        out.c[0] += kSh9K0 * p.p00 * sd;
        out.c[1] += kSh9K1 * p.p11 * ss1;
        out.c[2] += kSh9K1 * p.p10 * sd;
        out.c[3] += kSh9K1 * p.p11 * sc1;
        out.c[4] += kSh9K22 * p.p22 * ss2; // k2 x z = (k2 / 2) sin^2(theta) sin(2 phi)
        out.c[5] += kSh9K2 * p.p21 * ss1;
        out.c[6] += kSh9K20 * p.p20 * sd;
        out.c[7] += kSh9K2 * p.p21 * sc1;
        out.c[8] += kSh9K22 * p.p22 * sc2;
    }
    return out;
}

void gaussLegendre(uint32_t n, std::vector<double>& x, std::vector<double>& w) {
    n = std::clamp<uint32_t>(n, 1, 4096);
    x.assign(n, 0.0);
    w.assign(n, 0.0);
    for (uint32_t i = 0; i < n; ++i) {
        double z = std::cos(kPi * (double(i) + 0.75) / (double(n) + 0.5)), dp = 1.0;
        for (int iter = 0; iter < 100; ++iter) {
            double p0 = 1.0, p1 = z;
            for (uint32_t k = 2; k <= n; ++k) {
                double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / double(k);
                p0 = p1;
                p1 = p2;
            }
            dp = double(n) * (z * p1 - p0) / (z * z - 1.0);
            double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-15) break;
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
}

Sh9Rgb sh9ProjectFunction(const std::function<glm::dvec3(const glm::dvec3&)>& radiance,
                          uint32_t polarNodes) {
    Sh9Rgb out;
    if (!radiance) return out;
    uint32_t n = std::clamp<uint32_t>(polarNodes, 2, 512), nPhi = 4 * n;
    std::vector<double> x, w;
    gaussLegendre(n, x, w);
    double dPhi = 2.0 * kPi / nPhi;
    for (int hemi = 0; hemi < 2; ++hemi) {
        for (uint32_t i = 0; i < n; ++i) {
            // [-1, 1] -> [0, 1] (upper) or [-1, 0] (lower).
            double mu = 0.5 * x[i] + (hemi == 0 ? 0.5 : -0.5), weight = 0.5 * w[i] * dPhi;
            double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
            for (uint32_t j = 0; j < nPhi; ++j) {
                double phi = dPhi * (j + 0.5);
                glm::dvec3 dir(s * std::cos(phi), mu, s * std::sin(phi));
                glm::dvec3 L = radianceOrZero(radiance(dir)) * weight;
                Sh9 y = sh9Basis(dir);
                for (size_t k = 0; k < 9; ++k)
                    out.c[k] += L * y[k];
            }
        }
    }
    return out;
}

std::array<double, 3> sh9WindowWeights(ShWindow window) {
    if (window == ShWindow::NonNegative) return {1.0, 0.75, 0.4};
    return {1.0, 1.0, 1.0};
}

Sh9Rgb sh9IrradianceCoefficients(const Sh9Rgb& radiance, ShWindow window) {
    std::array<double, 3> wl = sh9WindowWeights(window);
    const double a[3] = {kPi * wl[0], 2.0 * kPi / 3.0 * wl[1], kPi / 4.0 * wl[2]};
    static constexpr int kBand[9] = {0, 1, 1, 1, 2, 2, 2, 2, 2};
    Sh9Rgb e;
    for (size_t k = 0; k < 9; ++k)
        e.c[k] = radiance.c[k] * a[kBand[k]];
    return e;
}

glm::dvec3 sh9Irradiance(const Sh9Rgb& radiance, const glm::dvec3& n, ShWindow window) {
    return sh9Evaluate(sh9IrradianceCoefficients(radiance, window), n);
}

Sh9Rgb sh9RotateY(const Sh9Rgb& sh, double angle) {
    if (!std::isfinite(angle)) return sh;
    // L'(phi) = L(phi + angle): a cos(m phi) + b sin(m phi) becomes
    // (a cos(m angle) + b sin(m angle)) cos(m phi) + (b cos(m angle) - a sin(m angle)) sin(m phi).
    double a = std::remainder(angle, 2.0 * kPi);
    double c1 = std::cos(a), s1 = std::sin(a), c2 = std::cos(2.0 * a), s2 = std::sin(2.0 * a);
    Sh9Rgb r = sh;
    auto pair = [&](size_t cosIdx, size_t sinIdx, double c, double s) {
        r.c[cosIdx] = sh.c[cosIdx] * c + sh.c[sinIdx] * s;
        r.c[sinIdx] = sh.c[sinIdx] * c - sh.c[cosIdx] * s;
    };
    pair(3, 1, c1, s1); // band 1: x, z
    pair(7, 5, c1, s1); // band 2, |m| = 1: xy, yz
    pair(8, 4, c2, s2); // band 2, |m| = 2: x^2 - z^2, 2xz
    return r;
}

} // namespace pnb::lighting
