// translucency.h — light through blended surfaces (issue 43, docs/REFERENCE.md "Light through
// glass"): which materials transmit, the transmittance of one hit on them, and the product of
// the hits a ray collected on its way (self_intersection.h's passTranslucent filter). Shared by
// the three tracers. Internal to pnb_reference.
//
// The model (the shared contract of issue 43): a hit on a Blend material whose castsShadows is
// true lets through T = baseColor.rgb x (1 - alpha) per channel, baseColor and alpha the base
// colour factor times the base colour texture at the hit's UV (KHR_texture_transform applied;
// linear RGB; alpha = the texture's alpha x the factor's). Several hits multiply. Mask and
// Opaque surfaces stop the ray (T = 0); a Blend material that casts no shadow is not in any
// tracer's scene (T = 1).
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "pnb/scene.h"
#include "pnb_reference/shadow_tracer.h"
#include "self_intersection.h"
#include "texture_decode.h"

namespace pnb::reference::detail {

// A Blend material that casts shadows: it attenuates the light that crosses it.
inline bool isTranslucentCaster(const Material& m) { return m.alphaMode == AlphaMode::Blend && m.castsShadows; }

// T = rgb x (1 - alpha), each channel clamped to [0, 1] (a texel or factor outside [0, 1], as
// a float texture may hold, neither amplifies light nor makes it negative).
glm::vec3 transmittanceOf(glm::vec4 baseColor);

// The translucent submesh instances of one Embree scene, by Embree geometry id.
class TranslucentSurfaces {
public:
    // Registers submesh `submesh` of mesh `mesh`, attached as geometry `geometryId` with the
    // triangle list `indices` (3 per triangle, each below the mesh's vertexCount): decodes the
    // UV set of its material's base-colour slot (once per mesh and set) and the texture (once
    // per texture; a block-compressed one leaves the factor alone, counted). Errors: those of
    // decodeStream.
    std::optional<TracerError> add(const Scene& scene, unsigned geometryId, uint32_t mesh, const Submesh& submesh,
                                   std::vector<uint32_t> indices);

    size_t count() const { return mSurfaces.size(); }
    // Base-colour textures that could not be decoded (block compressed): the factor stands in.
    uint32_t texturesFactorOnly() const { return mTexturesFactorOnly; }

    // The transmittance of one recorded hit (1 for a geometry that is not translucent).
    glm::vec3 transmittance(const TranslucentHit& hit) const;

    // The product of the transmittances of the distinct crossings in `hits` whose distance is
    // below tMax. A crossing is counted once: Embree may offer a triangle twice (the BVH's
    // spatial splits reference it from several leaves), and a ray through the edge two
    // triangles of a surface share hits both; hits on one geometry within the point's relative
    // error band of each other (kPointRelativeError x t) are one crossing. `hits` is sorted by
    // geometry, distance and triangle first, so the product is taken in one order whatever
    // order traversal found them in: the same bits on any number of threads.
    glm::vec3 product(std::vector<TranslucentHit>& hits,
                      float tMax = std::numeric_limits<float>::infinity()) const;

private:
    struct Surface {
        glm::vec4 factor{1.0f};
        int texture = -1; // into mTextures
        TextureSlot slot; // its KHR_texture_transform
        std::vector<uint32_t> indices;
        const std::vector<glm::vec2>* uv = nullptr; // the slot's UV set (in mUvs), may be empty
    };
    std::vector<int> mSurfaceOfGeometry; // -1: not translucent
    std::vector<Surface> mSurfaces;
    std::vector<LinearTexture> mTextures;
    std::vector<int> mTextureOfScene;    // per scene texture: -2 not tried, -1 undecodable
    std::vector<std::unique_ptr<std::vector<glm::vec2>>> mUvs; // stable addresses
    std::vector<std::pair<uint64_t, const std::vector<glm::vec2>*>> mUvOfMeshSet;
    uint32_t mTexturesFactorOnly = 0;
};

} // namespace pnb::reference::detail
