// Diffuse indirect irradiance, one bounce or more, with Embree (see indirect_tracer.h).
#include "pnb_reference/indirect_tracer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "cosine_sampling.h"
#include "mesh_decode.h"
#include "placed_lights.h"
#include "pnb/texture_transform.h"
#include "pnb_lighting/scene_lights.h"
#include "pnb_reference/local_light.h"
#include "self_intersection.h"
#include "texture_decode.h"
#include "triangle_scene.h"

namespace pnb::reference {

namespace {


// What a hit needs to know about the instance it hit.
struct Instance {
    uint32_t material = 0;
    std::vector<uint32_t> indices;  // 3 per triangle
    std::vector<glm::vec2> uv;      // the base-colour slot's UV set, per vertex (empty: none)
    std::vector<glm::vec3> color;   // COLOR_0 per vertex (empty: white)
};

struct MaterialInfo {
    glm::vec3 albedo{1.0f}; // base-colour factor x (1 - metallic)
    int texture = -1;       // index into Impl::textures
    TextureSlot transform;  // its KHR_texture_transform (pnb/texture_transform.h)
};

struct LightInfo {
    LightType type = LightType::Directional;
    glm::vec3 radiance{0.0f};   // colour x intensity
    glm::vec3 position{0.0f};   // origin-relative
    glm::vec3 toward{0.0f, 1.0f, 0.0f}; // directional: toward the light
    glm::vec3 travel{0.0f, -1.0f, 0.0f}; // spot: the direction it shines in
    float range = 0, cosOuter = 0, cosInner = 1;
};

} // namespace

// The vertices of a batch's paths, one per ray (point x sample): where the path is now (NaN:
// ended), the side it arrived on, and the product of the albedos (and glass) along it.
struct PathVertices {
    std::vector<glm::vec3> position, normal, throughput;
};

struct IndirectTracer::Impl {
    std::unique_ptr<detail::TriangleScene> reflectors; // Embree geometry id = index into instances
    std::vector<Instance> instances;
    std::vector<MaterialInfo> materials;
    std::vector<detail::LinearTexture> textures;
    std::vector<LightInfo> lights;
    std::unique_ptr<ShadowTracer> shadows;
    int sun = -1; // index into lights

    // The first reflector along org + t dir (t > tnear): where, the side the ray arrives on, and
    // its albedo times the transmittance of the glass crossed before it. False: nothing (sky).
    bool trace(detail::TraceContext& context, std::vector<detail::TranslucentHit>& crossed, glm::vec3 org,
               glm::vec3 dir, float tnear, glm::vec3& position, glm::vec3& normal, glm::vec3& albedo) const;
    // contribution[k] += throughput[k] x the direct irradiance at vertex k from `lights`.
    void addDirect(const std::vector<int>& lights, const PathVertices& v, std::vector<glm::vec3>& visibility,
                   std::vector<glm::vec3>& contribution, glm::dvec3 eye) const;
    // Takes every path of the batch (points first.., `samples` rays each) that has not ended to
    // its next vertex (`vertex` = 2, 3, ...): a cosine-weighted direction about the side it
    // arrived on, the throughput times the albedo there; a path ends on the sky, on black, or
    // by roulette (converged). False when every path has ended.
    bool continuePaths(PathVertices& path, size_t first, uint32_t samples, uint32_t vertex,
                       const IndirectSettings& settings, glm::dvec3 eye) const;
};

namespace {

// Runs work(i) for i in [0, count) on every core, each thread with its own trace context.
template <typename Work>
void parallelTrace(size_t count, const detail::TriangleScene& reflectors, glm::dvec3 eye, Work&& work) {
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<size_t> next{0};
    auto worker = [&] {
        detail::TraceContext context;
        rtcInitIntersectContext(&context.embree);
        context.eye = eye;
        context.fixedBand = kVertexRelativeError * glm::length(eye) + reflectors.worldBand;
        std::vector<detail::TranslucentHit> crossed; // the translucent surfaces of one ray
        context.translucentHits = &crossed;
        for (size_t i = next.fetch_add(1); i < count; i = next.fetch_add(1)) work(context, crossed, i);
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
}

bool validPoint(glm::vec3 p, glm::vec3 n) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && glm::length(n) > 0.0f &&
           std::isfinite(n.x + n.y + n.z);
}

// The seed of the directions leaving vertex `vertex` (2, 3, ...): another stream than the first
// vertex's (which keeps settings.seed, so that one bounce is what it always was).
uint64_t vertexSeed(uint64_t seed, uint32_t vertex) {
    return detail::splitmix64(seed ^ (0xA24BAED4963EE407ull * vertex));
}

} // namespace

bool IndirectTracer::Impl::trace(detail::TraceContext& context, std::vector<detail::TranslucentHit>& crossed,
                                 glm::vec3 org, glm::vec3 dir, float tnear, glm::vec3& position,
                                 glm::vec3& normal, glm::vec3& albedoOut) const {
    RTCRayHit rh;
    rh.ray.org_x = org.x, rh.ray.org_y = org.y, rh.ray.org_z = org.z;
    rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
    rh.ray.tnear = tnear;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.time = 0, rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    crossed.clear();
    rtcIntersect1(reflectors->scene, &context.embree, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false; // black sky
    const Instance& inst = instances[rh.hit.geomID];
    const MaterialInfo& m = materials[inst.material];
    glm::vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    if (!(glm::length(ng) > 0.0f)) return false;
    ng = glm::normalize(ng);
    if (glm::dot(ng, dir) > 0.0f) ng = -ng; // the side the ray arrives on
    position = org + dir * rh.ray.tfar;
    normal = ng;
    const float w = 1.0f - rh.hit.u - rh.hit.v;
    const uint32_t* tri = &inst.indices[size_t(rh.hit.primID) * 3];
    glm::vec3 albedo = m.albedo;
    if (!inst.color.empty())
        albedo *= inst.color[tri[0]] * w + inst.color[tri[1]] * rh.hit.u + inst.color[tri[2]] * rh.hit.v;
    if (m.texture >= 0 && !inst.uv.empty()) {
        glm::vec2 uv = inst.uv[tri[0]] * w + inst.uv[tri[1]] * rh.hit.u + inst.uv[tri[2]] * rh.hit.v;
        const Vec2 t = textureTransformUv(m.transform, Vec2{uv.x, uv.y});
        uv = glm::vec2(t.x, t.y);
        albedo *= glm::vec3(textures[size_t(m.texture)].sample(uv));
    }
    // The light reflected back towards the ray's origin crosses the glass between them
    // (translucency.h): only surfaces nearer than the reflector count.
    albedoOut = albedo * reflectors->translucent.product(crossed, rh.ray.tfar);
    return true;
}

void IndirectTracer::Impl::addDirect(const std::vector<int>& lightIndices, const PathVertices& v,
                                     std::vector<glm::vec3>& visibility, std::vector<glm::vec3>& contribution,
                                     glm::dvec3 eye) const {
    const size_t rays = v.position.size();
    visibility.resize(rays);
    for (int li : lightIndices) {
        const LightInfo& l = lights[size_t(li)];
        if (l.type == LightType::Directional)
            shadows->colorVisibility(v.position, l.toward, visibility, eye);
        else
            shadows->colorVisibilityToPoint(v.position, l.position, visibility, eye);
        for (size_t k = 0; k < rays; ++k) {
            if (!(visibility[k].x > 0.0f || visibility[k].y > 0.0f || visibility[k].z > 0.0f)) continue;
            glm::vec3 toLight = l.toward;
            float attenuation = 1.0f;
            if (l.type != LightType::Directional) {
                glm::vec3 d = l.position - v.position[k];
                float d2 = glm::dot(d, d);
                toLight = d2 > 0.0f ? d / std::sqrt(d2) : glm::vec3(0, 0, 1);
                // lights.glsl's falloff (local_light.h).
                attenuation = float(rangeAttenuation(d2, l.range));
                if (l.type == LightType::Spot)
                    attenuation *= float(spotConeFactor(glm::dot(l.travel, -toLight), l.cosOuter, l.cosInner));
            }
            float cosine = std::max(0.0f, glm::dot(v.normal[k], toLight));
            contribution[k] += v.throughput[k] * visibility[k] * l.radiance * (attenuation * cosine);
        }
    }
}

IndirectTracer::IndirectTracer() : mImpl(std::make_unique<Impl>()) {}
IndirectTracer::~IndirectTracer() = default;

TracerResult<std::unique_ptr<IndirectTracer>> IndirectTracer::build(const Scene& scene, glm::dvec3 origin,
                                                                    const FramePose& at) {
    auto start = std::chrono::steady_clock::now();
    auto shadows = ShadowTracer::build(scene, origin, at); // also validates nodes, meshes, indices, the pose
    if (!shadows) return shadows.error();
    auto posed = detail::PosedScene::make(scene, at);
    if (!posed) return posed.error();
    std::unique_ptr<IndirectTracer> tracer(new IndirectTracer);
    Impl& impl = *tracer->mImpl;
    IndirectStats& stats = tracer->mStats;
    impl.shadows = std::move(*shadows);

    // Materials and their textures.
    std::vector<int> textureSlot(scene.textures.size(), -2); // -2 not tried, -1 undecodable
    for (const Material& m : scene.materials) {
        MaterialInfo info;
        float metallic = std::clamp(m.metallicFactor, 0.0f, 1.0f);
        info.albedo = glm::vec3(m.baseColorFactor.x, m.baseColorFactor.y, m.baseColorFactor.z) * (1.0f - metallic);
        const TextureSlot& slot = m.textures[size_t(TextureSlotKind::BaseColor)];
        if (slot.texture != kNone && slot.texture < scene.textures.size()) {
            int& t = textureSlot[slot.texture];
            if (t == -2) {
                auto decoded = detail::decodeTexture(scene, slot.texture);
                if (decoded) {
                    t = int(impl.textures.size());
                    impl.textures.push_back(std::move(*decoded));
                } else {
                    t = -1;
                    ++stats.texturesFactorOnly;
                }
            }
            info.texture = t;
            info.transform = slot;
            stats.texturedMaterials += t >= 0;
        }
        impl.materials.push_back(info);
    }

    // Lights, as every tracer places them (placed_lights.h).
    std::vector<const Light*> placed; // impl.lights' descriptors, in the player's order (by node)
    for (const detail::PlacedLight& p : detail::placeLights(scene, posed->world(), origin)) {
        LightInfo info;
        info.type = p.type;
        info.radiance = p.radiance;
        info.position = glm::vec3(p.position);
        info.travel = p.travel;
        info.toward = -info.travel;
        info.range = float(p.range);
        info.cosOuter = float(p.cosOuter);
        info.cosInner = float(p.cosInner);
        impl.lights.push_back(info);
        placed.push_back(p.desc);
    }
    // The sun GI bounces, by the player's rule.
    impl.sun = lighting::bouncedSunIndex(placed.size(), [&](size_t i) -> const Light& { return *placed[i]; });
    stats.lights = uint32_t(impl.lights.size());

    // Reflectors (triangle_scene.h), each with what a hit on it needs: its material, UVs of the
    // base-colour slot's set and vertex colours, decoded once per mesh.
    std::vector<std::vector<glm::dvec4>> uvs[2], colors(scene.meshes.size());
    uvs[0].resize(scene.meshes.size());
    uvs[1].resize(scene.meshes.size());
    std::vector<bool> decoded(scene.meshes.size(), false);
    auto reflectors = detail::buildTriangleScene(
        scene, *posed, origin,
        [&](unsigned id, uint32_t, uint32_t mesh, const Submesh& sm,
            std::vector<uint32_t>&& indices) -> std::optional<TracerError> {
            if (!decoded[mesh]) {
                for (int set = 0; set < 2; ++set) {
                    auto uv = detail::decodeStream(scene, mesh, set ? VertexSemantic::TexCoord1 : VertexSemantic::TexCoord0,
                                                   false);
                    if (!uv) return uv.error();
                    uvs[set][mesh] = std::move(*uv);
                }
                auto c = detail::decodeStream(scene, mesh, VertexSemantic::Color0, false);
                if (!c) return c.error();
                colors[mesh] = std::move(*c);
                decoded[mesh] = true;
            }
            const Material& m = scene.materials[sm.material];
            Instance inst;
            inst.material = sm.material;
            inst.indices = std::move(indices);
            const auto& uvSet = uvs[std::min<int>(m.textures[size_t(TextureSlotKind::BaseColor)].texCoord, 1)][mesh];
            for (const glm::dvec4& u : uvSet) inst.uv.push_back(glm::vec2(u));
            for (const glm::dvec4& c : colors[mesh]) inst.color.push_back(glm::vec3(c));
            if (impl.instances.size() <= id) impl.instances.resize(id + 1);
            impl.instances[id] = std::move(inst);
            return std::nullopt;
        });
    if (!reflectors) return reflectors.error();
    impl.reflectors = std::move(*reflectors);
    stats.triangles = impl.reflectors->triangles;
    stats.instances = impl.reflectors->instances;
    stats.translucentInstances = impl.reflectors->translucentInstances;
    stats.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return tracer;
}

void IndirectTracer::irradiance(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                                const IndirectSettings& settings, std::span<glm::vec3> mean,
                                std::span<glm::vec3> standardError, glm::dvec3 eye) const {
    const Impl& impl = *mImpl;
    const size_t count = positions.size();
    const glm::vec3 nan(std::numeric_limits<float>::quiet_NaN());
    if (normals.size() != count || mean.size() != count || standardError.size() != count ||
        settings.samples == 0) {
        std::fill(mean.begin(), mean.end(), nan);
        std::fill(standardError.begin(), standardError.end(), nan);
        return;
    }
    std::vector<int> lights;
    if (settings.lights == IndirectLights::Sun) {
        if (impl.sun >= 0) lights.push_back(impl.sun);
    } else {
        for (size_t l = 0; l < impl.lights.size(); ++l) lights.push_back(int(l));
    }
    const uint32_t samples = settings.samples;
    const uint32_t maxVertices = settings.bounces == 0 ? kMaxConvergedBounces : settings.bounces;
    const size_t batch = std::max<size_t>(1, (1u << 18) / samples); // points per batch

    PathVertices path;
    std::vector<glm::vec3> visibility; // colour: through the glass between bounce and light
    std::vector<glm::vec3> contribution;
    for (size_t first = 0; first < count; first += batch) {
        const size_t points = std::min(batch, count - first);
        const size_t rays = points * samples;
        path.position.assign(rays, nan);
        path.normal.assign(rays, glm::vec3(0.0f));
        path.throughput.assign(rays, glm::vec3(0.0f));
        // 1. The first surface along each cosine-weighted direction, and its albedo there.
        parallelTrace(points, *impl.reflectors, eye, [&](detail::TraceContext& context,
                                                        std::vector<detail::TranslucentHit>& crossed, size_t i) {
            const size_t point = first + i;
            const glm::vec3 p = positions[point], n = normals[point];
            if (!validPoint(p, n)) return;
            const detail::CosineFrame frame(glm::normalize(n));
            const float tnear = float(kPointRelativeError * glm::length(glm::dvec3(p) - eye));
            for (uint32_t s = 0; s < samples; ++s) {
                const size_t k = i * samples + s;
                const glm::vec3 dir = frame.direction(settings.seed, point, s);
                impl.trace(context, crossed, p, dir, tnear, path.position[k], path.normal[k], path.throughput[k]);
            }
        });
        // 2. Direct irradiance at every vertex from each light, with shadow rays (batched: the
        //    shadow tracer parallelises each call); then the paths go on for more bounces.
        contribution.assign(rays, glm::vec3(0.0f));
        impl.addDirect(lights, path, visibility, contribution, eye);
        for (uint32_t vertex = 2; vertex <= maxVertices; ++vertex) {
            if (!impl.continuePaths(path, first, samples, vertex, settings, eye)) break; // all ended
            impl.addDirect(lights, path, visibility, contribution, eye);
        }
        // 3. Mean and standard error per point: E = (1/N) sum rho E_direct (pdf cos/pi cancels
        //    the cosine and the 1/pi of the Lambertian BRDF).
        for (size_t i = 0; i < points; ++i) {
            const size_t point = first + i;
            const glm::vec3 p = positions[point], n = normals[point];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !(glm::length(n) > 0.0f)) {
                mean[point] = standardError[point] = nan;
                continue;
            }
            glm::dvec3 sum(0.0), sum2(0.0);
            for (uint32_t s = 0; s < samples; ++s) {
                glm::dvec3 v(contribution[i * samples + s]);
                sum += v;
                sum2 += v * v;
            }
            const double n1 = double(samples);
            glm::dvec3 m = sum / n1;
            glm::dvec3 var = samples > 1 ? glm::max(sum2 / n1 - m * m, glm::dvec3(0.0)) * (n1 / (n1 - 1.0)) : glm::dvec3(0.0);
            mean[point] = glm::vec3(m);
            standardError[point] = glm::vec3(glm::sqrt(var / n1));
        }
    }
}

bool IndirectTracer::Impl::continuePaths(PathVertices& path, size_t first, uint32_t samples, uint32_t vertex,
                                         const IndirectSettings& settings, glm::dvec3 eye) const {
    const Impl& impl = *this;
    const glm::vec3 nan(std::numeric_limits<float>::quiet_NaN());
    const uint64_t seed = vertexSeed(settings.seed, vertex);
    const bool roulette = settings.bounces == 0 && vertex >= 3;
    std::atomic<bool> alive{false};
    parallelTrace(path.position.size() / samples, *impl.reflectors, eye,
                  [&](detail::TraceContext& context, std::vector<detail::TranslucentHit>& crossed, size_t i) {
        bool any = false;
        for (uint32_t s = 0; s < samples; ++s) {
            const size_t k = i * samples + s;
            glm::vec3& p = path.position[k];
            if (!std::isfinite(p.x)) continue; // ended
            glm::vec3& throughput = path.throughput[k];
            if (!(std::max({throughput.x, throughput.y, throughput.z}) > 0.0f)) { // black: nothing more
                p = nan;
                continue;
            }
            if (roulette) {
                const float survival = std::min(0.95f, std::max({throughput.x, throughput.y, throughput.z}));
                const float u = detail::unitFloat(detail::splitmix64(seed ^ ((first + i) << 20) ^ s ^ (1ull << 63)));
                if (!(u < survival)) {
                    p = nan;
                    continue;
                }
                throughput /= survival;
            }
            const glm::vec3 dir = detail::CosineFrame(path.normal[k]).direction(seed, first + i, s);
            const float tnear = float(kPointRelativeError * glm::length(glm::dvec3(p) - eye));
            glm::vec3 albedo(0.0f);
            if (!impl.trace(context, crossed, p, dir, tnear, p, path.normal[k], albedo)) {
                p = nan;
                continue;
            }
            throughput *= albedo;
            any = true;
        }
        if (any) alive.store(true, std::memory_order_relaxed);
    });
    return alive.load();
}

} // namespace pnb::reference
