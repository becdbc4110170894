// pnb_lighting/sh9.h — diffuse image-based lighting as real spherical harmonics of bands 0..2
// (9 coefficients per colour channel): projection of an environment's radiance, irradiance by
// the cosine-lobe convolution, rotation about the up axis, and a window that keeps the
// irradiance non-negative. Pure CPU (no GL): the converter bakes the coefficients, the shaders
// evaluate sh9Basis with the same constants.
//
// Frame: world +Y is up (glTF). The basis is the usual real SH with the polar axis on +Y and the
// azimuth phi measured from +X towards +Z (x = sin(theta) cos(phi), y = cos(theta),
// z = sin(theta) sin(phi)); index, (l, m) and function, with no Condon-Shortley sign:
//   0 (0, 0)  k0                    k0  = 1 / (2 sqrt(pi))      = 0.282095
//   1 (1,-1)  k1 z                  k1  = sqrt(3) / (2 sqrt(pi)) = 0.488603
//   2 (1, 0)  k1 y
//   3 (1, 1)  k1 x
//   4 (2,-2)  k2 x z                k2  = sqrt(15) / (2 sqrt(pi)) = 1.092548
//   5 (2,-1)  k2 y z
//   6 (2, 0)  k20 (3 y^2 - 1)       k20 = sqrt(5) / (4 sqrt(pi)) = 0.315392
//   7 (2, 1)  k2 x y
//   8 (2, 2)  k22 (x^2 - z^2)       k22 = sqrt(15) / (4 sqrt(pi)) = 0.546274
// so each (m, -m) pair is (cos m phi, sin m phi) times one polar factor, which makes the rotation
// about +Y a plane rotation of each pair by m * angle (sh9RotateY; exact, not resampled).
//
// Equirectangular images: texel (i, j) of a W x H image (row 0 at the top) covers
// u in [i/W, (i+1)/W], v in [j/H, (j+1)/H] with theta = pi v (v = 0 is the zenith, +Y) and
// phi = 2 pi (u - 1/2) (the centre column looks along +X, u = 3/4 along +Z); equirectDirection and
// equirectUv are the mapping both ways. The projection treats every texel as constant radiance
// over its exact patch of the sphere and integrates the basis over the patch in closed form (the
// basis separates into a polynomial in cos(theta) times cos/sin(m phi)), so:
//   - the weights are the exact solid angles dphi * (cos theta0 - cos theta1) (the sin(theta)
//     weighting, integrated rather than sampled at the texel centre): they sum to 4 pi for any
//     size, and a constant image projects to exactly L * sqrt(4 pi) in band 0 and 0 elsewhere;
//   - a 1 x 1 image is valid and means a constant (its band-1/2 integrals vanish exactly).
//
// Irradiance (Ramamoorthi & Hanrahan 2001, "An Efficient Representation for Irradiance
// Environment Maps", eq. 7-8): E(n) = sum_lm A_l w_l L_lm Y_lm(n) with A0 = pi, A1 = 2 pi / 3,
// A2 = pi / 4 (the clamped cosine's zonal coefficients) and w_l the window below. A constant
// radiance L gives E = pi L for every normal; a white Lambertian surface reflects E / pi.
//
// Window (ShWindow::NonNegative): E(n) is the environment convolved with the zonal kernel
// K(t) = sum_l A_l w_l (2l + 1) / (4 pi) P_l(t), t = cos(angle between n and the light). Without a
// window K(t) = 3/32 + t/2 + 15/32 t^2, which is negative for t in (-0.82, -0.24) (minimum
// -0.0396 at t = -8/15): a very bright sun 122 degrees from a normal pushes E below zero (the
// sky can be 1 nit and the sun 1e5, tests/player/sh9_test.cpp shows it). Hanning or Lanczos-sigma
// windows of width 3 still leave K(-1) < 0. We use w = (1, 3/4, 2/5), which makes the kernel
// K(t) = (3/16) (1 + t)^2: non-negative everywhere (so E >= 0 for any non-negative environment,
// exactly, not by clamping), zero at the antipode (no back-lighting) and non-decreasing in t. Among
// windows whose kernel is non-negative and has no back lobe it has the largest peak K(1) (maximise
// 1/4 + w1/2 + 5 w2/16 subject to K(-1) >= 0 and the vertex at t <= -1). Its cost in energy: band 0
// is untouched, so the irradiance averaged over all normals (the total energy) and the irradiance
// of any constant environment are unchanged; for a single directional source the peak falls from
// 1.0625 (unwindowed; exact clamped cosine: 1) to 0.75 of the source's irradiance and the side
// (t = 0) rises from 0.094 to 0.19 (exact: 0): light is spread, not lost. Smooth skies carry little
// band-1/2 energy and change little.
//
// Every function is total: NaN, infinite or negative radiance samples count as 0 (radiance is
// non-negative), a zero or non-finite direction evaluates as +Y, an empty or short image gives
// all-zero coefficients, a non-finite angle rotates by 0.
//
// Does NOT do: bands above 2 (R&H 2001: order 2 leaves an average irradiance error under 3%;
// the clamped cosine test here measures 0.8% of the peak),
// bilinear reconstruction of the image (texels are constant patches), rotation about other axes,
// sampling the image itself (specular: split_sum.h and the prefiltered cube), sky visibility.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace pnb::lighting {

inline constexpr double kSh9K0 = 0.28209479177387814;  // 1 / (2 sqrt(pi))
inline constexpr double kSh9K1 = 0.48860251190291992;  // sqrt(3) / (2 sqrt(pi))
inline constexpr double kSh9K2 = 1.09254843059207907;  // sqrt(15) / (2 sqrt(pi))
inline constexpr double kSh9K20 = 0.31539156525252005; // sqrt(5) / (4 sqrt(pi))
inline constexpr double kSh9K22 = 0.54627421529603953; // sqrt(15) / (4 sqrt(pi))

using Sh9 = std::array<double, 9>;
// Coefficients of an RGB function: c[k] holds basis k's coefficient for (r, g, b).
struct Sh9Rgb {
    std::array<glm::dvec3, 9> c{};
};

enum class ShWindow { None, NonNegative };

// The 9 basis functions at direction w (normalised here; zero or non-finite w evaluates at +Y).
Sh9 sh9Basis(const glm::dvec3& w);
// sum_k c[k] * sh9Basis(w)[k].
glm::dvec3 sh9Evaluate(const Sh9Rgb& sh, const glm::dvec3& w);

// The equirectangular mapping (see the header comment). equirectDirection takes any u, v (v is
// clamped to [0, 1], u wraps; non-finite gives +Y); equirectUv returns u in [0, 1), v in [0, 1].
glm::dvec3 equirectDirection(double u, double v);
glm::dvec2 equirectUv(const glm::dvec3& w);

// Projection of an equirectangular radiance image: `rgb` holds width * height texels of three
// floats, row 0 at the top. Exact for a piecewise-constant image (see the header comment). A zero
// size or an `rgb` shorter than width * height * 3 gives all zeros.
Sh9Rgb sh9ProjectEquirect(std::span<const float> rgb, uint32_t width, uint32_t height);

// Projection of an analytic radiance L(w) (w unit, world frame) by deterministic product
// quadrature: Gauss-Legendre in cos(theta) with `polarNodes` nodes on each hemisphere (the horizon
// is a boundary, so a sky with a ground discontinuity at y = 0 keeps full order) times
// 4 * polarNodes uniform azimuths (exact for the basis' trigonometric factors). Exact for a
// constant and for any polynomial radiance of degree <= 2 * polarNodes - 3; polarNodes is clamped
// to [2, 512], L is called 8 * polarNodes^2 times.
Sh9Rgb sh9ProjectFunction(const std::function<glm::dvec3(const glm::dvec3&)>& radiance,
                          uint32_t polarNodes = 32);

// The n-point Gauss-Legendre rule on [-1, 1] (Newton on P_n; n clamped to [1, 4096]): exact for
// polynomials of degree <= 2n - 1. sh9ProjectFunction's polar rule, shared with the sky.
void gaussLegendre(uint32_t n, std::vector<double>& nodes, std::vector<double>& weights);

// Window weights per band (w0, w1, w2): (1, 1, 1) or (1, 3/4, 2/5).
std::array<double, 3> sh9WindowWeights(ShWindow window);
// Radiance SH -> irradiance SH: coefficient k times A_l * w_l. Evaluate the result with
// sh9Evaluate (or the shader's basis) to get E(n), in the radiance's unit times steradians
// (nits -> lux).
Sh9Rgb sh9IrradianceCoefficients(const Sh9Rgb& radiance, ShWindow window);
// E(n) = sh9Evaluate(sh9IrradianceCoefficients(radiance, window), n).
glm::dvec3 sh9Irradiance(const Sh9Rgb& radiance, const glm::dvec3& n, ShWindow window);

// The coefficients of the environment turned by `angle` radians about +Y (right-handed: seen
// from above, +X turns towards -Z for a positive angle): L'(w) = L(R_y(-angle) w), so a feature
// at direction d appears at R_y(angle) d, with R_y the matrix of glm::rotate(angle, (0, 1, 0)).
Sh9Rgb sh9RotateY(const Sh9Rgb& sh, double angle);

} // namespace pnb::lighting
