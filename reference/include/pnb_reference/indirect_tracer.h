// pnb_reference/indirect_tracer.h — ground truth for diffuse indirect light: Monte-Carlo
// irradiance at surface points from light that reached them after one diffuse reflection (what
// the player's light propagation volumes approximate), or after up to N of them, or converged
// (IndirectSettings::bounces), ray traced with Embree.
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
// More bounces (bounces != 1): the path goes on from x_1 with a cosine-weighted direction about
// the side it arrived on, and every vertex x_k adds throughput_k E_direct(x_k) with throughput_k =
// rho(x_1) ... rho(x_k) (times the glass crossed): the cosine pdf cancels the cosine and the 1/pi
// of each Lambertian reflection, as at the first vertex. Converged (bounces = 0) stops a path by
// Russian roulette from the third vertex on (survival max(throughput) capped at 0.95, the
// survivor's throughput divided by it: unbiased), with a safety cap of kMaxConvergedBounces.
//
// Does NOT do: alpha-masked holes (masked surfaces are opaque), the metallic-roughness texture
// (metallic is the factor), block-compressed textures (their factor only; counted in stats),
// specular bounces, emissive surfaces as sources.
#pragma once

#include <charconv>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

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
    // Diffuse reflections a path may take: 1 = one bounce (the default: the truth of the
    // one-bounce techniques, bit-identical to the tracer before bounces existed), N > 1 = up to
    // N, 0 = converged (unlimited, Russian roulette).
    uint32_t bounces = 1;
};

// The most vertices a converged path may have: roulette ends paths long before, unless the
// albedo is ~1 everywhere (a white furnace), where 0.95^256 < 1e-5 bounds the bias.
inline constexpr uint32_t kMaxConvergedBounces = 256;

// The command-line spelling of IndirectSettings::bounces (pnb-reference --indirect-bounces, pnb-judge
// --gi-bounces): a count 1..kMaxConvergedBounces or "converged" (0). Nullopt: not one of them.
inline std::optional<uint32_t> parseIndirectBounces(std::string_view text) {
    if (text == "converged") return 0u;
    uint32_t n = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
    if (ec != std::errc() || end != text.data() + text.size() || n == 0 || n > kMaxConvergedBounces)
        return std::nullopt;
    return n;
}
// And back: "converged" or the count.
inline std::string indirectBouncesName(uint32_t bounces) {
    return bounces == 0 ? std::string("converged") : std::to_string(bounces);
}

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
    // `at`: the instant traced (frame_pose.h): geometry and lights posed there.
    static TracerResult<std::unique_ptr<IndirectTracer>> build(const Scene& scene, glm::dvec3 origin,
                                                               const FramePose& at = {});

    ~IndirectTracer();
    IndirectTracer(const IndirectTracer&) = delete;
    IndirectTracer& operator=(const IndirectTracer&) = delete;

    // For every i with finite positions[i] and non-zero normals[i] (origin-relative, unit
    // normal facing the viewer): mean[i] = indirect irradiance after settings.bounces (rgb, in
    // the lights' units: lux x albedo for the sun), standardError[i] = the estimate's standard error per channel.
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
