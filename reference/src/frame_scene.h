// frame_scene.h — what FrameTracer (pnb_reference/frame_tracer.h) traces against: every level-0
// surface of the scene in one Embree scene with the material data a hit needs (normals,
// tangents, both UV sets, vertex colours, decoded textures), the punctual lights placed as the
// player places them, and the environment. Answers three questions: the surface a ray sees (with
// its material evaluated as material.glsl does), how much light gets through along a shadow ray,
// and the environment's radiance in a direction. Internal to pnb_reference.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "frame_environment.h"
#include "frame_random.h"
#include "placed_lights.h"
#include "pnb/scene.h"
#include "pnb_reference/frame_tracer.h"
#include "self_intersection.h"
#include "texture_decode.h"
#include "triangle_scene.h"

namespace pnb::reference::detail {

// One punctual light, origin-relative, as lights.glsl shades it.
// A light as the frame lights with it.
using FrameLight = PlacedLight;

// A surface a ray met, its material evaluated there (material.glsl's Surface).
struct FrameSurface {
    glm::vec3 position{0.0f}; // origin-relative
    float distance = 0;       // along the ray
    glm::vec3 geometric{0.0f}; // unit geometric normal on the side the ray arrived from
    glm::vec3 normal{0.0f};    // unit shading normal, on that side too (normal map applied)
    glm::vec3 baseColor{1.0f};
    float metallic = 0, roughness = 1;
    glm::vec3 emissive{0.0f};
    bool unlit = false;
};

class FrameScene {
public:
    // At instant `at` (posed_scene.h).
    static TracerResult<std::unique_ptr<FrameScene>> build(const Scene& scene, glm::dvec3 origin, const FramePose& at,
                                                           FrameStats& stats);

    // A per-thread query context (self_intersection.h) for a camera at origin-relative `eye`.
    TraceContext context(glm::dvec3 eye) const;

    // The nearest surface along org + t dir (dir unit), t > tnear, that the ray does not pass:
    // alpha-masked holes, Blend surfaces with probability 1 - alpha (one random number from
    // `rng` each), single-sided surfaces seen from behind. `rays` counts the Embree queries.
    std::optional<FrameSurface> trace(TraceContext& context, glm::vec3 org, glm::vec3 dir, float tnear,
                                      FrameRandom& rng, uint64_t& rays) const;

    // The fraction of light that gets from org to the light along dir: 0 behind an opaque or
    // masked (at or above its cut-off) surface that casts shadows, the product of translucency.h's
    // transmittances of the Blend surfaces that cast shadows, 1 through everything else.
    // `toPoint`: dir is the segment to a point light (length included, t in (tnear, 1)),
    // `lightBand` its error band (self_intersection.h); else dir is unit and the ray unbounded.
    glm::vec3 transmittance(TraceContext& context, glm::vec3 org, glm::vec3 dir, float tnear, bool toPoint,
                            double lightBand, uint64_t& rays) const;

    // The environment's radiance along world direction w (rotation and intensity applied), black
    // without an ENVM radiance image.
    glm::vec3 environment(glm::vec3 w, const EnvironmentPose& pose) const {
        return mEnvironment ? mEnvironment->radiance(w, pose) : glm::vec3(0.0f);
    }
    // The environment to sample (next-event estimation), or null: none, or black everywhere.
    const EnvironmentMap* sampledEnvironment() const {
        return mEnvironment && mEnvironment->sampleable() ? &*mEnvironment : nullptr;
    }

    const std::vector<FrameLight>& lights() const { return mLights; }
    bool hasEnvironment() const { return mEnvironment.has_value(); }

private:
    struct Mesh {
        std::vector<glm::vec3> position; // object space (the winding's front side)
        std::vector<glm::vec3> normal;   // empty: none (flat normals)
        std::vector<glm::vec4> tangent;  // empty: none
        std::array<std::vector<glm::vec2>, 2> uv;
        std::vector<glm::vec4> color;    // empty: white
    };
    struct Slot {
        int texture = -1; // into mTextures
        TextureSlot transform;
    };
    struct MaterialInfo {
        glm::vec4 baseColor{1.0f};
        float metallic = 1, roughness = 1, normalScale = 1, alphaCutoff = 0.5f;
        glm::vec3 emissive{0.0f}; // factor x strength
        AlphaMode alphaMode = AlphaMode::Opaque;
        bool doubleSided = false, unlit = false, castsShadows = true;
        std::array<Slot, size_t(TextureSlotKind::Count)> slots;
    };
    struct Instance {
        uint32_t material = 0, mesh = 0;
        std::vector<uint32_t> indices; // 3 per triangle
        glm::mat3 model{1.0f}, normalMatrix{1.0f};
        float mirror = 1; // -1 where the placement mirrors (surface.vert's tangent sign)
    };
    // What a hit is before the pass / stop decision: the material inputs at the hit point.
    struct HitPoint {
        const Instance* instance = nullptr;
        const MaterialInfo* material = nullptr;
        glm::vec4 baseColor{1.0f};
        bool frontFacing = true;
    };

    HitPoint hitPoint(const RTCRayHit& rh, glm::vec3 dir, float bary[3], glm::vec2 uv[2]) const;
    glm::vec4 sampleSlot(const MaterialInfo& m, TextureSlotKind kind, const glm::vec2 uv[2], glm::vec4 otherwise) const;
    FrameSurface shade(const HitPoint& hit, const RTCRayHit& rh, glm::vec3 org, glm::vec3 dir, const float bary[3],
                       const glm::vec2 uv[2]) const;

    std::unique_ptr<TriangleScene> mScene;
    std::vector<Mesh> mMeshes;
    std::vector<MaterialInfo> mMaterials;
    std::vector<Instance> mInstances; // by Embree geometry id
    std::vector<LinearTexture> mTextures;
    std::vector<FrameLight> mLights;
    std::optional<EnvironmentMap> mEnvironment;
    glm::dvec3 mOrigin{0.0};
};

} // namespace pnb::reference::detail
