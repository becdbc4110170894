// lpv_math.h — the numbers behind Light Propagation Volumes (Kaplanyan & Dachsbacher 2010; seed
// 004): the L1 spherical-harmonic basis, the clamped-cosine lobe, the solid angles of a cell's
// faces seen from its neighbour, and where the cascades sit. Pure CPU (no GL): the compute
// shaders (player/shaders/lpv_*.comp) hard-code the same constants, and the tests check both.
//
// Conventions (Sloan's real SH, the order the GPU stores them in: one RGBA texel per colour):
//   y0 = 1/(2 sqrt(pi)), (y1, y2, y3) = sqrt(3)/(2 sqrt(pi)) * (-y, z, -x)  -- stored as (c0, -y, z, -x)
// Units: the volumes store radiance divided by the sun's irradiance (dimensionless), so neither
// a 1e-6 nor a 1e6 scene, nor a 1e6-lux sun, leaves fp16's range; the look-up multiplies back.
#pragma once

#include <array>
#include <vector>
#include <cstdint>

#include <glm/glm.hpp>

namespace pnb::player {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kShY0 = 0.28209479177387814;  // 1 / (2 sqrt(pi))
inline constexpr double kShY1 = 0.48860251190291992;  // sqrt(3) / (2 sqrt(pi))
// The clamped cosine max(0, n.w) projected on the basis: zonal coefficients sqrt(pi)/2 and
// sqrt(pi/3), rotated to the normal n.
inline constexpr double kLobeC0 = 0.88622692545275801; // sqrt(pi) / 2
inline constexpr double kLobeC1 = 1.02332670794648848; // sqrt(pi / 3)
// Solid angles of a unit cell's faces seen from the centre of the neighbouring cell it shares
// its near face with: the far face and each of the four side faces. far + 4 side = 2 pi / 3
// (the near face's); six neighbours x (far + 4 side) = 4 pi.
inline constexpr double kFarFaceSolidAngle = 0.4006696846462392;
inline constexpr double kSideFaceSolidAngle = 0.4234313544367684;

using Sh4 = std::array<double, 4>;

// The basis evaluated in direction w (unit).
Sh4 shBasis(const glm::dvec3& w);
// SH coefficients of max(0, n.w) (n unit); their integral over the sphere is pi.
Sh4 cosineLobe(const glm::dvec3& n);
// sum_k a_k * shBasis(w)_k
double shEvaluate(const Sh4& a, const glm::dvec3& w);
// Integral over the sphere of the function with coefficients a (only the band-0 term survives).
inline double shIntegral(const Sh4& a) { return a[0] * kShY0 * 4.0 * kPi; }

// Exact solid angle of the axis-aligned rectangle [x0,x1] x [y0,y1] in the plane z = d > 0 seen
// from the origin (sum of corner terms atan(x y / (d sqrt(x^2 + y^2 + d^2)))).
double rectangleSolidAngle(double x0, double x1, double y0, double y1, double d);

// One cascade: a cubic grid of `cells`^3 cells of `cellSize` whose minimum corner is `origin`
// (world, double). Cascade 0 is the finest.
struct LpvCascade {
    glm::dvec3 origin{0.0};
    double cellSize = 0;
    uint32_t cells = 0;
    glm::dvec3 max() const { return origin + cellSize * double(cells); }
    bool contains(const glm::dvec3& p) const;
};

// Where the cascades are this frame.
//   - cellSize > 0: every cascade follows the camera; cascade k has cells of cellSize * 2^k,
//     is centred on the camera shifted by a quarter of its extent along the view direction, and
//     its origin snapped to whole cells (sub-cell camera motion moves nothing).
//   - cellSize == 0 (auto): the outer cascade is the scene's bounding cube with one cell of
//     margin on each side (fixed: it does not move with the camera); each finer cascade halves
//     the cell and follows the camera as above.
// Non-finite or empty scene bounds give no cascades.
std::vector<LpvCascade> placeCascades(uint32_t count, uint32_t cells, double cellSize,
                                      const glm::dvec3& sceneMin, const glm::dvec3& sceneMax,
                                      const glm::dvec3& camera, const glm::dvec3& forward);

// The probes' grid (one cascade of `cells`) with gi.cell_size 0: the scene's bounding cube
// (returns 0, placeCascades' auto) unless that spaces the probes wider than maxSpacing (> 0);
// then maxSpacing, a grid following the camera. A 2 km street scene at 20 probes would put
// them 110 m apart in a 20 m street; an interior keeps its fixed, cached grid.
double probeCellSize(uint32_t cells, double maxSpacing, const glm::dvec3& sceneMin, const glm::dvec3& sceneMax);

} // namespace pnb::player
