// pnb_player/camera.h — the view: a double-precision position, an orientation, and the
// reversed-Z projection with a 32-bit float depth buffer (near maps to 1, far or infinity to 0),
// which keeps depth precision nearly uniform in log space: near/far ratios of 1e-5 and beyond
// still resolve.
//
// Camera-relative: matrices place the camera at the origin. Positions are made relative in
// double before they become float, so a scene 10^6 units from the origin renders as at the origin.
#pragma once

#include <array>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "pnb/chunks.h"

namespace pnb::player {

struct CameraState {
    glm::dvec3 position{0.0};
    glm::dquat rotation{1, 0, 0, 0}; // camera looks along its local -Z, +Y up (glTF)
    float yfovRadians = 0.8f;
    float znear = 0.1f;
    float zfar = 0.0f; // 0 = infinite
};

struct ViewMatrices {
    glm::dvec3 position{0.0};
    glm::mat4 view{1.0f};          // camera-relative world -> view (rotation only)
    glm::mat4 projection{1.0f};    // reversed-Z, depth range [0, 1] (glClipControl)
    glm::mat4 viewProjection{1.0f};
    glm::mat4 inverseViewProjection{1.0f};
    std::array<glm::vec4, 6> frustumPlanes{}; // camera-relative, inside: dot(p, (x,y,z,1)) >= 0
    float znear = 0.1f, zfar = 0.0f;
    float yfov = 0.8f, aspect = 1.0f; // vertical field of view (radians), width / height
};

ViewMatrices makeViewMatrices(const CameraState& camera, float aspect);

// Camera-relative AABB test against the frustum (conservative: may keep boxes just outside).
bool intersectsFrustum(const ViewMatrices& view, const glm::dvec3& boxMin, const glm::dvec3& boxMax);

// A camera that sees all of `bounds` from the +Z/+Y diagonal (when the container has none).
CameraState framingCamera(const Aabb& bounds, float yfovRadians);

} // namespace pnb::player
