// converter/src/mesh_bounds.cpp — axis-aligned boxes and bounding spheres of mesh vertices.
//
// The sphere is the smaller of two cheap candidates: Ritter's (start from two far-apart points,
// grow to take in each outlier; tight for elongated meshes) and the box-centred one (tight for
// symmetric, box-like meshes, where Ritter can be up to ~5% larger). Neither is the minimal
// sphere; both are exact containers. Everything is computed in double and the float radius is
// rounded *up* from the float centre's true farthest distance, plus 1e-6 relative slack, so a
// player testing |p - c| <= r in float never culls a vertex on the boundary.
//
// Based on: Ritter, "An Efficient Bounding Sphere", Graphics Gems (1990).

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh_internal.h"

namespace pnb::converter::mesh_detail {

namespace {

void expand(Aabb& box, const float* p) {
    if (box.min.x > box.max.x) { // empty
        box.min = box.max = {p[0], p[1], p[2]};
        return;
    }
    // Positions are finite here (step 2 of the pipeline), so std::min/max (no NaN handling,
    // unlike fmin/fmax, which are libm calls) are exact.
    box.min = {std::min(box.min.x, p[0]), std::min(box.min.y, p[1]), std::min(box.min.z, p[2])};
    box.max = {std::max(box.max.x, p[0]), std::max(box.max.y, p[1]), std::max(box.max.z, p[2])};
}

double distance(const double c[3], const float* p) {
    double d0 = p[0] - c[0], d1 = p[1] - c[1], d2 = p[2] - c[2];
    return std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

size_t farthestFrom(std::span<const float> positions, const double c[3]) {
    size_t best = 0;
    double bestDistance = -1;
    for (size_t i = 0; i * 3 < positions.size(); ++i) {
        double d = distance(c, &positions[i * 3]);
        if (d > bestDistance) bestDistance = d, best = i;
    }
    return best;
}

// Radius from centre c to the farthest vertex.
double maxDistance(std::span<const float> positions, const double c[3]) {
    double r = 0;
    for (size_t i = 0; i * 3 < positions.size(); ++i)
        r = std::fmax(r, distance(c, &positions[i * 3]));
    return r;
}

} // namespace

Aabb boundsOfIndexed(std::span<const float> positions, std::span<const uint32_t> indices) {
    Aabb box;
    for (uint32_t i : indices)
        expand(box, &positions[size_t(i) * 3]);
    return box;
}

Aabb boundsOfAll(std::span<const float> positions) {
    Aabb box;
    for (size_t i = 0; i * 3 < positions.size(); ++i)
        expand(box, &positions[i * 3]);
    return box;
}

Sphere boundingSphere(std::span<const float> positions, const Aabb& box) {
    Sphere result;
    if (positions.empty()) return result;

    // Ritter: the two ends of an approximate diameter, then grow.
    const double first[3] = {positions[0], positions[1], positions[2]};
    const float* y = &positions[farthestFrom(positions, first) * 3];
    const double yd[3] = {y[0], y[1], y[2]};
    const float* z = &positions[farthestFrom(positions, yd) * 3];
    double ritter[3] = {(yd[0] + z[0]) / 2, (yd[1] + z[1]) / 2, (yd[2] + z[2]) / 2};
    double ritterRadius = distance(ritter, z);
    for (size_t i = 0; i * 3 < positions.size(); ++i) {
        const float* p = &positions[i * 3];
        double d = distance(ritter, p);
        if (d <= ritterRadius) continue;
        double grown = (ritterRadius + d) / 2;
        double move = (grown - ritterRadius) / d;
        for (int k = 0; k < 3; ++k)
            ritter[k] += (p[k] - ritter[k]) * move;
        ritterRadius = grown;
    }

    const double boxCenter[3] = {(double(box.min.x) + box.max.x) / 2,
                                 (double(box.min.y) + box.max.y) / 2,
                                 (double(box.min.z) + box.max.z) / 2};
    const double* center = maxDistance(positions, boxCenter) <= ritterRadius ? boxCenter : ritter;

    // Re-measure from the centre as stored (float), then round the radius up.
    result.center = {float(center[0]), float(center[1]), float(center[2])};
    const double stored[3] = {result.center.x, result.center.y, result.center.z};
    double radius = maxDistance(positions, stored);
    float r = float(radius * (1.0 + 1e-6));
    while (double(r) < radius)
        r = std::nextafter(r, std::numeric_limits<float>::infinity());
    result.radius = r;
    return result;
}

} // namespace pnb::converter::mesh_detail
