// Placing a draw item (place_item.h).
#include "load/place_item.h"

#include <limits>

#include <glm/gtc/matrix_inverse.hpp>

#include "lod_select.h" // maxStretch

namespace pnb::player {

void placeBox(const glm::dmat4& m, const Aabb& box, glm::dvec3& outMin, glm::dvec3& outMax) {
    if (box.empty()) { // nothing to bound: a point at the origin of the placement
        outMin = outMax = glm::dvec3(m[3]);
        return;
    }
    outMin = glm::dvec3(std::numeric_limits<double>::max());
    outMax = -outMin;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 p((c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                           (c & 4) ? box.max.z : box.min.z);
        const glm::dvec3 w = glm::dvec3(m * glm::dvec4(p, 1.0));
        outMin = glm::min(outMin, w);
        outMax = glm::max(outMax, w);
    }
}

void placeItem(DrawItem& item, const glm::dmat4& world, const Aabb& local) {
    item.world = world;
    item.normalMatrix = glm::mat3(glm::inverseTranspose(glm::dmat3(world)));
    item.worldScale = maxStretch(glm::dmat3(world));
    item.mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
    placeBox(world, local, item.boundsMin, item.boundsMax);
}

} // namespace pnb::player
