// Local-light shadow atlas math (local_shadows.h): tile sizes, packing, tile matrices.
#include <algorithm>
#include <bit>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "shadows/local_shadows.h"

namespace pnb::player {

namespace {

// The (x, y) of Morton index m: even bits to x, odd bits to y.
glm::uvec2 mortonDecode(uint64_t m) {
    glm::uvec2 p(0u);
    for (uint32_t bit = 0; bit < 32; ++bit) {
        p.x |= uint32_t((m >> (2 * bit)) & 1u) << bit;
        p.y |= uint32_t((m >> (2 * bit + 1)) & 1u) << bit;
    }
    return p;
}

// Places `sizes` (powers of two, non-increasing, each a multiple of `unit`) in Morton order over
// an atlas of `atlas` texels: a square of side s starts at the next multiple of (s/unit)² cells,
// which is where the previous, larger-or-equal squares end, so nothing overlaps and no gap opens.
// Returns how many of the squares fit.
size_t packMorton(const std::vector<uint32_t>& sizes, uint32_t atlas, uint32_t unit, std::vector<glm::uvec2>& at) {
    const uint64_t cells = uint64_t(atlas / unit) * (atlas / unit);
    uint64_t cursor = 0;
    at.clear();
    for (uint32_t s : sizes) {
        const uint64_t span = uint64_t(s / unit) * (s / unit);
        cursor = (cursor + span - 1) / span * span;
        if (cursor + span > cells) break;
        at.push_back(mortonDecode(cursor) * unit);
        cursor += span;
    }
    return at.size();
}

} // namespace

uint32_t localShadowTileSize(float screenFraction, uint32_t viewportHeight, uint32_t minTile, uint32_t maxTile) {
    const float wanted = std::clamp(screenFraction, 0.0f, 1.0f) * float(viewportHeight);
    const uint32_t side = std::bit_ceil(uint32_t(std::max(wanted, 1.0f)));
    return std::clamp(side, minTile, std::max(minTile, maxTile));
}

std::vector<LocalShadowPlacement> planLocalShadows(std::vector<LocalShadowRequest> requests, uint32_t viewportHeight,
                                                   const RenderSettings& s, uint32_t atlas) {
    std::stable_sort(requests.begin(), requests.end(), [](const LocalShadowRequest& a, const LocalShadowRequest& b) {
        return a.screenFraction > b.screenFraction;
    });
    if (requests.size() > s.shadowLocalLights) requests.resize(s.shadowLocalLights);
    const uint32_t minTile = std::min(kMinLocalShadowTile, atlas);
    const uint32_t maxTile = std::min(std::bit_floor(std::max(s.shadowLocalMaxTile, minTile)), atlas);
    std::vector<uint32_t> wanted;
    for (const LocalShadowRequest& r : requests)
        wanted.push_back(localShadowTileSize(r.screenFraction, viewportHeight, minTile, maxTile));

    // Halve everything until all fit (or nothing can shrink), then drop what still does not.
    std::vector<LocalShadowPlacement> out;
    std::vector<glm::uvec2> at;
    for (uint32_t shift = 0;; ++shift) {
        // Tiles in packing order: by size, largest first; each light's faces together.
        std::vector<size_t> order(requests.size());
        for (size_t i = 0; i < order.size(); ++i) order[i] = i;
        auto sizeOf = [&](size_t i) { return std::max(wanted[i] >> shift, minTile); };
        std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return sizeOf(a) > sizeOf(b); });
        std::vector<uint32_t> sizes;
        for (size_t i : order)
            for (uint32_t f = 0; f < (requests[i].cube ? 6u : 1u); ++f) sizes.push_back(sizeOf(i));
        const size_t placed = packMorton(sizes, atlas, minTile, at);
        const bool canShrink = std::any_of(order.begin(), order.end(), [&](size_t i) { return sizeOf(i) > minTile; });
        if (placed < sizes.size() && canShrink) continue;
        size_t tile = 0;
        for (size_t i : order) {
            LocalShadowPlacement p;
            p.light = requests[i].light;
            p.size = sizeOf(i);
            p.faces = requests[i].cube ? 6u : 1u;
            if (tile + p.faces > placed) break; // the rest do not fit even at the smallest size
            for (uint32_t f = 0; f < p.faces; ++f) p.origins[f] = at[tile++];
            out.push_back(p);
        }
        return out;
    }
}

glm::mat4 localShadowMatrix(glm::vec3 position, glm::vec3 direction, float tanHalf, float range) {
    const glm::vec3 d = glm::normalize(direction);
    const glm::vec3 up = std::abs(d.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::mat4 view = glm::lookAt(position, position + d, up);
    const float n = range * 1e-3f, f = range;
    // Reversed-Z: view depth n -> 1, f -> 0 (GL_ZERO_TO_ONE clip control, as the main view).
    glm::mat4 p(0.0f);
    p[0][0] = 1.0f / tanHalf;
    p[1][1] = 1.0f / tanHalf;
    p[2][2] = n / (f - n);
    p[2][3] = -1.0f;
    p[3][2] = n * f / (f - n);
    return p * view;
}

} // namespace pnb::player
