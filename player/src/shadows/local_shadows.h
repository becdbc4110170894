// local_shadows.h — shadows of point and spot lights (docs/PLAYER.md "Local-light shadows"):
// one depth atlas (D32F, reversed-Z) holding a square tile per spot light and six per point light
// (the cube's faces as perspective tiles: the atlas stays one 2D texture, sampled with the same
// PCF as the sun's), each tile's side following the light's size on screen, the whole within
// shadows.local_atlas² texels.
//
// Per frame: the lights are ranked by how large they are on screen and the first
// shadows.local_lights get tiles (planLocalShadows, plain math, tested in
// tests/player/local_shadow_math_test.cpp); a tile is drawn again only when its light, its place
// in the atlas or the scene's casters changed (its depths do not depend on the camera), then
// lighting (shaders/include/local_shadows.glsl) reads each lit pixel's tile. No atlas exists
// while no local light casts a shadow in view. Blended casters (issue 43) give the atlas the
// sun's colour companions (shadow_maps.h), one layer each, nearest depth stored as 1 - z.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "pnb_player/gl_handles.h"
#include "pnb_player/settings.h"
#include "shadows/shadow_maps.h" // TranslucentMaps

namespace pnb::player {

struct FrameContext;
struct ShadowContext;
struct LightContext;

// One light that wants a shadow this frame.
struct LocalShadowRequest {
    uint32_t light = 0;       // GpuScene::lights index
    bool cube = false;        // six faces (point lights; spot lights wider than 60 degrees)
    float screenFraction = 0; // bounding sphere's projected radius / half the view height (<= 1)
};

// Where a light's tiles are: `faces` squares of `size` texels at `origins` in the atlas.
struct LocalShadowPlacement {
    uint32_t light = 0;
    uint32_t size = 0;
    uint32_t faces = 0;
    std::array<glm::uvec2, 6> origins{};
};

// The tile side a light wants: its screen fraction x the viewport height, rounded up to a power of
// two within [minTile, maxTile].
uint32_t localShadowTileSize(float screenFraction, uint32_t viewportHeight, uint32_t minTile,
                             uint32_t maxTile);

// Places the requests (largest on screen first, at most `maxLights`) in an atlas of `atlas`²
// texels: power-of-two squares in Morton order, which packs them without gaps when placed largest
// first. When they do not fit, every tile is halved (not below minTile) and the packing retried;
// lights that still do not fit at minTile get no shadow (left out of the result).
std::vector<LocalShadowPlacement> planLocalShadows(std::vector<LocalShadowRequest> requests,
                                                   uint32_t viewportHeight, const RenderSettings& s,
                                                   uint32_t atlas);

// The smallest tile side (texels); a light smaller on screen still gets this much.
inline constexpr uint32_t kMinLocalShadowTile = 32;

// Camera-relative world -> clip of one tile: a reversed-Z perspective from `position` down
// `direction` with the half-angle whose tangent is `tanHalf`, near = range / 1000, far = range.
glm::mat4 localShadowMatrix(glm::vec3 position, glm::vec3 direction, float tanHalf, float range);

// The six cube-face directions (+x, -x, +y, -y, +z, -z), in the order the tiles are stored.
inline constexpr std::array<glm::vec3, 6> kCubeFaceDirections = {
    glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0),
    glm::vec3(0, -1, 0), glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)};

// The renderer's local-shadow state across frames.
struct LocalShadowContext {
    GlHandle atlas;       // D32F, comparison on (sampler2DShadow, GL_GEQUAL: reversed-Z)
    GlHandle framebuffer;             // the atlas, depth only (opaque and masked casters)
    GlHandle translucentFramebuffer;  // the companions (blended casters), while they exist
    GlHandle depthView;               // the atlas without comparison: the blended round's depth test
    uint32_t translucentDivisor = 1;  // the companions' side = the atlas' / this
    TranslucentMaps translucent; // blended casters' companions, while there are some
    uint32_t atlasSize = 0;
    // What each tile holds, to draw only the tiles whose content changed.
    struct TileKey {
        uint32_t light = ~0u, size = 0, face = 0;
        glm::uvec2 origin{0};
        glm::dvec3 position{0.0};
        glm::vec3 direction{0.0f};
        float range = 0, tanHalf = 0;
        uint64_t materialsVersion = 0;
        bool operator==(const TileKey&) const = default;
    };
    std::vector<TileKey> drawn; // tiles as last drawn
    std::vector<LocalShadowPlacement> placements; // this frame's
    uint32_t tilesDrawn = 0;    // this frame
    uint32_t tiles = 0;         // this frame, in use
};

// Ranks, places, writes the tiles' data (binding 9) and the lights' tile indices into the frame's
// light list, and draws the tiles whose content changed. After prepareLights, before lighting.
void runLocalShadows(FrameContext& ctx, LocalShadowContext& localShadows, const ShadowContext& shadows,
                     const LightContext& lights);

} // namespace pnb::player
