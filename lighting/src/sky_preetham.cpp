// Preetham, Shirley & Smits 1999 daylight sky (see sky_preetham.h).
#include "pnb_lighting/sky_preetham.h"

#include "pnb_lighting/sh9.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace pnb::lighting {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwilight = 6.0 * kPi / 180.0; // below this the sky is black
constexpr double kMinCos = 1e-3;

double clampTurbidity(double t) {
    return std::isnan(t) ? 3.0 : std::clamp(t, 2.0, 10.0);
}

bool unitOrFalse(const glm::dvec3& w, glm::dvec3& out) {
    double m = std::max({std::abs(w.x), std::abs(w.y), std::abs(w.z)});
    if (!(m > 0.0) || !std::isfinite(m)) return false;
    glm::dvec3 s = w / m;
    out = s / std::sqrt(glm::dot(s, s));
    return true;
}

double finiteNonNegative(double v) {
    return (std::isfinite(v) && v > 0.0) ? v : 0.0;
}

} // namespace

double perezF(const PerezCoefficients& k, double cosTheta, double gamma) {
    double c = std::isnan(cosTheta) ? 1.0 : std::clamp(cosTheta, kMinCos, 1.0);
    double g = std::isnan(gamma) ? 0.0 : std::clamp(gamma, 0.0, kPi), cg = std::cos(g);
    return (1.0 + k.a * std::exp(k.b / c)) * (1.0 + k.c * std::exp(k.d * g) + k.e * cg * cg);
}

std::array<PerezCoefficients, 3> preethamCoefficients(double turbidity) {
    double t = clampTurbidity(turbidity);
    return {PerezCoefficients{0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251,
                              0.1206 * t - 2.5771, -0.0670 * t + 0.3703},
            PerezCoefficients{-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125,
                              -0.0641 * t - 0.8989, -0.0033 * t + 0.0452},
            PerezCoefficients{-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102,
                              -0.0441 * t - 1.6537, -0.0109 * t + 0.0529}};
}

double preethamZenithLuminance(double turbidity, double thetaSun) {
    double t = clampTurbidity(turbidity),
           ts = std::isnan(thetaSun) ? 0.0 : std::clamp(thetaSun, 0.0, kPi / 2);
    double chi = (4.0 / 9.0 - t / 120.0) * (kPi - 2.0 * ts); // in [0, 1.344] for T >= 2: tan finite
    return (4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192;
}

glm::dvec2 preethamZenithChromaticity(double turbidity, double thetaSun) {
    double t = clampTurbidity(turbidity),
           ts = std::isnan(thetaSun) ? 0.0 : std::clamp(thetaSun, 0.0, kPi / 2);
    double s3 = ts * ts * ts, s2 = ts * ts;
    double x = t * t * (0.00166 * s3 - 0.00375 * s2 + 0.00209 * ts) +
               t * (-0.02903 * s3 + 0.06377 * s2 - 0.03202 * ts + 0.00394) +
               (0.11693 * s3 - 0.21196 * s2 + 0.06052 * ts + 0.25886);
    double y = t * t * (0.00275 * s3 - 0.00610 * s2 + 0.00317 * ts) +
               t * (-0.04214 * s3 + 0.08970 * s2 - 0.04153 * ts + 0.00516) +
               (0.15346 * s3 - 0.26756 * s2 + 0.06670 * ts + 0.26688);
    return {x, y};
}

glm::dvec3 xyYToLinearRec709(double x, double y, double Y) {
    if (!(y > 0.0) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(Y))
        return glm::dvec3(0.0);
    double X = x * Y / y, Z = (1.0 - x - y) * Y / y;
    glm::dvec3 rgb(3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z,
                   -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z,
                   0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z);
    return {finiteNonNegative(rgb.x), finiteNonNegative(rgb.y), finiteNonNegative(rgb.z)};
}

PreethamSky::PreethamSky(const PreethamSkyParams& params) {
    turbidity_ = clampTurbidity(params.turbidity);
    glm::dvec3 sun(0.0, 1.0, 0.0);
    unitOrFalse(params.sunDirection, sun);
    double elevation = std::asin(std::clamp(sun.y, -1.0, 1.0));
    if (elevation < 0.0) {
        fade_ = std::max(0.0, 1.0 + elevation / kTwilight);
        // The sun on the horizon at the same azimuth (straight down: any azimuth, take +X).
        glm::dvec3 flat(sun.x, 0.0, sun.z);
        sun = glm::length(flat) > 1e-12 ? glm::normalize(flat) : glm::dvec3(1.0, 0.0, 0.0);
    }
    sun_ = sun;
    thetaSun_ = std::acos(std::clamp(sun.y, 0.0, 1.0));
    k_ = preethamCoefficients(turbidity_);
    zenithY_ = std::max(0.0, preethamZenithLuminance(turbidity_, thetaSun_));
    glm::dvec2 xy = preethamZenithChromaticity(turbidity_, thetaSun_);
    zenithX_ = xy.x;
    zenithYc_ = xy.y;
    denomY_ = perezF(k_[0], 1.0, thetaSun_);
    denomX_ = perezF(k_[1], 1.0, thetaSun_);
    denomYc_ = perezF(k_[2], 1.0, thetaSun_);

    // Sky irradiance on a horizontal surface: Gauss-Legendre (24 nodes) in mu = cos(theta) on
    // [0, 1] times 96 azimuths.
    const int n = 24, nPhi = 96;
    std::vector<double> x, w;
    gaussLegendre(n, x, w);
    glm::dvec3 e(0.0);
    for (int i = 0; i < n; ++i) {
        double mu = 0.5 * x[i] + 0.5, s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        for (int j = 0; j < nPhi; ++j) {
            double phi = 2.0 * kPi * (j + 0.5) / nPhi;
            e += skyRadiance(glm::dvec3(s * std::cos(phi), mu, s * std::sin(phi))) *
                 (mu * 0.5 * w[i] * 2.0 * kPi / nPhi);
        }
    }
    skyE_ = e;
    glm::dvec3 albedo = glm::clamp(params.groundAlbedo, glm::dvec3(0.0), glm::dvec3(1.0));
    glm::dvec3 sunE(finiteNonNegative(params.sunIlluminance.x),
                    finiteNonNegative(params.sunIlluminance.y),
                    finiteNonNegative(params.sunIlluminance.z));
    double sunCos =
        elevation >= 0.0 ? sun.y : 0.0; // the sun lights the ground only above the horizon
    glm::dvec3 g = albedo * (skyE_ + sunE * sunCos) / kPi;
    ground_ = {finiteNonNegative(g.x), finiteNonNegative(g.y), finiteNonNegative(g.z)};
}

double PreethamSky::skyLuminanceKcd(double cosTheta, double gamma) const {
    return zenithY_ * perezF(k_[0], cosTheta, gamma) / denomY_;
}

glm::dvec3 PreethamSky::skyRadiance(const glm::dvec3& d) const {
    if (fade_ <= 0.0) return glm::dvec3(0.0);
    double gamma = std::acos(std::clamp(glm::dot(d, sun_), -1.0, 1.0));
    double Y = 1000.0 * fade_ * skyLuminanceKcd(d.y, gamma);
    double x = zenithX_ * perezF(k_[1], d.y, gamma) / denomX_;
    double y = zenithYc_ * perezF(k_[2], d.y, gamma) / denomYc_;
    return xyYToLinearRec709(x, y, std::max(0.0, Y));
}

glm::dvec3 PreethamSky::radiance(const glm::dvec3& dir) const {
    glm::dvec3 d;
    if (!unitOrFalse(dir, d)) return glm::dvec3(0.0);
    return d.y < 0.0 ? ground_ : skyRadiance(d);
}

double PreethamSky::luminance(const glm::dvec3& dir) const {
    glm::dvec3 d;
    if (!unitOrFalse(dir, d)) return 0.0;
    if (d.y < 0.0) return 0.2126 * ground_.x + 0.7152 * ground_.y + 0.0722 * ground_.z;
    if (fade_ <= 0.0) return 0.0;
    double gamma = std::acos(std::clamp(glm::dot(d, sun_), -1.0, 1.0));
    return finiteNonNegative(1000.0 * fade_ * skyLuminanceKcd(d.y, gamma));
}

double preethamSunIlluminance(double turbidity, const glm::dvec3& sunDirection) {
    double t = std::isfinite(turbidity) ? std::clamp(turbidity, 2.0, 10.0) : 3.0;
    glm::dvec3 d = sunDirection;
    double len = glm::length(d);
    double y = (std::isfinite(len) && len > 0) ? d.y / len : 1.0;
    double elevationDeg = std::asin(std::clamp(y, -1.0, 1.0)) * (180.0 / 3.14159265358979323846);
    double airMass = 10.0;
    if (elevationDeg > 5.6) {
        double zenithDeg = 90.0 - elevationDeg;
        airMass = 1.0 / (std::cos(zenithDeg * 3.14159265358979323846 / 180.0) +
                         0.50572 * std::pow(96.07995 - zenithDeg, -1.6364));
        airMass = std::min(airMass, 10.0);
    }
    return 128000.0 * std::exp(-(0.25 + 0.07 * (t - 3.0)) * airMass);
}

} // namespace pnb::lighting
