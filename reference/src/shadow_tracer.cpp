// Ground-truth directional-light visibility with Embree 3 (see shadow_tracer.h).
//
// Based on: the Embree 3 API manual (rtcOccluded16, RTCIntersectContext coherent flag, robust
// scene flag, denormal flushing advice); the origin-relative ("camera-relative") vertex trick of
// the player's renderer, applied here on the CPU in double.
#include "pnb_reference/shadow_tracer.h"

#include "pnb/node_transform.h"
#include "mesh_decode.h"
#include "embree_geometry.h"
#include "posed_scene.h"
#include "self_intersection.h"
#include "translucency.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>


#if defined(__SSE__) || defined(__x86_64__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#define PNB_REFERENCE_HAS_MXCSR 1
#endif

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

namespace pnb::reference {

using detail::meshName;
using detail::nodeName;
using detail::readIndex;
using detail::passTranslucent;
using detail::rejectOwnSurface;
using detail::TraceContext;
using detail::TranslucentHit;

namespace {

// What Embree's device error callback last reported; Embree may call it from build threads.
struct ErrorSink {
    std::mutex mutex;
    std::string last;
};

void embreeError(void* user, RTCError code, const char* message) {
    auto* sink = static_cast<ErrorSink*>(user);
    std::lock_guard<std::mutex> lock(sink->mutex);
    sink->last = "error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

} // namespace

struct ShadowTracer::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ErrorSink errors; // outlives the device's use of it (released in the destructor below)
    // Per geometry (the filter's user pointer), per triangle: kVertexRelativeError x the largest
    // origin-relative vertex magnitude, the triangle's own error band.
    std::vector<std::unique_ptr<std::vector<float>>> triangleTolerances;
    detail::TranslucentSurfaces translucent; // the Blend casters, by geometry id

    ~Embree() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {

using Clock = std::chrono::steady_clock;

TracerError inputError(std::string message) { return {TracerErrorKind::Input, std::move(message)}; }

// Sets flush-to-zero and denormals-are-zero for the lifetime of the guard (Embree's advice for
// traversal speed), restoring the caller's MXCSR afterwards.
class DenormalGuard {
public:
#ifdef PNB_REFERENCE_HAS_MXCSR
    DenormalGuard() : mSaved(_mm_getcsr()) {
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    }
    ~DenormalGuard() { _mm_setcsr(mSaved); }

private:
    unsigned int mSaved;
#endif
};


} // namespace

ShadowTracer::~ShadowTracer() = default;

TracerResult<std::unique_ptr<ShadowTracer>> ShadowTracer::build(const Scene& scene,
                                                                glm::dvec3 origin, const FramePose& at) {
    auto start = Clock::now();
    std::unique_ptr<ShadowTracer> tracer(new ShadowTracer);
    tracer->mOrigin = origin;
    tracer->mEmbree = std::make_unique<Embree>();
    Embree& embree = *tracer->mEmbree;

    embree.device = rtcNewDevice(nullptr);
    if (!embree.device)
        return TracerError{TracerErrorKind::Embree,
                           "Embree could not create a device (error " +
                               std::to_string(int(rtcGetDeviceError(nullptr))) +
                               "; does this CPU support SSE2?)"};
    rtcSetDeviceErrorFunction(embree.device, embreeError, &embree.errors);
    auto embreeFailure = [&](const char* what) {
        std::lock_guard<std::mutex> lock(embree.errors.mutex);
        return TracerError{TracerErrorKind::Embree,
                           std::string("Embree: ") + what + " (" +
                               (embree.errors.last.empty() ? "no error reported" : embree.errors.last) +
                               ")"};
    };

    embree.scene = rtcNewScene(embree.device);
    if (!embree.scene) return embreeFailure("rtcNewScene failed");
    // Robust: no traversal shortcuts that trade accuracy for speed; this is the reference.
    rtcSetSceneFlags(embree.scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(embree.scene, RTC_BUILD_QUALITY_HIGH);

    TracerStats& stats = tracer->mStats;
    const std::vector<Node>& nodes = scene.nodes.nodes;
    std::vector<uint32_t> triangleIndices; // the instance's opaque casters, one geometry
    std::vector<std::pair<const Submesh*, std::vector<uint32_t>>> translucent; // one geometry each

    for (size_t i = 0; i < nodes.size(); ++i)
        if (nodes[i].parent != kNone && nodes[i].parent >= i)
            return inputError(nodeName(scene, uint32_t(i)) + ": parent " + std::to_string(nodes[i].parent) +
                              " does not precede it");
    // Every drawn copy of a mesh, as the player places them (EXT_mesh_gpu_instancing included),
    // in the pose traced (posed_scene.h).
    auto posed = detail::PosedScene::make(scene, at);
    if (!posed) return posed.error();
    for (const MeshInstance& copy : posed->instances()) {
        const size_t i = copy.node;
        const Node& n = nodes[i];
        if (n.mesh >= scene.meshes.size())
            return inputError(nodeName(scene, uint32_t(i)) + " refers to mesh " +
                              std::to_string(n.mesh) + " of " + std::to_string(scene.meshes.size()));
        const Mesh& mesh = fullDetailMesh(scene, n.mesh); // the MDET detail, not a proxy
        const uint32_t indexBytes = mesh.indexType == IndexType::U16 ? 2 : 4;
        const uint64_t indexCount = mesh.indices.size() / indexBytes;

        // The triangles of this instance's casting submeshes (the player draws lod 0 only).
        triangleIndices.clear();
        translucent.clear();
        for (const Submesh& sm : mesh.submeshes) {
            if (sm.lod != 0) continue;
            if (mesh.primitive != Primitive::Triangles || sm.material == kNone) {
                ++stats.excludedInstances;
                continue;
            }
            if (sm.material >= scene.materials.size())
                return inputError(meshName(scene, n.mesh) + " refers to material " +
                                  std::to_string(sm.material) + " of " +
                                  std::to_string(scene.materials.size()));
            const Material& m = scene.materials[sm.material];
            if (!m.castsShadows) { // a Blend surface that casts nothing lets everything through
                ++stats.excludedInstances;
                continue;
            }
            if (uint64_t(sm.firstIndex) + sm.indexCount > indexCount)
                return inputError(meshName(scene, n.mesh) + ": submesh indices " +
                                  std::to_string(sm.firstIndex) + "+" +
                                  std::to_string(sm.indexCount) + " run past its " +
                                  std::to_string(indexCount) + " indices");
            ++stats.casterInstances;
            if (m.alphaMode == AlphaMode::Mask) ++stats.maskedCastersTreatedOpaque;
            std::vector<uint32_t>* target = &triangleIndices;
            if (detail::isTranslucentCaster(m)) {
                ++stats.translucentCasters;
                target = &translucent.emplace_back(&sm, std::vector<uint32_t>{}).second;
            }
            const uint64_t end = uint64_t(sm.firstIndex) + sm.indexCount / 3 * 3;
            for (uint64_t k = sm.firstIndex; k < end; ++k) {
                uint32_t index = readIndex(mesh, k);
                if (index >= mesh.vertexCount)
                    return inputError(meshName(scene, n.mesh) + ": index " + std::to_string(index) +
                                      " at position " + std::to_string(k) +
                                      " is not below vertexCount " +
                                      std::to_string(mesh.vertexCount));
                target->push_back(index);
            }
        }
        std::erase_if(translucent, [](const auto& t) { return t.second.empty(); });
        if (triangleIndices.empty() && translucent.empty()) continue;

        auto positions = posed->positions(copy.node);
        if (!positions) return positions.error();
        const glm::dmat4 world = glm::make_mat4(copy.world.data());
        auto attach = [&](const std::vector<uint32_t>& indices, RTCFilterFunctionN filter) {
            stats.triangles += indices.size() / 3;
            return detail::attachTriangles(embree.device, embree.scene,
                                           {*positions, world, origin, indices, filter, false},
                                           embree.triangleTolerances, tracer->mWorldBand);
        };
        if (!triangleIndices.empty() && !attach(triangleIndices, rejectOwnSurface))
            return embreeFailure("attaching a geometry failed");
        for (auto& [sm, indices] : translucent) {
            const auto id = attach(indices, passTranslucent);
            if (!id) return embreeFailure("attaching a geometry failed");
            if (auto e = embree.translucent.add(scene, *id, n.mesh, *sm, std::move(indices))) return *e;
        }
    }
    stats.translucentTexturesFactorOnly = embree.translucent.texturesFactorOnly();

    rtcCommitScene(embree.scene);
    if (rtcGetDeviceError(embree.device) != RTC_ERROR_NONE)
        return embreeFailure("building the Embree scene failed");
    stats.buildMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return tracer;
}

void ShadowTracer::visibility(std::span<const glm::vec3> positions, glm::vec3 towardLight,
                              std::span<float> out, glm::dvec3 eye) const {
    trace(positions, towardLight, nullptr, Output{out, {}}, eye);
}

void ShadowTracer::visibilityToPoint(std::span<const glm::vec3> positions, glm::vec3 light,
                                     std::span<float> out, glm::dvec3 eye) const {
    trace(positions, glm::vec3(0.0f, 1.0f, 0.0f), &light, Output{out, {}}, eye);
}

void ShadowTracer::colorVisibility(std::span<const glm::vec3> positions, glm::vec3 towardLight,
                                   std::span<glm::vec3> out, glm::dvec3 eye) const {
    trace(positions, towardLight, nullptr, Output{{}, out}, eye);
}

void ShadowTracer::colorVisibilityToPoint(std::span<const glm::vec3> positions, glm::vec3 light,
                                          std::span<glm::vec3> out, glm::dvec3 eye) const {
    trace(positions, glm::vec3(0.0f, 1.0f, 0.0f), &light, Output{{}, out}, eye);
}

void ShadowTracer::trace(std::span<const glm::vec3> positions, glm::vec3 towardLight,
                         const glm::vec3* point, Output out, glm::dvec3 eye) const {
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    const size_t count = positions.size();
    const bool color = out.binary.empty() && !out.color.empty();
    // Colour: the product of the transmittances crossed (translucency.h); binary: 1 unless an
    // opaque caster blocks (the translucent ones are passed unrecorded).
    auto write = [&](size_t i, glm::vec3 value) {
        if (color) out.color[i] = value;
        else out.binary[i] = value.x;
    };
    const float lightLength = glm::length(towardLight);
    const bool pointOk = !point || (std::isfinite(point->x) && std::isfinite(point->y) && std::isfinite(point->z));
    if ((color ? out.color.size() : out.binary.size()) != count || !std::isfinite(lightLength) ||
        !(lightLength > 0.0f) || !pointOk || !std::isfinite(eye.x) || !std::isfinite(eye.y) ||
        !std::isfinite(eye.z)) {
        std::fill(out.binary.begin(), out.binary.end(), kNaN);
        std::fill(out.color.begin(), out.color.end(), glm::vec3(kNaN));
        return;
    }
    const glm::vec3 dir = towardLight / lightLength;
    RTCScene scene = mEmbree->scene;

    constexpr size_t kPacket = 16;
    constexpr size_t kChunk = kPacket * 64; // work unit handed to a thread
    const size_t chunks = (count + kChunk - 1) / kChunk;
    std::atomic<size_t> nextChunk{0};

    auto traceChunk = [&](size_t chunk) {
        const size_t begin = chunk * kChunk, end = std::min(count, begin + kChunk);
        TraceContext context;
        rtcInitIntersectContext(&context.embree);
        context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT; // neighbouring pixels, one direction
        context.eye = eye;
        context.fixedBand = kVertexRelativeError * glm::length(eye) + mWorldBand;
        if (point) context.lightBand = kPointRelativeError * glm::length(glm::dvec3(*point) - eye);
        std::vector<TranslucentHit> hits[kPacket]; // per lane (the ray's id), colour queries only
        if (color) context.translucentHits = hits;
        for (size_t first = begin; first < end; first += kPacket) {
            // The manual requires the packet aligned to 64 bytes; Embree's AVX-512 path also
            // reads the valid mask with an aligned 64-byte load, so a mask that happens to sit
            // off a 64-byte boundary (as under ASan's stack layout) faults inside rtcOccluded16.
            RTCRay16 ray; // RTC_ALIGN(64)
            alignas(64) int valid[kPacket];
            bool any = false;
            for (size_t lane = 0; lane < kPacket; ++lane) {
                const size_t i = first + lane;
                valid[lane] = 0;
                hits[lane].clear();
                // Inactive lanes still get defined values (Embree may load them).
                ray.org_x[lane] = ray.org_y[lane] = ray.org_z[lane] = 0.0f;
                ray.dir_x[lane] = dir.x, ray.dir_y[lane] = dir.y, ray.dir_z[lane] = dir.z;
                ray.tnear[lane] = 0.0f;
                ray.tfar[lane] = std::numeric_limits<float>::infinity();
                ray.time[lane] = 0.0f;
                ray.mask[lane] = 0xFFFFFFFFu;
                ray.id[lane] = unsigned(lane);
                ray.flags[lane] = 0;
                if (i >= end) continue;
                const glm::vec3 p = positions[i];
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                    write(i, glm::vec3(kNaN));
                    continue;
                }
                // From the point itself: its own surface is rejected by rejectOwnSurface. Nothing
                // nearer than the point's own error band can be told from its surface anyway, so
                // the ray skips that stretch (tnear): a ray that leaves its surface at more than a
                // grazing angle is past the surface's band by then and never calls the filter for
                // it. No offset along a normal: shadow edges do not move.
                ray.org_x[lane] = p.x, ray.org_y[lane] = p.y, ray.org_z[lane] = p.z;
                ray.tnear[lane] = float(kPointRelativeError * glm::length(glm::dvec3(p) - eye));
                if (point) { // a segment to the light: the direction is not normalised, t = 1 at it
                    const glm::vec3 d = *point - p;
                    const double length = glm::length(glm::dvec3(d));
                    if (!(length > 0.0)) { // the point is the light: nothing lies between
                        write(i, glm::vec3(1.0f));
                        continue;
                    }
                    ray.dir_x[lane] = d.x, ray.dir_y[lane] = d.y, ray.dir_z[lane] = d.z;
                    ray.tnear[lane] = float(double(ray.tnear[lane]) / length);
                    // The segment stops short of the light by the light's own error band, as it
                    // starts past the point's (tnear): a hit there cannot be told from the
                    // light's position. The filter also rejects surfaces through the light.
                    ray.tfar[lane] = float(1.0 - context.lightBand / length);
                }
                valid[lane] = -1;
                any = true;
            }
            if (!any) continue;
            rtcOccluded16(valid, scene, &context.embree, &ray);
            for (size_t lane = 0; lane < kPacket; ++lane) {
                if (!valid[lane]) continue;
                const bool blocked = ray.tfar[lane] < 0.0f; // -inf: an opaque caster
                write(first + lane, blocked ? glm::vec3(0.0f)
                                    : color ? mEmbree->translucent.product(hits[lane])
                                            : glm::vec3(1.0f));
            }
        }
    };
    auto worker = [&] {
        DenormalGuard guard;
        for (size_t c = nextChunk.fetch_add(1); c < chunks; c = nextChunk.fetch_add(1)) traceChunk(c);
    };

    const size_t threads =
        std::min<size_t>(std::max(1u, std::thread::hardware_concurrency()), chunks);
    std::vector<std::thread> pool;
    for (size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
}

} // namespace pnb::reference
