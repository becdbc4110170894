// player/math/shadow_fit.h — light matrices of directional-light shadow maps (pure CPU, no GL).
//
// Every fit works in camera-relative world space (world minus the camera position, double), the
// space the renderer draws in, and returns a matrix from that space to shadow clip space:
// x, y in [-1, 1] across the map, z in [0, 1] with 0 nearest the light (divide by w: LiSPSM is a
// perspective map, the others have w = 1).
//
// Casters outside the view still shadow visible receivers: every fit pulls its near plane (the
// side facing the light) out to the scene bounds ("pancaking" by extent, seed 000's canyon case),
// so nothing between the light and a receiver is clipped.
//
// Based on: seed 000 (PSSM/SDSM fitting, extrusion toward the light), seed 002 (LiSPSM after
// Wimmer, Scherzer, Purgathofer 2004: n_opt and the uniform fallback), the stable cascades of
// Valient ("Stable rendering of cascaded shadow maps", ShaderX6): bounding-sphere extents and a
// light-space origin snapped to whole texels.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace pnb::player {

// The camera for fitting: orientation and lens, at the origin of camera-relative space. The view
// spans half heights h(d) = halfHeight + d tanHalfFovY at view depth d: a perspective camera has
// halfHeight = 0, an orthographic one tanHalfFovY = 0 and halfHeight = ymag (a box, not a frustum).
struct FitCamera {
    glm::dvec3 forward{0, 0, -1}, right{1, 0, 0}, up{0, 1, 0}; // orthonormal
    double tanHalfFovY = 0.4, aspect = 1.0;
    double halfHeight = 0.0; // orthographic ymag (0: perspective)
    glm::dvec3 position{0.0}; // absolute world position (texel snapping is done in world space)
};

struct FitBox {
    glm::dvec3 min{0.0}, max{0.0}; // camera-relative world AABB
};

enum class FitMode { Sphere, Tight };

struct ShadowFit {
    glm::dmat4 matrix{1.0};   // camera-relative world -> shadow clip
    double texelWorld = 0;    // world size of one texel (ortho); at the near end for LiSPSM
    double depthRange = 0;    // world distance along the light covered by z in [0, 1] (ortho)
    bool warped = false;      // LiSPSM applied a perspective warp (false: fell back to uniform)
};

// World -> light rotation: rows are the light-space x, y and z axes; +z points toward the light
// (opposite `lightTravel`). Depends on the light direction only, so cascades do not swim when the
// camera turns. Any unit direction works, straight down included.
glm::dmat3 lightRotation(const glm::dvec3& lightTravel);

// The 8 corners of the view slice between view depths `sliceNear` and `sliceFar`.
void sliceCorners(const FitCamera& camera, double sliceNear, double sliceFar, glm::dvec3 out[8]);

// The vertices of the view slice [sliceNear, sliceFar] intersected with `box` (empty if they do
// not meet): where receivers of that slice can be.
std::vector<glm::dvec3> clipSliceToBox(const FitCamera& camera, double sliceNear, double sliceFar,
                                       const FitBox& box);

// One cascade covering the view slice [sliceNear, sliceFar].
//   Sphere: the slice's bounding sphere sets the extent (invariant under camera rotation) and the
//           light-space origin is snapped to whole texels of `resolution` (invariant under
//           translation up to whole-texel steps): no shimmering, at the cost of resolution.
//   Tight:  the light-space bounding rectangle of the slice clipped to the scene: more
//           resolution, but it swims as the camera moves.
ShadowFit fitCascade(const FitCamera& camera, double sliceNear, double sliceFar,
                     const glm::dmat3& light, const FitBox& scene, uint32_t resolution, FitMode mode);

// An orthographic map around a light-space rectangle [lo, hi] (x, y), the depth taken from
// `scene` toward the light and from `receiversLow` away from it. Used by fitCascade and by GPU
// (SDSM) fits that found the rectangle from samples.
ShadowFit fitLightRectangle(const glm::dmat3& light, glm::dvec2 lo, glm::dvec2 hi, double receiversLow,
                            const FitBox& scene, uint32_t resolution);

// The baseline: one orthographic map over the whole scene, independent of the camera.
ShadowFit fitScene(const glm::dmat3& light, const FitBox& scene, uint32_t resolution);

// LiSPSM over the view slice [viewNear, viewFar] (one map). Its warp redistributes texels for a
// perspective viewer (nearer = larger on screen); an orthographic camera (halfHeight > 0) has no
// such falloff, so it gets the uniform fit (fitCascade, Tight) with warped = false. The warp's near distance is
// n_opt = (z_n + sqrt(z_n z_f)) / sin(gamma) (Wimmer et al.); as the view direction approaches
// the light direction (sin(gamma) -> 0) n_opt grows without bound and the map degrades smoothly
// to the uniform fit, which is used outright once the warp would be negligible.
ShadowFit fitLispsm(const FitCamera& camera, double viewNear, double viewFar,
                    const glm::dvec3& lightTravel, const FitBox& scene, uint32_t resolution);

// Shadow-space position (after the divide) of a camera-relative point: x, y in [-1, 1], z in [0, 1].
glm::dvec3 toShadow(const ShadowFit& fit, const glm::dvec3& p);

} // namespace pnb::player
