// pnb_reference/shadow_tracer.h — ground-truth visibility of a directional light or of a point
// (point or spot) light, ray traced with Embree 3 against a decoded container, to measure the
// player's shadow maps against.
//
// Does: builds one Embree scene (RTC_BUILD_QUALITY_HIGH, robust mode, triangle geometry) from the
// shadow casters of a pnb::Scene — every level-0 submesh instance whose material has
// castsShadows = true, Blend ones as translucent casters (issue 43) — with world
// transforms composed in double from the node graph (as the player's buildSceneGraph does; at a
// FramePose, the posed graph and deformed meshes: frame_pose.h, docs/REFERENCE.md "Moving frames") and
// vertices made relative to a caller-given origin before they are rounded to float; then answers
// "is this point lit?" for many points at once, on all cores, with 16-ray packets: by a ray to
// infinity (directional) or by the segment to a light's position (visibilityToPoint); and "how
// much light of each colour reaches it through the glass on the way?" (colorVisibility*).
//
// Does NOT do: alpha-mask texture lookups (Mask casters are treated as opaque and counted, see
// TracerStats), soft shadows (a directional light of zero angular size, point lights of zero
// radius), a light's range, spot cone or falloff (visibility is geometric: whether anything lies
// between; local_light.h weighs and restricts it), placing lights from the node graph
// (placeLocalLight does), refraction or Fresnel reflection at Blend surfaces (they only
// attenuate), images or files (pnb-reference does).
//
// Self-intersection (docs/REFERENCE.md): rays start exactly at the query point; a hit is
// rejected as the point's own surface when the point lies within the hit triangle's error band
// (its distance to the triangle's plane is below positionTolerance + triangleTolerance, both
// relative: no constant in scene units, so the verdict does not depend on the unit of length).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "pnb/error.h"
#include "pnb/scene.h"
#include "pnb_reference/frame_pose.h"

namespace pnb::reference {

enum class TracerErrorKind : uint8_t {
    Input,       // the scene is inconsistent (an index or stream size out of range)
    Unsupported, // valid data this tracer cannot use (an octahedral-encoded position stream)
    Embree,      // Embree refused: no device (unsupported CPU), out of memory
};

struct TracerError {
    TracerErrorKind kind = TracerErrorKind::Input;
    std::string message; // names the mesh, node or stream at fault
};

template <class T> using TracerResult = Result<T, TracerError>;

// What build() put into the Embree scene. Valid once build() succeeded; never changes after.
struct TracerStats {
    uint64_t triangles = 0;               // casting triangles in the Embree scene
    uint32_t casterInstances = 0;         // submesh instances (node x level-0 submesh) that cast
    uint32_t maskedCastersTreatedOpaque = 0; // of those, alphaMode Mask: traced as opaque
    uint32_t translucentCasters = 0;      // of those, alphaMode Blend: they transmit (colour
                                          // queries) and are passed by visibility()
    uint32_t translucentTexturesFactorOnly = 0; // their base-colour textures that could not be
                                          // decoded (block compressed): the factor stands in
    uint32_t excludedInstances = 0;       // level-0 submesh instances that cast nothing:
                                          // castsShadows false, no material, not triangles
    double buildMs = 0;                   // decode + transform + Embree BVH build, milliseconds
};

// Error bands of the self-intersection test, both relative (dimensionless), so that scaling a
// scene and its camera by any factor gives the same verdict (docs/REFERENCE.md, "Tolerances"):
//   - a query point may be off its surface by kPointRelativeError x its distance from the eye:
//     the player reconstructs positions from a D32F reversed-Z depth buffer, whose relative depth
//     error is a few 2^-24 (tests/player/precision_test.cpp measures it); 2^-16 leaves a wide margin yet
//     stays below 1/30 of a pixel's footprint at 2160 rows and a 60 degree field of view;
//   - a triangle may be off its true place by kVertexRelativeError x (its largest origin-relative
//     vertex magnitude + the eye's distance from the origin): rounding origin-relative vertices to
//     float here and camera-relative vertices in the player's float vertex transform are each
//     within 2^-24 of those magnitudes per coordinate; 2^-20 is 16 x that.
//   - and everything may be off by kWorldRelativeError x the largest world-space magnitude:
//     node transforms compose in double, whose rounding at 10^7 from the world origin is
//     ~2 x 10^-9 per operation: a millimetre scene placed there is uncertain to a part in 10^6
//     of its size (2^-48 covers a handful of such roundings, in the player and here).
inline constexpr double kPointRelativeError = 1.0 / 65536.0;      // 2^-16
inline constexpr double kVertexRelativeError = 1.0 / 1048576.0;   // 2^-20
inline constexpr double kWorldRelativeError = 1.0 / 281474976710656.0; // 2^-48

class ShadowTracer {
public:
    // Builds the Embree scene of `scene`'s shadow casters. `origin` (world space, scene units;
    // normally the camera position) is subtracted from every vertex in double before it is
    // rounded to float, so precision holds for scenes far (10^6 units) from the world origin;
    // visibility() positions are relative to the same origin.
    // Errors: Input (node/mesh/material index out of range, a stream whose size disagrees with
    // vertexCount, an index >= vertexCount, a submesh range past the index buffer, no position
    // stream), Unsupported (octahedral positions), Embree (device or build failure).
    // `scene` is read only during the call. Thread safety: build() may run concurrently with
    // itself (each call owns its Embree device).
    // `at`: the instant traced (frame_pose.h; default: the container as stored); Input errors
    // also for a clip it names that does not exist.
    static TracerResult<std::unique_ptr<ShadowTracer>> build(const Scene& scene, glm::dvec3 origin,
                                                             const FramePose& at = {});

    ~ShadowTracer();
    ShadowTracer(const ShadowTracer&) = delete;
    ShadowTracer& operator=(const ShadowTracer&) = delete;

    // For every i: out[i] = 1 if a ray from positions[i] towards the light reaches infinity
    // unblocked, 0 if an opaque caster (Opaque or Mask) blocks it, NaN if positions[i] has a
    // non-finite component (no geometry at that pixel). Translucent (Blend) casters do not block
    // here: this is the opaque part of colorVisibility().
    //   positions:   origin-relative world positions (scene units) of visible surface points.
    //   towardLight: direction from the surface towards the directional light (the negated
    //                direction the light shines in); normalised here, must be finite and non-zero.
    //   eye:         origin-relative position of the camera the positions were reconstructed
    //                for (their error grows with the distance from it). Default: the origin.
    // A hit on a triangle whose plane passes within the combined error band of the point is the
    // point's own surface (or one meeting it there) and does not block: no offset along a normal
    // is needed, so contact shadows and grazing light are judged without a bias of their own.
    // Preconditions (checked, violations fill `out` with NaN): out.size() == positions.size();
    // towardLight finite and non-zero; eye finite.
    // Uses up to std::thread::hardware_concurrency() threads (chunks of the span; rows of an
    // image are contiguous). Thread safety: const; concurrent calls are safe.
    void visibility(std::span<const glm::vec3> positions, glm::vec3 towardLight,
                    std::span<float> out, glm::dvec3 eye = glm::dvec3(0.0)) const;

    // The same for a point or spot light at `light` (origin-relative): 1 if the segment from
    // positions[i] to the light is unblocked, 0 if a caster lies on it (a light inside a closed
    // caster is hidden by it), NaN for non-finite positions, and everywhere if `light` is not
    // finite; 1 at the light itself. The segment leaves its point as a directional ray does (the
    // own-surface filter, tnear) and stops short of the light by the light's own error band,
    // kPointRelativeError x its distance from `eye` (tfar = 1 - band / length); a surface whose
    // plane passes within that band (plus the triangle's) of the light is the one the light sits
    // on (a lamp set into a ceiling) and does not block either. No constant in scene units.
    void visibilityToPoint(std::span<const glm::vec3> positions, glm::vec3 light,
                           std::span<float> out, glm::dvec3 eye = glm::dvec3(0.0)) const;

    // Colour visibility (docs/REFERENCE.md "Light through glass"): per point, the product of the
    // transmittances of the translucent casters (Blend, castsShadows) the ray crosses on its
    // way to the light, each T = baseColor.rgb x (1 - alpha) at the hit's texture coordinate and
    // counted once; (0, 0, 0) when an opaque caster (Opaque or Mask) blocks it; (1, 1, 1) when
    // nothing does. Every channel in [0, 1]; NaN (all three) where visibility() gives NaN, and
    // everywhere on the same precondition violations (out.size() == positions.size(), ...).
    // The same rays, tolerances and own-surface rule as visibility(), whose result is the
    // opaque part of this one (0 where this is 0, else 1). The product is taken in an order
    // fixed by the surfaces hit, not by traversal: the same bits on any number of threads.
    void colorVisibility(std::span<const glm::vec3> positions, glm::vec3 towardLight,
                         std::span<glm::vec3> out, glm::dvec3 eye = glm::dvec3(0.0)) const;
    // The same along the segment to a point or spot light at `light` (visibilityToPoint's rules).
    void colorVisibilityToPoint(std::span<const glm::vec3> positions, glm::vec3 light,
                                std::span<glm::vec3> out, glm::dvec3 eye = glm::dvec3(0.0)) const;

    const TracerStats& stats() const { return mStats; }
    glm::dvec3 origin() const { return mOrigin; }

private:
    struct Embree; // RTCDevice + RTCScene (Embree types stay out of this header)

    ShadowTracer() = default;
    // Where trace() writes: binary (visibility*) or, when `binary` is empty, colour.
    struct Output {
        std::span<float> binary;
        std::span<glm::vec3> color;
    };
    // visibility*() (point == nullptr: towards `toward`) and *visibilityToPoint().
    void trace(std::span<const glm::vec3> positions, glm::vec3 toward, const glm::vec3* point, Output out,
               glm::dvec3 eye) const;

    std::unique_ptr<Embree> mEmbree; // also owns the per-triangle tolerances the filter reads
    TracerStats mStats;
    glm::dvec3 mOrigin{0.0};
    double mWorldBand = 0; // kWorldRelativeError x the largest world-space vertex magnitude
};

} // namespace pnb::reference
