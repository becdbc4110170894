#include "pnb_player/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace pnb::player {

ViewMatrices makeViewMatrices(const CameraState& camera, float aspect) {
    ViewMatrices v;
    v.position = camera.position;
    v.znear = camera.znear;
    v.zfar = camera.zfar;
    v.yfov = camera.yfovRadians;
    v.aspect = aspect;
    v.view = glm::mat4(glm::mat3_cast(glm::conjugate(glm::quat(camera.rotation))));
    glm::mat4 p(0.0f);
    if (camera.projection == Projection::Orthographic) {
        // Parallel rays: x = x_view / (ymag aspect), y = y_view / ymag, w = 1. Reversed finite,
        // linear: z_ndc = 1 at -near, 0 at -far.
        v.orthographic = true;
        v.yfov = 0.0f;
        v.ymag = camera.ymag;
        double n = camera.znear, fa = camera.zfar;
        p[0][0] = 1.0f / (camera.ymag * aspect);
        p[1][1] = 1.0f / camera.ymag;
        p[2][2] = float(1.0 / (fa - n));
        p[3][2] = float(fa / (fa - n));
        p[3][3] = 1.0f;
    } else {
        float f = 1.0f / std::tan(camera.yfovRadians * 0.5f);
        p[0][0] = f / aspect;
        p[1][1] = f;
        p[2][3] = -1.0f;
        if (camera.zfar > 0.0f) {
            // Reversed finite: z_ndc = 1 at -near, 0 at -far.
            double n = camera.znear, fa = camera.zfar;
            p[2][2] = float(n / (fa - n));
            p[3][2] = float(fa * n / (fa - n));
        } else {
            // Reversed infinite: z_ndc = near / -z_view.
            p[2][2] = 0.0f;
            p[3][2] = camera.znear;
        }
    }
    v.projection = p;
    v.viewProjection = p * v.view;
    v.inverseViewProjection = glm::inverse(v.viewProjection);
    // Gribb-Hartmann planes from the rows of the clip matrix; depth range [0, 1] reversed.
    const glm::mat4& m = v.viewProjection;
    auto row = [&](int r) { return glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
    v.frustumPlanes = {row(3) + row(0), row(3) - row(0), row(3) + row(1),
                       row(3) - row(1), row(3) - row(2), row(2)};
    for (glm::vec4& plane : v.frustumPlanes) {
        float len = glm::length(glm::vec3(plane));
        if (len > 0) plane /= len;
    }
    return v;
}

double viewDepthFromBuffer(const ViewMatrices& view, double d) {
    if (!(d > 0)) return std::numeric_limits<double>::infinity();
    const double n = view.znear, f = view.zfar;
    if (view.orthographic) return n + (1.0 - d) * (f - n);
    return f > 0 ? n * f / (d * (f - n) + n) : n / d;
}

bool intersectsFrustum(const ViewMatrices& view, const glm::dvec3& boxMin, const glm::dvec3& boxMax) {
    glm::vec3 lo = glm::vec3(boxMin - view.position), hi = glm::vec3(boxMax - view.position);
    for (const glm::vec4& plane : view.frustumPlanes) {
        // The box corner furthest along the plane normal.
        glm::vec3 p(plane.x >= 0 ? hi.x : lo.x, plane.y >= 0 ? hi.y : lo.y,
                    plane.z >= 0 ? hi.z : lo.z);
        if (glm::dot(glm::vec3(plane), p) + plane.w < 0.0f) return false;
    }
    return true;
}

CameraState validOrthographic(CameraState c, const Aabb& bounds) {
    if (c.projection != Projection::Orthographic) return c;
    c.ymag = std::isfinite(c.ymag) && c.ymag != 0.0f ? std::abs(c.ymag) : 1.0f;
    if (!(c.znear >= 0.0f) || !std::isfinite(c.znear)) c.znear = 0.0f;
    if (c.zfar > 0.0f && std::isfinite(c.zfar)) return c;
    glm::dvec3 lo(bounds.min.x, bounds.min.y, bounds.min.z), hi(bounds.max.x, bounds.max.y, bounds.max.z);
    if (bounds.empty()) lo = hi = c.position;
    const glm::dvec3 forward = glm::dquat(c.rotation) * glm::dvec3(0, 0, -1);
    double farthest = 0;
    for (int k = 0; k < 8; ++k) {
        glm::dvec3 p{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        farthest = std::max(farthest, glm::dot(p - c.position, forward));
    }
    const double diagonal = std::max(glm::length(hi - lo), 1e-6 * std::max(1.0, glm::length(c.position)));
    c.zfar = float(std::max(farthest * 1.01, double(c.znear) + diagonal));
    return c;
}

CameraState framingCamera(const Aabb& bounds, float yfovRadians) {
    CameraState c;
    c.yfovRadians = yfovRadians;
    glm::dvec3 lo(bounds.min.x, bounds.min.y, bounds.min.z), hi(bounds.max.x, bounds.max.y, bounds.max.z);
    if (bounds.empty()) lo = hi = glm::dvec3(0.0);
    glm::dvec3 center = (lo + hi) * 0.5;
    // An empty or one-point scene gets a unit radius; any other keeps its own size, whatever
    // its unit of length.
    double radius = glm::length(hi - lo) * 0.5;
    if (!(radius > 0)) radius = 1.0;
    double distance = radius / std::sin(yfovRadians * 0.5);
    glm::dvec3 dir = glm::normalize(glm::dvec3(0.0, 0.5, 1.0));
    c.position = center + dir * distance;
    c.rotation = glm::quatLookAt(-dir, glm::dvec3(0, 1, 0));
    c.znear = float(std::max(distance - radius, radius * 1e-3) * 0.5);
    return c;
}

} // namespace pnb::player
