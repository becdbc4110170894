#include "shadow_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace pnb::player {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Rotation whose rows are x, y, z.
glm::dmat3 rows(const glm::dvec3& x, const glm::dvec3& y, const glm::dvec3& z) {
    return glm::transpose(glm::dmat3(x, y, z));
}

void sceneCorners(const FitBox& box, glm::dvec3 out[8]) {
    for (int c = 0; c < 8; ++c)
        out[c] = {(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                  (c & 4) ? box.max.z : box.min.z};
}

// Light-space depth interval of the scene: [lowest, highest] z (highest = nearest the light).
glm::dvec2 sceneDepthInterval(const glm::dmat3& light, const FitBox& scene) {
    glm::dvec3 corners[8];
    sceneCorners(scene, corners);
    glm::dvec2 z{kInf, -kInf};
    for (const glm::dvec3& c : corners) {
        double d = (light * c).z;
        z = {std::min(z.x, d), std::max(z.y, d)};
    }
    return z;
}

// Is `p` inside the view slice [a, b] (with a relative tolerance)?
bool insideSlice(const FitCamera& cam, double a, double b, const glm::dvec3& p) {
    double d = glm::dot(p, cam.forward);
    double eps = 1e-9 * b; // relative: the same verdict in any unit of length
    if (d < a - eps || d > b + eps) return false;
    double h = cam.halfHeight + d * cam.tanHalfFovY + eps, w = h * cam.aspect + eps;
    return std::abs(glm::dot(p, cam.up)) <= h && std::abs(glm::dot(p, cam.right)) <= w;
}

bool insideBox(const FitBox& box, const glm::dvec3& p) {
    // Relative to the box (a flat box gets its diagonal's tolerance on its flat axis).
    glm::dvec3 eps = 1e-9 * glm::max(glm::abs(box.max - box.min), glm::dvec3(glm::length(box.max - box.min)));
    return glm::all(glm::greaterThanEqual(p, box.min - eps)) && glm::all(glm::lessThanEqual(p, box.max + eps));
}

// Edges of a box-like solid given by 8 corners indexed by bits (x = 1, y = 2, z = 4).
constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                               {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

} // namespace

std::vector<glm::dvec3> clipSliceToBox(const FitCamera& camera, double sliceNear, double sliceFar,
                                       const FitBox& box) {
    // The vertices of the intersection of two convex solids: each one's corners inside the other,
    // and each one's edges crossing the other's faces.
    glm::dvec3 slice[8], corners[8];
    sliceCorners(camera, sliceNear, sliceFar, slice);
    sceneCorners(box, corners);
    std::vector<glm::dvec3> out;
    for (const glm::dvec3& p : slice)
        if (insideBox(box, p)) out.push_back(p);
    for (const glm::dvec3& p : corners)
        if (insideSlice(camera, sliceNear, sliceFar, p)) out.push_back(p);
    // Slice edges against the box's six planes.
    for (const auto& e : kEdges) {
        glm::dvec3 p0 = slice[e[0]], p1 = slice[e[1]];
        for (int axis = 0; axis < 3; ++axis) {
            for (double plane : {box.min[axis], box.max[axis]}) {
                double d0 = p0[axis] - plane, d1 = p1[axis] - plane;
                if ((d0 < 0) == (d1 < 0) || d0 == d1) continue;
                glm::dvec3 q = p0 + (p1 - p0) * (d0 / (d0 - d1));
                if (insideBox(box, q)) out.push_back(q);
            }
        }
    }
    // Box edges against the slice's six planes (near, far, and four sides: through the eye for
    // perspective, parallel to the view axis for orthographic).
    const double h0 = camera.halfHeight, w0 = camera.halfHeight * camera.aspect;
    struct Plane {
        glm::dvec3 n;
        double d;
    } planes[6] = {{camera.forward, -sliceNear}, {-camera.forward, sliceFar},
                   {camera.forward * camera.tanHalfFovY - camera.up, h0},
                   {camera.forward * camera.tanHalfFovY + camera.up, h0},
                   {camera.forward * camera.tanHalfFovY * camera.aspect - camera.right, w0},
                   {camera.forward * camera.tanHalfFovY * camera.aspect + camera.right, w0}};
    for (const auto& e : kEdges) {
        glm::dvec3 p0 = corners[e[0]], p1 = corners[e[1]];
        for (const Plane& pl : planes) {
            double d0 = glm::dot(pl.n, p0) + pl.d, d1 = glm::dot(pl.n, p1) + pl.d;
            if ((d0 < 0) == (d1 < 0) || d0 == d1) continue;
            glm::dvec3 q = p0 + (p1 - p0) * (d0 / (d0 - d1));
            if (insideSlice(camera, sliceNear, sliceFar, q)) out.push_back(q);
        }
    }
    return out;
}

glm::dmat3 lightRotation(const glm::dvec3& lightTravel) {
    glm::dvec3 z = -glm::normalize(lightTravel);
    // Any helper not parallel to z gives a valid basis; switching helpers only near the poles
    // keeps the basis a function of the light direction alone.
    glm::dvec3 helper = std::abs(z.y) < 0.99 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    glm::dvec3 x = glm::normalize(glm::cross(helper, z));
    return rows(x, glm::cross(z, x), z);
}

void sliceCorners(const FitCamera& camera, double sliceNear, double sliceFar, glm::dvec3 out[8]) {
    for (int c = 0; c < 8; ++c) {
        double d = (c & 4) ? sliceFar : sliceNear;
        double h = camera.halfHeight + d * camera.tanHalfFovY, w = h * camera.aspect;
        out[c] = camera.forward * d + camera.right * ((c & 1) ? w : -w) + camera.up * ((c & 2) ? h : -h);
    }
}

ShadowFit fitLightRectangle(const glm::dmat3& light, glm::dvec2 lo, glm::dvec2 hi,
                            double receiversLow, const FitBox& scene, uint32_t resolution) {
    glm::dvec2 sceneZ = sceneDepthInterval(light, scene);
    // Toward the light the map reaches the top of the scene: every caster above a receiver is in.
    // Away from it, receivers beyond the scene need no depth.
    // Floors relative to the scene's size (a rectangle around one point, receivers only at the
    // scene's top), so that the fit is the same in any unit of length.
    const double floor = 1e-9 * std::max(glm::length(scene.max - scene.min), glm::length(hi - lo));
    glm::dvec2 extent = glm::max(hi - lo, glm::dvec2(floor > 0 ? floor : 1e-300));
    double zHigh = sceneZ.y, zLow = std::max(receiversLow, sceneZ.x);
    if (!(zHigh > zLow)) zLow = zHigh - std::max(extent.x, extent.y);
    double margin = (zHigh - zLow) * 1e-3;
    zHigh += margin;
    zLow -= margin;
    glm::dvec2 centre = (lo + hi) * 0.5;
    glm::dvec2 scale = 2.0 / extent;
    double depthScale = 1.0 / (zHigh - zLow);

    glm::dmat4 m(0.0); // column-major: m[col][row]
    glm::dvec3 axisX = glm::transpose(light)[0], axisY = glm::transpose(light)[1],
               axisZ = glm::transpose(light)[2];
    for (int col = 0; col < 3; ++col) {
        m[col][0] = scale.x * axisX[col];
        m[col][1] = scale.y * axisY[col];
        m[col][2] = -depthScale * axisZ[col];
    }
    m[3] = {-scale.x * centre.x, -scale.y * centre.y, zHigh * depthScale, 1.0};
    ShadowFit fit;
    fit.matrix = m;
    fit.texelWorld = std::max(extent.x, extent.y) / double(resolution);
    fit.depthRange = zHigh - zLow;
    return fit;
}

namespace {

// The orthographic map around the light-space bounds of `points` (receivers).
ShadowFit fitLightBox(const glm::dmat3& light, const glm::dvec3* points, size_t count, const FitBox& scene,
                      uint32_t resolution) {
    glm::dvec3 lo(kInf), hi(-kInf);
    for (size_t i = 0; i < count; ++i) {
        glm::dvec3 l = light * points[i];
        lo = glm::min(lo, l);
        hi = glm::max(hi, l);
    }
    return fitLightRectangle(light, glm::dvec2(lo), glm::dvec2(hi), lo.z, scene, resolution);
}

} // namespace

ShadowFit fitCascade(const FitCamera& camera, double sliceNear, double sliceFar,
                     const glm::dmat3& light, const FitBox& scene, uint32_t resolution, FitMode mode) {
    if (mode == FitMode::Tight) {
        // The slice clipped to the scene: the part of it that can hold receivers.
        std::vector<glm::dvec3> corners = clipSliceToBox(camera, sliceNear, sliceFar, scene);
        if (corners.empty()) {
            corners.resize(8);
            sliceCorners(camera, sliceNear, sliceFar, corners.data());
        }
        return fitLightBox(light, corners.data(), corners.size(), scene, resolution);
    }
    // Bounding sphere of the slice: centre on the view axis equidistant from a near and a far
    // corner (k = tangent of the half-diagonal angle), or the far cap's centre if that is nearer.
    // Orthographic: the box's centre and half diagonal.
    double k2 = camera.tanHalfFovY * camera.tanHalfFovY * (1.0 + camera.aspect * camera.aspect);
    double a = sliceNear, b = sliceFar;
    double t = 0.5 * (a + b) * (1.0 + k2), radius;
    if (camera.halfHeight > 0) {
        t = 0.5 * (a + b);
        radius = std::sqrt(0.25 * (b - a) * (b - a) +
                           camera.halfHeight * camera.halfHeight * (1.0 + camera.aspect * camera.aspect));
    } else if (t >= b) {
        t = b;
        radius = b * std::sqrt(k2);
    } else {
        radius = std::sqrt((t - a) * (t - a) + a * a * k2);
    }
    double texel = 2.0 * radius / double(resolution);
    // Snap the centre in absolute light space, where the grid does not move with the camera.
    glm::dvec3 cameraLight = light * camera.position;
    glm::dvec3 centre = light * (camera.forward * t);
    glm::dvec2 absolute = glm::dvec2(centre + cameraLight);
    glm::dvec2 snapped = glm::floor(absolute / texel + 0.5) * texel - glm::dvec2(cameraLight);
    ShadowFit fit = fitLightRectangle(light, snapped - radius, snapped + radius, centre.z - radius,
                                      scene, resolution);
    fit.texelWorld = texel;
    return fit;
}

ShadowFit fitScene(const glm::dmat3& light, const FitBox& scene, uint32_t resolution) {
    glm::dvec3 corners[8];
    sceneCorners(scene, corners);
    return fitLightBox(light, corners, 8, scene, resolution);
}

ShadowFit fitLispsm(const FitCamera& camera, double viewNear, double viewFar,
                    const glm::dvec3& lightTravel, const FitBox& scene, uint32_t resolution) {
    if (camera.halfHeight > 0) // orthographic viewer: nothing to warp for
        return fitCascade(camera, viewNear, viewFar, lightRotation(lightTravel), scene, resolution, FitMode::Tight);
    glm::dvec3 l = glm::normalize(lightTravel);
    glm::dvec3 v = camera.forward;
    double cosGamma = glm::dot(v, l);
    double sinGamma = std::sqrt(std::max(0.0, 1.0 - cosGamma * cosGamma));
    // Light space with y along the view direction projected onto the shadow-map plane.
    glm::dvec3 zAxis = -l;
    glm::dvec3 yAxis = v - l * cosGamma;
    if (glm::length(yAxis) < 1e-9) return fitCascade(camera, viewNear, viewFar, lightRotation(l), scene, resolution, FitMode::Tight);
    yAxis = glm::normalize(yAxis);
    glm::dvec3 xAxis = glm::cross(yAxis, zAxis);
    glm::dmat3 light = rows(xAxis, yAxis, zAxis);

    // Body B: the view slice clipped to the scene (receivers can only be there), extruded toward
    // the light up to the scene's top (casters).
    glm::dvec2 sceneZ = sceneDepthInterval(light, scene);
    std::vector<glm::dvec3> receivers = clipSliceToBox(camera, viewNear, viewFar, scene);
    if (receivers.empty()) {
        glm::dvec3 corners[8];
        sliceCorners(camera, viewNear, viewFar, corners);
        receivers.assign(corners, corners + 8);
    }
    std::vector<glm::dvec3> body;
    glm::dvec3 lo(kInf), hi(-kInf);
    double nearest = kInf; // the body's nearest view depth: LiSPSM's z_n
    for (const glm::dvec3& r : receivers) {
        glm::dvec3 q = light * r;
        body.push_back(q);
        body.push_back({q.x, q.y, std::max(q.z, sceneZ.y)});
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
        nearest = std::min(nearest, glm::dot(r, v));
    }
    double d = hi.y - lo.y;
    double zn = std::max(nearest, viewNear) / std::max(sinGamma, 1e-12);
    double zf = zn + d * sinGamma;
    double n = (zn + std::sqrt(zf * zn)) / std::max(sinGamma, 1e-12);
    // The warp's strength is d / n; below 1e-4 it changes no texel, so use the uniform map and
    // never divide by a vanishing sin(gamma).
    if (!(d > 0) || !(n < d * 1e4) || !std::isfinite(n)) {
        ShadowFit fit = fitCascade(camera, viewNear, viewFar, light, scene, resolution, FitMode::Tight);
        return fit;
    }
    double f = n + d;
    double y0 = lo.y - n; // projection centre: B spans y' = y - y0 in [n, f]
    double a = (f + n) / (f - n), b = -2.0 * f * n / (f - n);
    glm::dvec3 wlo(kInf), whi(-kInf);
    for (const glm::dvec3& p : body) {
        double yp = p.y - y0;
        glm::dvec3 w{p.x / yp, a + b / yp, p.z / yp};
        wlo = glm::min(wlo, w);
        whi = glm::max(whi, w);
    }
    double sx = 2.0 / std::max(whi.x - wlo.x, 1e-12), cx = 0.5 * (whi.x + wlo.x);
    double sy = 2.0 / std::max(whi.y - wlo.y, 1e-12), cy = 0.5 * (whi.y + wlo.y);
    double dz = std::max(whi.z - wlo.z, 1e-12);
    double zTop = whi.z + dz * 1e-3, zRange = dz * 1.002;
    // Rows of the matrix acting on the light-space point (x, y, z, 1):
    //   w = y - y0; x' = sx (x - cx w); y' = sy ((a - cy) w + b); z' = (zTop w - z) / zRange.
    glm::dvec4 rowW{0, 1, 0, -y0};
    glm::dvec4 rowX = sx * (glm::dvec4(1, 0, 0, 0) - cx * rowW);
    glm::dvec4 rowY = sy * ((a - cy) * rowW + glm::dvec4(0, 0, 0, b));
    glm::dvec4 rowZ = (zTop * rowW - glm::dvec4(0, 0, 1, 0)) / zRange;
    glm::dmat4 lightSpace(glm::dvec4(xAxis.x, yAxis.x, zAxis.x, 0), glm::dvec4(xAxis.y, yAxis.y, zAxis.y, 0),
                          glm::dvec4(xAxis.z, yAxis.z, zAxis.z, 0), glm::dvec4(0, 0, 0, 1));
    glm::dmat4 warp = glm::transpose(glm::dmat4(rowX, rowY, rowZ, rowW));
    ShadowFit fit;
    fit.matrix = warp * lightSpace;
    fit.texelWorld = 2.0 * n / (sx * double(resolution));
    fit.depthRange = 0; // not linear in depth
    fit.warped = true;
    return fit;
}

glm::dvec3 toShadow(const ShadowFit& fit, const glm::dvec3& p) {
    glm::dvec4 c = fit.matrix * glm::dvec4(p, 1.0);
    return glm::dvec3(c) / c.w;
}

} // namespace pnb::player
