// pnb_reference/sky_tracer.h — ground truth for sky light: Monte-Carlo irradiance at surface
// points from the scene's environment (ENVM, docs/FORMAT.md), with the scene's own geometry
// hiding the parts of the sky it covers, ray traced with Embree. What the player's image-based
// diffuse term (irradiance SH x its sky-visibility approximation) is measured against.
//
// E(p, n) = ∫ L(R(w)) V(p, w) max(0, n.w) dw, estimated with cosine-weighted directions as
// pi x mean(L V): V = 0 when a ray from p along w meets a level-0, non-Blend triangle (the same
// occluders as IndirectTracer's reflectors), else the product of the transmittances of the
// translucent surfaces it crosses (Blend that casts shadows, docs/REFERENCE.md "Light through
// glass"; 1 when none: sky through a window is tinted), R the environment's rotation. In the
// radiance's unit times steradians: nits -> lux, before any albedo.
//
// Radiance sources (SkySource):
//   Image: the ENVM radiance texture, level 0 (RGBA16F or RGBA32F), bilinear with u wrapping and
//          v clamped (as the GPU samples it), x intensity. The environment's truth.
//   Sh:    the band-limited radiance whose clamped-cosine convolution is exactly irradianceSh:
//          coefficient k of band l divided by A_l (A = pi, 2 pi / 3, pi / 4), x intensity. The
//          window w_l stays in (dividing it out too would give the unwindowed radiance, whose
//          unoccluded irradiance is sum_k irradianceSh[k] / w_l Y_k, not the player's term). So
//          with visibility off the estimate converges to sh9Evaluate(irradianceSh rotated) x
//          intensity — the player's unoccluded term — and with visibility on the difference from
//          the player is its visibility approximation alone. This radiance can be negative in
//          places; it is kept linear (no clamp), or the identity above would not hold.
//
// Does NOT do: interreflection (sky light bounced off the scene — one bounce of sky — is not
// counted: an occluded ray contributes 0, whatever the occluder's albedo), alpha-masked holes
// (Mask surfaces are opaque, as in IndirectTracer), refraction or reflection at Blend surfaces
// (they only attenuate), the sun (the scene's directional light, not in the ENVM radiance), the specular term.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "pnb/scene.h"
#include "pnb_reference/shadow_tracer.h"

namespace pnb::reference {

enum class SkySource : uint8_t {
    Image, // the ENVM radiance texture (the truth)
    Sh,    // the radiance recovered from irradianceSh (isolates the visibility approximation)
};

struct SkySettings {
    uint32_t samples = 256; // cosine-weighted rays per point
    uint64_t seed = 1;      // the same seed gives the same estimate, on any number of threads
    SkySource source = SkySource::Image;
    // The environment turned about +Y by this angle, in sh9RotateY's sense (pnb_lighting/sh9.h:
    // right-handed, seen from above +X turns towards -Z for a positive angle): a world direction
    // w sees the environment at R_y(-angle) w, R_y = glm::rotate(angle, +Y); a feature at d
    // appears at R_y(angle) d.
    float rotationRadians = 0;
    float intensity = 1;    // scales the radiance (the player's ibl.intensity)
    bool visibility = true; // false: no occlusion rays, the unoccluded irradiance
};

struct SkyStats {
    uint64_t triangles = 0;  // level-0 triangles: occluding (non-blended) and translucent
    uint32_t instances = 0;  // submesh instances among them
    uint32_t translucentInstances = 0; // translucent (Blend, casting) instances: they attenuate
    uint32_t radianceWidth = 0, radianceHeight = 0; // the decoded image (0 x 0: none)
    double buildMs = 0;
};

class SkyTracer {
public:
    // Builds the occluder scene of `scene`, vertices relative to `origin` (world, normally the
    // camera), and decodes the environment's radiance image. Errors: Input when the scene has no
    // ENVM chunk (sky light needs one) or its radiance texture cannot be read (missing level 0,
    // short data, a format other than RGBA16F/RGBA32F); otherwise as ShadowTracer::build. An
    // environment without a radiance texture builds: only SkySource::Sh can then be traced.
    // `at`: the instant traced (frame_pose.h): the occluders posed there.
    static TracerResult<std::unique_ptr<SkyTracer>> build(const Scene& scene, glm::dvec3 origin,
                                                          const FramePose& at = {});

    ~SkyTracer();
    SkyTracer(const SkyTracer&) = delete;
    SkyTracer& operator=(const SkyTracer&) = delete;

    // Whether SkySource::Image can be traced (the ENVM has a radiance texture).
    bool hasRadianceImage() const;

    // For every i with finite positions[i] and non-zero, finite normals[i] (origin-relative,
    // unit normal facing the viewer): mean[i] = sky irradiance (rgb, lux for a radiance in
    // nits), standardError[i] = the estimate's standard error per channel. NaN where there is no
    // surface. All NaN when the spans' sizes differ, samples is 0, or the source is Image and
    // there is no radiance image. Uses all cores; deterministic for a seed.
    void irradiance(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                    const SkySettings& settings, std::span<glm::vec3> mean,
                    std::span<glm::vec3> standardError, glm::dvec3 eye = glm::dvec3(0.0)) const;

    const SkyStats& stats() const { return mStats; }

private:
    struct Impl;
    SkyTracer();
    std::unique_ptr<Impl> mImpl;
    SkyStats mStats;
};

} // namespace pnb::reference
