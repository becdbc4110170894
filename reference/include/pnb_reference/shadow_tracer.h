// pnb_reference/shadow_tracer.h — ground-truth visibility of a directional light, ray traced with
// Embree 3 against a decoded container, to measure the player's shadow maps against.
//
// Does: builds one Embree scene (RTC_BUILD_QUALITY_HIGH, robust mode, triangle geometry) from the
// shadow casters of a pnb::Scene — every level-0 submesh instance whose material has
// castsShadows = true and alphaMode != Blend, exactly the instances the player draws — with world
// transforms composed in double from the node graph (as the player's buildSceneGraph does) and
// vertices made relative to a caller-given origin before they are rounded to float; then answers
// "is this point lit?" for many points at once, on all cores, with 16-ray packets.
//
// Does NOT do: alpha-mask texture lookups (Mask casters are treated as opaque and counted, see
// TracerStats), point or spot lights, soft shadows (a directional light of zero angular size),
// transmission through Blend materials (they cast nothing), images or files (pnb-reference does).
//
// Self-intersection (docs/REFERENCE.md): a query point is moved off its surface along the normal
// (flipped to face the light) by kRelativeOffset * max(1, |position|), and the ray starts at
// tnear = that same distance. A point whose normal is unknown (zero) is only moved by tnear.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "pnb/error.h"
#include "pnb/scene.h"

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
    uint32_t excludedInstances = 0;       // level-0 submesh instances that cast nothing:
                                          // castsShadows false, Blend, no material, not triangles
    double buildMs = 0;                   // decode + transform + Embree BVH build, milliseconds
};

// How far a query point is moved off its surface, relative to max(1, |position|) in scene units:
// 1e-4 covers float rounding of origin-relative positions (2^-24 relative) and the error of
// positions reconstructed by the player (depth-buffer precision) with a wide margin, while
// staying below a millimetre for points within 10 units of the origin. See docs/REFERENCE.md.
inline constexpr float kRelativeOffset = 1e-4f;

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
    static TracerResult<std::unique_ptr<ShadowTracer>> build(const Scene& scene, glm::dvec3 origin);

    ~ShadowTracer();
    ShadowTracer(const ShadowTracer&) = delete;
    ShadowTracer& operator=(const ShadowTracer&) = delete;

    // For every i: out[i] = 1 if a ray from positions[i] towards the light reaches infinity
    // unblocked, 0 if a caster blocks it, NaN if positions[i] has a non-finite component (no
    // geometry at that pixel).
    //   positions:   origin-relative world positions (scene units).
    //   normals:     unit world normals of the surfaces the points lie on; a zero (or non-finite)
    //                normal means unknown. May be empty (all unknown); otherwise the same size as
    //                positions.
    //   towardLight: direction from the surface towards the directional light (the negated
    //                direction the light shines in); normalised here, must be finite and non-zero.
    // Preconditions (checked, violations fill `out` with NaN): out.size() == positions.size();
    // normals empty or of that size; towardLight finite and non-zero.
    // Uses up to std::thread::hardware_concurrency() threads (chunks of the span; rows of an
    // image are contiguous). Thread safety: const; concurrent calls are safe.
    void visibility(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                    glm::vec3 towardLight, std::span<float> out) const;

    const TracerStats& stats() const { return mStats; }
    glm::dvec3 origin() const { return mOrigin; }

private:
    struct Embree; // RTCDevice + RTCScene (Embree types stay out of this header)

    ShadowTracer() = default;

    std::unique_ptr<Embree> mEmbree;
    TracerStats mStats;
    glm::dvec3 mOrigin{0.0};
};

} // namespace pnb::reference
