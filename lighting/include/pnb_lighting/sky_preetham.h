// pnb_lighting/sky_preetham.h — the analytic daylight sky of Preetham, Shirley & Smits 1999 ("A
// Practical Analytic Model for Daylight", SIGGRAPH 99, Appendix A.2): sky radiance in any
// direction for a turbidity and a sun direction, in physical units (cd/m^2 = nits, linear
// Rec.709/sRGB primaries), so the player can put it beside its sun's illuminance (lux) under one
// exposure, project it with sh9ProjectFunction and prefilter it like an HDR image. Pure CPU (no
// GL).
//
// Model (theta = the view's zenith angle, gamma = the angle between the view and the sun,
// theta_s = the sun's zenith angle, T = turbidity):
//   Perez:        F(theta, gamma) = (1 + A exp(B / cos theta)) (1 + C exp(D gamma) + E cos^2 gamma)
//   distribution: Y = Y_z F_Y(theta, gamma) / F_Y(0, theta_s), likewise x and y (chromaticity)
//   coefficients: (A..E) = M (T, 1) per quantity, the paper's table (Y: A = 0.1787 T - 1.4630,
//                 B = -0.3554 T + 0.4275, C = -0.0227 T + 5.3251, D = 0.1206 T - 2.5771,
//                 E = -0.0670 T + 0.3703; x and y in sky_preetham.cpp)
//   zenith:       Y_z = (4.0453 T - 4.9710) tan(chi) - 0.2155 T + 2.4192  [kcd/m^2],
//                 chi = (4/9 - T/120) (pi - 2 theta_s);
//                 x_z, y_z = (T^2, T, 1) M (theta_s^3, theta_s^2, theta_s, 1) (3 x 4 tables)
//   colour:       X = x Y / y, Z = (1 - x - y) Y / y, then the XYZ -> linear Rec.709 (D65) matrix
//                 of IEC 61966-2-1; negative components (out of gamut) are clipped to 0.
// Units: Y_z is in kcd/m^2 in the paper; radiance() returns cd/m^2 (x 1000). The sun disc itself is
// not part of the sky (the player's directional light is the sun; Preetham's sun spectral radiance
// is not modelled here).
//
// Ranges and totality:
//   - turbidity is clamped to [2, 10] (the fit's range; NaN -> 3);
//   - the sun direction is normalised; zero or non-finite counts as the zenith (+Y);
//   - sun below the horizon: the model is undefined there (tan(chi) < 0 and Y_z eventually turns
//     negative). We evaluate it with the sun at elevation 0 and scale the whole sky by
//     fade = 1 + elevation / 6 degrees, so the sky darkens linearly to black when the sun is 6
//     degrees below the horizon (end of civil twilight) and is black below that: continuous
//     through sunset, not a twilight model (no reddening, no Earth shadow);
//   - views below the horizon (y < 0) see the ground: a constant Lambertian radiance
//     albedo / pi * (E_sky + E_sun), with E_sky the sky's own irradiance on a horizontal surface
//     (integrated once, Gauss-Legendre) and E_sun = sunIlluminance * max(0, sun.y) (the player's
//     sun, lux per channel on a surface facing it; 0 by default, so only the sky lights the
//     ground). Views with 0 <= y < 1e-3 use cos(theta) = 1e-3 (the Perez exp(B / cos) is 0 there);
//   - a zero or non-finite view direction gives 0; every output is finite and >= 0.
//
// Does NOT do: Hosek-Wilkie 2012 (better near the horizon and for high turbidity), the sun disc,
// aerial perspective, night sky, ground albedo's effect on the sky itself (Preetham has none).
#pragma once

#include <array>

#include <glm/glm.hpp>

namespace pnb::lighting {

// The five Perez coefficients of one quantity.
struct PerezCoefficients {
    double a = 0, b = 0, c = 0, d = 0, e = 0;
};
// F(theta, gamma) for cos(theta) (clamped to [1e-3, 1]) and gamma in radians.
double perezF(const PerezCoefficients& k, double cosTheta, double gamma);
// Coefficients for luminance Y, chromaticity x and chromaticity y at turbidity T (clamped).
std::array<PerezCoefficients, 3> preethamCoefficients(double turbidity);
// Zenith luminance in kcd/m^2 and zenith chromaticity (x, y) for sun zenith angle thetaSun in
// [0, pi/2] (clamped) and turbidity T (clamped).
double preethamZenithLuminance(double turbidity, double thetaSun);
glm::dvec2 preethamZenithChromaticity(double turbidity, double thetaSun);
// CIE xyY -> linear Rec.709 RGB in the unit of Y, negative components clipped; y <= 0 or
// non-finite input gives 0.
glm::dvec3 xyYToLinearRec709(double x, double y, double Y);

// The sun's direct illuminance on a surface facing it (lux) that goes with this sky, from a
// simple clear-sky model, so that the sky can be put beside a scene's sun of any brightness:
// E = 128 000 lux x exp(-a m), with m the Kasten-Young (1989) relative air mass at the sun's
// elevation (held at 10 below 5.6 degrees, so a sun on the horizon does not make the sky
// thousands of times brighter than its sun) and a luminous extinction per air mass of
// 0.25 + 0.07 (T - 3) (T clamped as the sky's): about 100 klx for a zenith sun at T = 3, 49 klx
// at 15 degrees. An approximation to the order of 10-20 %, not Preetham's spectral sun.
double preethamSunIlluminance(double turbidity, const glm::dvec3& sunDirection);

struct PreethamSkyParams {
    double turbidity = 3.0;
    glm::dvec3 sunDirection{0.0, 1.0, 0.0}; // towards the sun, world (+Y up)
    glm::dvec3 groundAlbedo{0.2};           // clamped to [0, 1]
    glm::dvec3 sunIlluminance{0.0};         // lux on a surface facing the sun, per channel
};

class PreethamSky {
public:
    explicit PreethamSky(const PreethamSkyParams& params = {});

    // Radiance towards the viewer from direction `dir` (from the viewer outwards), nits, linear
    // Rec.709.
    glm::dvec3 radiance(const glm::dvec3& dir) const;
    // The luminance Y of the model in direction dir (nits), before colour conversion and clipping;
    // the ground's luminance below the horizon.
    double luminance(const glm::dvec3& dir) const;

    double turbidity() const { return turbidity_; }
    // The sun direction the model uses (elevation clamped to >= 0) and the below-horizon fade.
    glm::dvec3 modelSunDirection() const { return sun_; }
    double fade() const { return fade_; }
    // Y_z (nits, fade applied) and the zenith chromaticity.
    double zenithLuminance() const { return 1000.0 * zenithY_ * fade_; }
    glm::dvec2 zenithChromaticity() const { return {zenithX_, zenithYc_}; }
    // The sky's irradiance on an upward horizontal surface, lux per channel (fade applied).
    glm::dvec3 skyHorizontalIlluminance() const { return skyE_; }
    glm::dvec3 groundRadiance() const { return ground_; }

private:
    double skyLuminanceKcd(double cosTheta, double gamma) const;
    glm::dvec3 skyRadiance(const glm::dvec3& unitDir) const;

    double turbidity_ = 3.0, fade_ = 1.0, thetaSun_ = 0.0;
    glm::dvec3 sun_{0.0, 1.0, 0.0};
    std::array<PerezCoefficients, 3> k_{};
    double zenithY_ = 0, zenithX_ = 0, zenithYc_ = 0; // kcd/m^2, x, y
    double denomY_ = 1, denomX_ = 1, denomYc_ = 1;    // F(0, theta_s) per quantity
    glm::dvec3 skyE_{0.0}, ground_{0.0};
};

} // namespace pnb::lighting
