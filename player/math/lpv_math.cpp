// LPV numbers: SH basis, cosine lobe, face solid angles and cascade placement (see lpv_math.h).
#include "lpv_math.h"

#include <algorithm>
#include <cmath>

namespace pnb::player {

Sh4 shBasis(const glm::dvec3& w) { return {kShY0, -kShY1 * w.y, kShY1 * w.z, -kShY1 * w.x}; }

Sh4 cosineLobe(const glm::dvec3& n) { return {kLobeC0, -kLobeC1 * n.y, kLobeC1 * n.z, -kLobeC1 * n.x}; }

double shEvaluate(const Sh4& a, const glm::dvec3& w) {
    Sh4 y = shBasis(w);
    return a[0] * y[0] + a[1] * y[1] + a[2] * y[2] + a[3] * y[3];
}

double rectangleSolidAngle(double x0, double x1, double y0, double y1, double d) {
    auto corner = [d](double x, double y) { return std::atan(x * y / (d * std::sqrt(x * x + y * y + d * d))); };
    return corner(x1, y1) - corner(x0, y1) - corner(x1, y0) + corner(x0, y0);
}

bool LpvCascade::contains(const glm::dvec3& p) const {
    glm::dvec3 hi = max();
    return p.x >= origin.x && p.y >= origin.y && p.z >= origin.z && p.x < hi.x && p.y < hi.y && p.z < hi.z;
}

std::vector<LpvCascade> placeCascades(uint32_t count, uint32_t cells, double cellSize,
                                      const glm::dvec3& sceneMin, const glm::dvec3& sceneMax,
                                      const glm::dvec3& camera, const glm::dvec3& forward) {
    std::vector<LpvCascade> out;
    if (count == 0 || cells == 0) return out;
    glm::dvec3 extent = sceneMax - sceneMin;
    double largest = std::max({extent.x, extent.y, extent.z});
    bool sceneOk = std::isfinite(largest) && largest > 0;
    auto following = [&](double cell) {
        LpvCascade c;
        c.cellSize = cell;
        c.cells = cells;
        double size = cell * double(cells);
        glm::dvec3 centre = camera + forward * (0.25 * size);
        c.origin = glm::floor((centre - 0.5 * size) / cell) * cell;
        return c;
    };
    if (cellSize > 0) {
        if (!std::isfinite(cellSize)) return out;
        for (uint32_t k = 0; k < count; ++k) out.push_back(following(std::ldexp(cellSize, int(k))));
        return out;
    }
    if (!sceneOk) return out;
    // The outer cascade holds the scene's bounding cube with a cell to spare on each side, so
    // that the half-cell shifts of injection and look-up never leave it (with half a cell, a
    // surface on the scene's boundary facing out lands exactly on the grid's edge, in or out by
    // rounding).
    LpvCascade outer;
    outer.cells = cells;
    outer.cellSize = largest / (cells > 2 ? double(cells) - 2.0 : 1.0);
    outer.origin = 0.5 * (sceneMin + sceneMax) - 0.5 * outer.cellSize * double(cells);
    for (uint32_t k = 0; k + 1 < count; ++k)
        out.push_back(following(std::ldexp(outer.cellSize, -int(count - 1 - k))));
    out.push_back(outer);
    return out;
}

double probeCellSize(uint32_t cells, double maxSpacing, const glm::dvec3& sceneMin, const glm::dvec3& sceneMax) {
    const glm::dvec3 extent = sceneMax - sceneMin;
    const double largest = std::max({extent.x, extent.y, extent.z});
    const double cube = largest / (cells > 2 ? double(cells) - 2.0 : 1.0); // placeCascades' outer cell
    return maxSpacing > 0 && std::isfinite(maxSpacing) && cube > maxSpacing ? maxSpacing : 0.0;
}

} // namespace pnb::player
