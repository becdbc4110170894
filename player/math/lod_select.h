// player/math/lod_select.h — level-of-detail selection by projected screen-space error (pure
// CPU, no GL).
//
// A draw item has levels 0 (full detail) .. n-1, each with the converter's simplification error
// against full detail (Submesh::lodError, mesh units; docs/FORMAT.md). The error of a level as
// seen is that error times the node's largest world stretch, projected at the item's distance:
//
//     errorPx = error * worldScale * pixelScale / distance,
//     pixelScale = viewportHeight / (2 tan(yfov / 2))        (pixels per unit at distance 1)
//
// with `distance` the nearest point of the item's world bounds to the eye (conservative: no point
// of the item is nearer, so no point's error is larger than errorPx at the view's centre).
// Selection takes the coarsest level whose errorPx is <= the threshold; with hysteresis h a
// *coarser* level than the current one is taken only once its errorPx is <= threshold * (1 - h),
// while a level whose errorPx is over the threshold is left at once. So a camera parked at a
// switching distance does not flip levels frame to frame: in distance, the band between
// switching to and back from a level is a factor 1 / (1 - h).
//
// Every function is total: zero, negative, infinite or NaN inputs give a level in range (full
// detail whenever the projected error cannot be bounded), never NaN.
//
// Orthographic views: a segment's size on screen does not depend on its distance, so the rule
// holds with pixelScale = viewportHeight / (2 ymag) (lodPixelScaleOrthographic) and distance 1
// for every item (lodDistance).
//
// Does NOT do: the off-axis growth of a pixel's angle (up to 1 / cos^2 of the angle to the view axis: x1.7 at the
// corners of a 60 degree 16:9 view; the threshold absorbs it, docs/PLAYER.md).
#pragma once

#include <cstdint>
#include <span>

#include <glm/glm.hpp>

namespace pnb::player {

// viewportHeight / (2 tan(yfov / 2)): pixels a unit-long segment facing the eye covers at unit
// distance. yfov <= 0 or not finite gives +infinity (nothing can be bounded: selection keeps full
// detail); yfov >= pi or a zero height gives 0 (everything is below a pixel).
double lodPixelScale(double yfovRadians, uint32_t viewportHeight);

// viewportHeight / (2 ymag): pixels a unit-long segment facing the view covers at any distance
// from an orthographic camera of half height ymag. ymag <= 0 or not finite gives +infinity.
double lodPixelScaleOrthographic(double ymag, uint32_t viewportHeight);

// The `distance` the rule divides by: distanceToBox for a perspective view, 1 for an orthographic
// one (its pixelScale is already pixels per unit at any distance).
double lodDistance(bool orthographic, const glm::dvec3& eye, const glm::dvec3& lo, const glm::dvec3& hi);

// Distance from `eye` to the nearest point of the box [lo, hi]; 0 inside. NaN inputs give 0.
double distanceToBox(const glm::dvec3& eye, const glm::dvec3& lo, const glm::dvec3& hi);

// Largest factor by which `m` stretches any vector (its largest singular value): the world
// scale of a node with non-uniform scale, rotation and shear. Non-finite entries give +infinity.
double maxStretch(const glm::dmat3& m);

struct LodRule {
    float thresholdPx = 1.0f; // lod.threshold_px: largest projected error accepted, pixels
    float hysteresis = 0.2f;  // lod.hysteresis: h in [0, 1); coarser only below threshold (1 - h)
};

// The level to draw this frame. `errors` per level, mesh units, level 0 first; they are made
// nondecreasing here (a level counts as at least as wrong as any finer one). `current` is the
// level drawn last frame (clamped to the levels there are). Returns a level < errors.size()
// (0 for an empty span). A level with error 0 is always acceptable (it is exact).
uint32_t selectLod(std::span<const float> errors, double worldScale, double distance,
                   double pixelScale, const LodRule& rule, uint32_t current);

// lod.force (>= 0: that level, clamped to what exists; -1: `selected`) and lod.bias (levels
// added to `selected`: + coarser, - finer), clamped to [0, levelCount - 1]. Force wins over bias.
uint32_t applyLodOverrides(uint32_t selected, uint32_t levelCount, int bias, int force);

} // namespace pnb::player
