// Ground-truth directional-light visibility with Embree 3 (see shadow_tracer.h).
//
// Based on: the Embree 3 API manual (rtcOccluded16, RTCIntersectContext coherent flag, robust
// scene flag, denormal flushing advice); the origin-relative ("camera-relative") vertex trick of
// the player's renderer, applied here on the CPU in double.
#include "pnb_reference/shadow_tracer.h"

#include "pnb/node_transform.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
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

    ~Embree() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {

using Clock = std::chrono::steady_clock;

TracerError inputError(std::string message) { return {TracerErrorKind::Input, std::move(message)}; }

// The string `ref` names, or "" (also for a reference past the table: names are only decoration).
std::string nameOf(const Scene& scene, StringRef ref) {
    return ref < scene.strings.strings.size() ? std::string(scene.strings.strings[ref]) : "";
}

std::string meshName(const Scene& scene, uint32_t mesh) {
    std::string name = nameOf(scene, scene.meshes[mesh].name);
    return "mesh " + std::to_string(mesh) + (name.empty() ? "" : " '" + name + "'");
}

std::string nodeName(const Scene& scene, uint32_t node) {
    std::string name = nameOf(scene, scene.nodes.nodes[node].name);
    return "node " + std::to_string(node) + (name.empty() ? "" : " '" + name + "'");
}

template <class T> T load(const std::byte* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

// One stored component as the GPU's vertex fetch reads it (OpenGL 4.5 §10.3.7 / §2.3.5.1):
// normalised unsigned c / (2^b - 1), normalised signed max(c / (2^(b-1) - 1), -1).
double readComponent(const std::byte* p, ComponentType type, bool normalized) {
    switch (type) {
    case ComponentType::F32: return load<float>(p);
    case ComponentType::F16: return glm::unpackHalf1x16(load<uint16_t>(p));
    case ComponentType::I8: {
        double c = load<int8_t>(p);
        return normalized ? std::max(c / 127.0, -1.0) : c;
    }
    case ComponentType::U8: {
        double c = load<uint8_t>(p);
        return normalized ? c / 255.0 : c;
    }
    case ComponentType::I16: {
        double c = load<int16_t>(p);
        return normalized ? std::max(c / 32767.0, -1.0) : c;
    }
    case ComponentType::U16: {
        double c = load<uint16_t>(p);
        return normalized ? c / 65535.0 : c;
    }
    case ComponentType::I32: {
        double c = load<int32_t>(p);
        return normalized ? std::max(c / 2147483647.0, -1.0) : c;
    }
    case ComponentType::U32: {
        double c = load<uint32_t>(p);
        return normalized ? c / 4294967295.0 : c;
    }
    case ComponentType::Count: break;
    }
    return 0.0;
}

// Mesh-space positions: value = stored (normalised if so flagged) * dequantScale + dequantOffset,
// as FORMAT.md §4.3 specifies and the player's vertex shader applies (F32 Plain streams have scale
// 1, offset 0). Missing components (componentCount < 3) read as 0, as GL's vertex fetch does.
TracerResult<std::vector<glm::dvec3>> decodePositions(const Scene& scene, uint32_t meshIndex) {
    const Mesh& mesh = scene.meshes[meshIndex];
    const VertexStream* stream = nullptr;
    for (const VertexStream& s : mesh.streams)
        if (s.semantic == VertexSemantic::Position) {
            stream = &s;
            break;
        }
    if (!stream)
        return inputError(meshName(scene, meshIndex) + " has casting triangles but no position stream");
    const VertexStream& s = *stream;
    if (s.encoding != VertexEncoding::Plain)
        return TracerError{TracerErrorKind::Unsupported,
                           meshName(scene, meshIndex) +
                               ": the position stream is octahedral-encoded (a unit-vector "
                               "encoding); positions must be Plain"};
    if (s.componentType >= ComponentType::Count || s.componentCount < 1 || s.componentCount > 4)
        return inputError(meshName(scene, meshIndex) + ": position stream has an invalid layout");
    const uint64_t elementBytes = uint64_t(componentSizeBytes(s.componentType)) * s.componentCount;
    if (s.data.size() != elementBytes * mesh.vertexCount)
        return inputError(meshName(scene, meshIndex) + ": position stream holds " +
                          std::to_string(s.data.size()) + " bytes, expected " +
                          std::to_string(elementBytes * mesh.vertexCount) + " (vertexCount " +
                          std::to_string(mesh.vertexCount) + ")");
    const double scale[3] = {s.dequantScale.x, s.dequantScale.y, s.dequantScale.z};
    const double offset[3] = {s.dequantOffset.x, s.dequantOffset.y, s.dequantOffset.z};
    const uint32_t componentBytes = componentSizeBytes(s.componentType);
    std::vector<glm::dvec3> out(mesh.vertexCount);
    for (uint32_t v = 0; v < mesh.vertexCount; ++v) {
        const std::byte* element = s.data.data() + uint64_t(v) * elementBytes;
        for (uint32_t c = 0; c < 3; ++c) {
            double stored = c < s.componentCount
                                ? readComponent(element + c * componentBytes, s.componentType,
                                                s.normalized)
                                : 0.0;
            out[v][int(c)] = stored * scale[c] + offset[c];
        }
    }
    return out;
}

uint32_t readIndex(const Mesh& mesh, uint64_t k) {
    if (mesh.indexType == IndexType::U16) return load<uint16_t>(mesh.indices.data() + k * 2);
    return load<uint32_t>(mesh.indices.data() + k * 4);
}

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

// The intersect context of one visibility() call: Embree hands it to the filter below.
struct TraceContext {
    RTCIntersectContext embree; // first: Embree sees a pointer to this member
    glm::dvec3 eye{0.0};        // origin-relative camera the query points were reconstructed for
    double fixedBand = 0;       // the bands common to every hit of the call: kVertexRelativeError
                                // x |eye| + kWorldRelativeError x the largest world magnitude
};

// Occlusion filter: rejects a hit on the query point's own surface. The point lies on the hit
// triangle (up to the errors of both) when its distance to the triangle's plane, t |dir . Ng| /
// |Ng|, is within the point's error band plus the triangle's; then the hit is the surface the
// point was taken from (or one meeting it there, as a wall meets the ground), not an occluder.
// Everything is relative to magnitudes of the scene, so the test is invariant to the unit.
void rejectOwnSurface(const RTCFilterFunctionNArguments* args) {
    const auto& context = *reinterpret_cast<const TraceContext*>(args->context);
    const auto& tolerance = *static_cast<const std::vector<float>*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        RTCRayN* ray = args->ray;
        RTCHitN* hit = args->hit;
        const glm::dvec3 org(RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i),
                             RTCRayN_org_z(ray, args->N, i));
        const glm::dvec3 dir(RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i),
                             RTCRayN_dir_z(ray, args->N, i));
        const glm::dvec3 ng(RTCHitN_Ng_x(hit, args->N, i), RTCHitN_Ng_y(hit, args->N, i),
                            RTCHitN_Ng_z(hit, args->N, i));
        const double t = RTCRayN_tfar(ray, args->N, i); // the candidate hit's distance
        const double ngLength = glm::length(ng);
        const double distanceToPlane =
            ngLength > 0 ? t * std::fabs(glm::dot(dir, ng)) / (ngLength * glm::length(dir)) : 0.0;
        const double band = kPointRelativeError * glm::length(org - context.eye) +
                            double(tolerance[RTCHitN_primID(hit, args->N, i)]) + context.fixedBand;
        if (distanceToPlane <= band) args->valid[i] = 0;
    }
}

} // namespace

ShadowTracer::~ShadowTracer() = default;

TracerResult<std::unique_ptr<ShadowTracer>> ShadowTracer::build(const Scene& scene,
                                                                glm::dvec3 origin) {
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
    std::vector<glm::dmat4> world(nodes.size());
    std::vector<std::vector<glm::dvec3>> decoded(scene.meshes.size()); // decoded on first use
    std::vector<bool> isDecoded(scene.meshes.size(), false);
    std::vector<uint32_t> triangleIndices;

    for (size_t i = 0; i < nodes.size(); ++i) {
        const Node& n = nodes[i];
        if (n.parent != kNone && n.parent >= i)
            return inputError(nodeName(scene, uint32_t(i)) + ": parent " + std::to_string(n.parent) +
                              " does not precede it");
        const glm::dmat4 nodeMatrix = glm::make_mat4(nodeLocalMatrix(n).data());
        world[i] = n.parent == kNone ? nodeMatrix : world[n.parent] * nodeMatrix;
        if (n.mesh == kNone) continue;
        if (n.mesh >= scene.meshes.size())
            return inputError(nodeName(scene, uint32_t(i)) + " refers to mesh " +
                              std::to_string(n.mesh) + " of " + std::to_string(scene.meshes.size()));
        const Mesh& mesh = scene.meshes[n.mesh];
        const uint32_t indexBytes = mesh.indexType == IndexType::U16 ? 2 : 4;
        const uint64_t indexCount = mesh.indices.size() / indexBytes;

        // The triangles of this instance's casting submeshes (the player draws lod 0 only).
        triangleIndices.clear();
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
            if (!m.castsShadows || m.alphaMode == AlphaMode::Blend) {
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
            const uint64_t end = uint64_t(sm.firstIndex) + sm.indexCount / 3 * 3;
            for (uint64_t k = sm.firstIndex; k < end; ++k) {
                uint32_t index = readIndex(mesh, k);
                if (index >= mesh.vertexCount)
                    return inputError(meshName(scene, n.mesh) + ": index " + std::to_string(index) +
                                      " at position " + std::to_string(k) +
                                      " is not below vertexCount " +
                                      std::to_string(mesh.vertexCount));
                triangleIndices.push_back(index);
            }
        }
        if (triangleIndices.empty()) continue;

        if (!isDecoded[n.mesh]) {
            auto positions = decodePositions(scene, n.mesh);
            if (!positions) return positions.error();
            decoded[n.mesh] = std::move(*positions);
            isDecoded[n.mesh] = true;
        }
        const std::vector<glm::dvec3>& local = decoded[n.mesh];

        RTCGeometry geometry = rtcNewGeometry(embree.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        if (!geometry) return embreeFailure("rtcNewGeometry failed");
        rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
        // Embree pads vertex buffers it allocates itself so the last vertex can be read with a
        // 16-byte load.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), local.size()));
        auto* indices = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(uint32_t), triangleIndices.size() / 3));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geometry);
            return embreeFailure("allocating geometry buffers failed");
        }
        // World space in double, then relative to the origin, then float: the subtraction is
        // exact enough that far-away scenes keep sub-millimetre precision near the camera.
        const glm::dmat4& m = world[i];
        std::vector<double> magnitude(local.size());
        for (size_t v = 0; v < local.size(); ++v) {
            glm::dvec3 ws = glm::dvec3(m * glm::dvec4(local[v], 1.0));
            glm::dvec3 rel = ws - origin;
            vertices[v * 3 + 0] = float(rel.x);
            vertices[v * 3 + 1] = float(rel.y);
            vertices[v * 3 + 2] = float(rel.z);
            magnitude[v] = glm::length(rel);
            tracer->mWorldBand = std::max(tracer->mWorldBand, kWorldRelativeError * glm::length(ws));
        }
        std::memcpy(indices, triangleIndices.data(), triangleIndices.size() * sizeof(uint32_t));
        auto tolerance = std::make_unique<std::vector<float>>(triangleIndices.size() / 3);
        for (size_t t = 0; t < tolerance->size(); ++t)
            (*tolerance)[t] = float(kVertexRelativeError *
                                    std::max({magnitude[triangleIndices[t * 3]],
                                              magnitude[triangleIndices[t * 3 + 1]],
                                              magnitude[triangleIndices[t * 3 + 2]]}));
        rtcSetGeometryUserData(geometry, tolerance.get());
        rtcSetGeometryOccludedFilterFunction(geometry, rejectOwnSurface);
        embree.triangleTolerances.push_back(std::move(tolerance));
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(embree.scene, geometry);
        rtcReleaseGeometry(geometry); // the scene holds its reference
        stats.triangles += triangleIndices.size() / 3;
    }

    rtcCommitScene(embree.scene);
    if (rtcGetDeviceError(embree.device) != RTC_ERROR_NONE)
        return embreeFailure("building the Embree scene failed");
    stats.buildMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return tracer;
}

void ShadowTracer::visibility(std::span<const glm::vec3> positions, glm::vec3 towardLight,
                              std::span<float> out, glm::dvec3 eye) const {
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    const size_t count = positions.size();
    const float lightLength = glm::length(towardLight);
    if (out.size() != count || !std::isfinite(lightLength) || !(lightLength > 0.0f) ||
        !std::isfinite(eye.x) || !std::isfinite(eye.y) || !std::isfinite(eye.z)) {
        std::fill(out.begin(), out.end(), kNaN);
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
                    out[i] = kNaN;
                    continue;
                }
                // From the point itself: its own surface is rejected by rejectOwnSurface. Nothing
                // nearer than the point's own error band can be told from its surface anyway, so
                // the ray skips that stretch (tnear): a ray that leaves its surface at more than a
                // grazing angle is past the surface's band by then and never calls the filter for
                // it. No offset along a normal: shadow edges do not move.
                ray.org_x[lane] = p.x, ray.org_y[lane] = p.y, ray.org_z[lane] = p.z;
                ray.tnear[lane] = float(kPointRelativeError * glm::length(glm::dvec3(p) - eye));
                valid[lane] = -1;
                any = true;
            }
            if (!any) continue;
            rtcOccluded16(valid, scene, &context.embree, &ray);
            for (size_t lane = 0; lane < kPacket; ++lane)
                if (valid[lane]) out[first + lane] = ray.tfar[lane] < 0.0f ? 0.0f : 1.0f; // -inf: hit
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
