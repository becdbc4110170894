// pnb_reference/frame_tracer.h — the whole frame's truth (issue 40): a progressive Monte-Carlo
// path tracer (Embree) of the player's scene model, giving the linear HDR radiance the player's
// hdr image approximates, pixel for pixel, with its standard error.
//
// What it renders (docs/REFERENCE.md "The whole frame"):
//   - the player's cameras: perspective or orthographic, pixel (0, 0) the top-left pixel of the
//     image as the player's dumps store it, one ray through each pixel's centre (the rasterizer
//     samples pixel centres too; no anti-aliasing on either side);
//   - the player's material model: glTF metallic-roughness with pnb_lighting/brdf.h (the twin of
//     brdf.glsl), base colour factor x texture x COLOR_0, the metallic-roughness texture (G
//     roughness, B metallic), roughness clamped to [0.03, 1] as material.glsl does, normal maps
//     with the stored tangents (handedness and mirroring as surface.vert), emissive factor x
//     strength x texture, alpha MASK (below the cut-off the surface is absent), alpha BLEND
//     (stochastic: a ray passes with probability 1 - alpha, as the blended colour is
//     alpha x surface + (1 - alpha) x behind), single-sided surfaces invisible from behind (the
//     player culls them), KHR_texture_transform and the UV set of every slot, unlit materials
//     (radiance = base colour + emissive). The occlusion texture is NOT applied: paths compute
//     occlusion;
//   - every punctual light with lights.glsl's falloff (rangeAttenuation, the spot cone's
//     smoothstep) by next-event estimation, shadow rays passing MASK holes and attenuated by
//     Blend surfaces that cast shadows (translucency.h's transmittance, the player's shadow
//     model; Blend surfaces that cast none let shadow rays through);
//   - the environment (ENVM radiance x intensity, rotated as pnb-reference --sky does): seen
//     directly where a camera ray misses (the player's background), lighting surfaces through
//     directions drawn from its map (luminance x solid angle) and BSDF-sampled rays, combined by
//     multiple importance sampling; black where there is no ENVM (the player's clear colour);
//   - any number of bounces (maxBounces), Russian roulette after kRouletteDepth of them.
// Not modelled: the near plane (rays start at the eye, or on the camera's plane when
// orthographic: what the player clips nearer than znear the truth shows); emitters are not
// sampled by next-event estimation (an emissive surface lights others through BSDF-sampled rays
// only: a small, bright one converges slowly).
// Importance sampling: one-sample MIS of a GGX lobe (D(h) cos(h) sampling) and a cosine lobe,
// chosen by the estimated specular vs diffuse weight, with the combined pdf.
//
// Determinism: sample k of pixel p draws its random numbers from a stream keyed by (seed, p, k)
// alone, and passes add samples in order, so the same seed and settings give bit-identical
// images on any number of threads (the time limit aside: it ends after a whole pass, and which
// pass depends on the machine).
//
// Extremes: vertices relative to the build origin in double, the self-intersection bands of
// self_intersection.h (relative to magnitudes: any scale, any distance from the origin); a
// non-finite sample counts as black and is counted (FrameStats::nonFiniteSamples): NaN and
// infinity never enter the image.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "pnb/scene.h"
#include "pnb_reference/shadow_tracer.h"

namespace pnb::reference {

struct FrameCamera {
    glm::dvec3 position{0.0};       // world
    glm::dmat3 worldFromView{1.0};  // columns: the view's +X, +Y, +Z in world (it looks down -Z)
    bool orthographic = false;
    double yfovRadians = 0.8, aspect = 1.0; // perspective: vertical field of view, width / height
    double xmag = 1.0, ymag = 1.0;          // orthographic half extents (world units)
    int width = 64, height = 64;
};

struct FrameTraceSettings {
    uint32_t maxBounces = 16;     // indirect bounces after the first hit; 0 = direct light only
                                  // (lights, environment, emissive surfaces seen from it)
    uint32_t samplesPerPass = 4;  // samples per pixel added by each pass
    uint32_t minSamples = 16;     // the noise target is not trusted before this many
    uint32_t maxSamples = 4096;   // per pixel
    double noiseTarget = 0.003;   // stop once relativeNoise (FrameImage) is below it (0: never)
    double timeLimitSeconds = 120; // stop after the pass that crosses it (0: no limit)
    uint64_t seed = 1;
    unsigned threads = 0;         // 0: every core
    // The environment's orientation and scale (the player's ibl.rotation_deg, ibl.intensity):
    // a world direction w sees the ENVM at R_y(-angle) w (sh9RotateY's sense, as SkyTracer).
    double iblRotationRadians = 0, iblIntensity = 1;
    // Draw directions from the environment's map too (luminance x solid angle), weighted against
    // BSDF sampling by the balance heuristic; false: BSDF sampling alone (slower, same limit).
    bool sampleEnvironment = true;
    // Verification only (the furnace tests): every surface a Lambert reflector of albedo base
    // colour x (1 - metallic), no specular lobe, so closed forms exist. Not the player's model.
    bool lambertianOnly = false;
};

struct FrameStats {
    uint64_t triangles = 0;
    uint32_t instances = 0, lights = 0, textures = 0;
    uint32_t texturesFactorOnly = 0;   // textures that could not be decoded: factors only
    uint32_t meshesWithoutNormals = 0; // flat (geometric) normals used: no or octahedral normals
    bool environment = false;          // an ENVM radiance image lights the scene
    uint64_t nonFiniteSamples = 0;     // dropped samples (NaN or infinite radiance)
    double buildMs = 0;
};

struct FrameImage {
    int width = 0, height = 0;
    std::vector<glm::vec3> mean;          // linear HDR radiance, row 0 = the image's top row
    std::vector<glm::vec3> standardError; // of the mean, per channel
    uint32_t samples = 0, passes = 0;     // samples per pixel
    double ms = 0;                        // wall time of render()
    uint64_t rays = 0;                    // camera, bounce and shadow rays traced
    // The expected relative MSE the truth's own noise gives a perfect renderer: the mean over
    // pixels and channels of stderr^2 / (mean^2 + 0.01) (the relMSE of issue 40, eps 0.01).
    double relativeNoise = 0;
    FrameStats stats;
};

class FrameTracer {
public:
    // Builds the Embree scene of `scene` (every level-0 submesh instance; Blend ones too),
    // vertices relative to `origin` (world, normally the camera), decodes its textures, lights
    // and environment. `at`: the instant traced (frame_pose.h): geometry (deformed normals and
    // tangents included) and lights posed there. Errors as ShadowTracer::build.
    static TracerResult<std::unique_ptr<FrameTracer>> build(const Scene& scene, glm::dvec3 origin,
                                                            const FramePose& at = {});

    ~FrameTracer();
    FrameTracer(const FrameTracer&) = delete;
    FrameTracer& operator=(const FrameTracer&) = delete;

    // Renders the frame seen by `camera` progressively until settings' noise target, sample cap
    // or time limit. Uses settings.threads threads (0: all cores).
    FrameImage render(const FrameCamera& camera, const FrameTraceSettings& settings) const;

    const FrameStats& stats() const { return mStats; }

private:
    struct Impl;
    FrameTracer();
    std::unique_ptr<Impl> mImpl;
    FrameStats mStats;
};

} // namespace pnb::reference
