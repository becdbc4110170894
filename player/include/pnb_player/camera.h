// pnb_player/camera.h — the view: a double-precision position, an orientation, and the
// reversed-Z projection with a 32-bit float depth buffer (near maps to 1, far or infinity to 0),
// which keeps depth precision nearly uniform in log space: near/far ratios of 1e-5 and beyond
// still resolve.
//
// Orthographic cameras (glTF "orthographic", CAMR Projection::Orthographic) use the same
// conventions: reversed, depth range [0, 1], near -> 1 and far -> 0, linear in between (w = 1),
// so every pass that tests or clears depth is unchanged. Their view rays are parallel: what
// depends on the distance to the eye (pixel footprint, view vector, LOD) goes through
// ViewMatrices::halfHeightAt / the helpers below rather than through yfov.
//
// Camera-relative: matrices place the camera at the origin. Positions are made relative in
// double before they become float, so a scene 10^6 units from the origin renders as at the origin.
#pragma once

#include <array>
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "pnb/chunks.h"

namespace pnb::player {

struct CameraState {
    glm::dvec3 position{0.0};
    glm::dquat rotation{1, 0, 0, 0}; // camera looks along its local -Z, +Y up (glTF)
    float yfovRadians = 0.8f;
    float znear = 0.1f;
    float zfar = 0.0f; // 0 = infinite (perspective; an orthographic view needs a far plane:
                       // the renderer supplies one past the scene when it is 0)
    Projection projection = Projection::Perspective;
    float ymag = 1.0f; // orthographic half height (world units); the half width is ymag times
                       // the viewport's aspect, as yfov's is for perspective (xmag is not used)
};

struct ViewMatrices {
    glm::dvec3 position{0.0};
    glm::mat4 view{1.0f};          // camera-relative world -> view (rotation only)
    glm::mat4 projection{1.0f};    // reversed-Z, depth range [0, 1] (glClipControl)
    glm::mat4 viewProjection{1.0f};
    glm::mat4 inverseViewProjection{1.0f};
    std::array<glm::vec4, 6> frustumPlanes{}; // camera-relative, inside: dot(p, (x,y,z,1)) >= 0
    float znear = 0.1f, zfar = 0.0f;
    float yfov = 0.8f, aspect = 1.0f; // vertical field of view (radians; 0 if orthographic), width / height
    bool orthographic = false;
    float ymag = 0.0f; // orthographic half height (0 if perspective)

    // Half the height the view spans at view depth `depth` (along the forward axis):
    // depth tan(yfov / 2) for perspective, ymag for orthographic. A pixel there is
    // 2 halfHeightAt(depth) / viewport height wide.
    double halfHeightAt(double depth) const {
        return orthographic ? double(ymag) : depth * std::tan(0.5 * double(yfov));
    }
    // The camera's forward axis (its -Z) in camera-relative world space.
    glm::dvec3 forward() const { return -glm::dvec3(view[0][2], view[1][2], view[2][2]); }
};

// Orthographic: near -> 1, far -> 0 linearly; a far plane at or before the near one, or a zero,
// negative or non-finite ymag, is the caller's to avoid (the renderer validates).
ViewMatrices makeViewMatrices(const CameraState& camera, float aspect);

// View depth (distance along the forward axis) of a reversed-Z depth-buffer value; +infinity for
// 0 or less (the clear value: nothing drawn).
double viewDepthFromBuffer(const ViewMatrices& view, double depth);

// Camera-relative AABB test against the frustum (conservative: may keep boxes just outside).
bool intersectsFrustum(const ViewMatrices& view, const glm::dvec3& boxMin, const glm::dvec3& boxMax);

// An orthographic camera made drawable: ymag as its magnitude (1 if zero or not finite) and, where
// it has no far plane (0: glTF requires one, other sources may lack it), one just beyond the far
// side of `bounds` (at least the near plane plus the scene's diagonal). Perspective: unchanged.
CameraState validOrthographic(CameraState camera, const Aabb& bounds);

// A camera that sees all of `bounds` from the +Z/+Y diagonal (when the container has none).
CameraState framingCamera(const Aabb& bounds, float yfovRadians);

} // namespace pnb::player
