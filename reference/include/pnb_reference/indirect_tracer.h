// pnb_reference/indirect_tracer.h — ground truth for one bounce of diffuse light: Monte-Carlo
// irradiance at surface points from light that reached them after exactly one diffuse
// reflection (what the player's light propagation volumes approximate), ray traced with Embree.
//
// E(p, n) = ∫ L1(x(w), -w) max(0, n.w) dw, estimated with cosine-weighted directions as
// (1/N) sum_j rho(x_j) E_direct(x_j), where x_j is the first surface a ray from p meets,
// rho its diffuse albedo (base-colour factor x base-colour texture at the hit's UV x vertex
// colour, x (1 - metallic factor)) and E_direct its irradiance from the scene's lights (the
// player's light model: KHR_lights_punctual intensities, lights.glsl's range window, shadow rays
// against the shadow casters, coloured by the glass they cross: ShadowTracer::colorVisibility).
// Translucent surfaces (Blend that casts shadows) reflect nothing; a bounce ray that crosses
// them on its way to x is attenuated by their transmittance (docs/REFERENCE.md "Light through
// glass"). Rays that leave the scene see black (no sky yet). The surface seen is the side the
// ray arrives on (two-sided reflectors).
//
// Does NOT do: alpha-masked holes (masked surfaces are opaque), the metallic-roughness texture
// (metallic is the factor), block-compressed textures (their factor only; counted in stats),
// specular bounces, emissive surfaces as sources, more than one bounce.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "pnb/scene.h"
#include "pnb_reference/shadow_tracer.h"

namespace pnb::reference {

enum class IndirectLights : uint8_t {
    All, // every light of the scene (the scene's truth)
    Sun, // the first directional light that casts shadows, else the first directional light
         // (what the player's GI bounces: the error of the technique alone)
};

struct IndirectSettings {
    uint32_t samples = 256; // cosine-weighted rays per point
    uint64_t seed = 1;      // the same seed gives the same estimate
    IndirectLights lights = IndirectLights::All;
};

struct IndirectStats {
    uint64_t triangles = 0;           // level-0 triangles: reflecting (non-blended) and translucent
    uint32_t instances = 0;           // submesh instances among them
    uint32_t translucentInstances = 0; // translucent (Blend, casting) instances: they reflect
                                       // nothing and attenuate the rays that cross them
    uint32_t texturedMaterials = 0;   // materials whose base-colour texture is sampled
    uint32_t texturesFactorOnly = 0;  // base-colour textures that could not be decoded (block
                                      // compressed): their material's factor stands in
    uint32_t lights = 0;              // lights the bounce is lit by
    double buildMs = 0;
};

class IndirectTracer {
public:
    // Builds the reflector scene and the shadow-caster tracer of `scene`, vertices relative to
    // `origin` (world, normally the camera). Errors as ShadowTracer::build.
    static TracerResult<std::unique_ptr<IndirectTracer>> build(const Scene& scene, glm::dvec3 origin);

    ~IndirectTracer();
    IndirectTracer(const IndirectTracer&) = delete;
    IndirectTracer& operator=(const IndirectTracer&) = delete;

    // For every i with finite positions[i] and non-zero normals[i] (origin-relative, unit
    // normal facing the viewer): mean[i] = one-bounce irradiance (rgb, in the lights' units:
    // lux x albedo for the sun), standardError[i] = the estimate's standard error per channel.
    // NaN where there is no surface. Spans must have equal sizes (else all NaN). Uses all cores.
    void irradiance(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                    const IndirectSettings& settings, std::span<glm::vec3> mean,
                    std::span<glm::vec3> standardError, glm::dvec3 eye = glm::dvec3(0.0)) const;

    const IndirectStats& stats() const { return mStats; }

private:
    struct Impl;
    IndirectTracer();
    std::unique_ptr<Impl> mImpl;
    IndirectStats mStats;
};

} // namespace pnb::reference
