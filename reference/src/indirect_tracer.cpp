// One-bounce diffuse irradiance with Embree (see indirect_tracer.h).
#include "pnb_reference/indirect_tracer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <thread>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "mesh_decode.h"
#include "pnb/node_transform.h"
#include "self_intersection.h"

namespace pnb::reference {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A base-colour texture's level 0 as linear RGBA, sampled bilinearly with its wrap modes.
struct LinearTexture {
    uint32_t width = 0, height = 0;
    Wrap wrapU = Wrap::Repeat, wrapV = Wrap::Repeat;
    std::vector<glm::vec4> texels; // row t = 0 first (FORMAT.md: neither UVs nor images flipped)

    glm::vec4 sample(glm::vec2 uv) const {
        auto wrap = [](float x, uint32_t size, Wrap mode) {
            int n = int(size);
            int i = int(std::floor(x));
            switch (mode) {
            case Wrap::ClampToEdge: return std::clamp(i, 0, n - 1);
            case Wrap::MirroredRepeat: {
                int period = ((i % (2 * n)) + 2 * n) % (2 * n);
                return period < n ? period : 2 * n - 1 - period;
            }
            default: return ((i % n) + n) % n;
            }
        };
        float x = uv.x * float(width) - 0.5f, y = uv.y * float(height) - 0.5f;
        if (!std::isfinite(x) || !std::isfinite(y)) return glm::vec4(1.0f);
        float fx = x - std::floor(x), fy = y - std::floor(y);
        int x0 = wrap(x, width, wrapU), x1 = wrap(x + 1.0f, width, wrapU);
        int y0 = wrap(y, height, wrapV), y1 = wrap(y + 1.0f, height, wrapV);
        auto at = [&](int i, int j) { return texels[size_t(j) * width + size_t(i)]; };
        return (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) + (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
    }
};

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// Level 0 of texture `index`, or nothing for block-compressed or missing data.
std::optional<LinearTexture> decodeTexture(const Scene& scene, uint32_t index) {
    const TextureDesc& d = scene.textures[index];
    const TextureMip* mip = nullptr;
    for (const TextureMip& m : scene.textureMips)
        if (m.texture == index && m.level == 0) mip = &m;
    if (!mip || d.dimension != TextureDimension::Tex2D || d.width == 0 || d.height == 0) return std::nullopt;
    int channels = 0, bytes = 0;
    switch (d.format) {
    case TextureFormat::R8: channels = 1, bytes = 1; break;
    case TextureFormat::RG8: channels = 2, bytes = 1; break;
    case TextureFormat::RGB8: channels = 3, bytes = 1; break;
    case TextureFormat::RGBA8: channels = 4, bytes = 1; break;
    case TextureFormat::R16F: channels = 1, bytes = 2; break;
    case TextureFormat::RG16F: channels = 2, bytes = 2; break;
    case TextureFormat::RGBA16F: channels = 4, bytes = 2; break;
    case TextureFormat::R32F: channels = 1, bytes = 4; break;
    case TextureFormat::RG32F: channels = 2, bytes = 4; break;
    case TextureFormat::RGBA32F: channels = 4, bytes = 4; break;
    default: return std::nullopt; // BC formats
    }
    const size_t count = size_t(d.width) * d.height;
    if (mip->data.size() < count * size_t(channels * bytes)) return std::nullopt;
    LinearTexture t;
    t.width = d.width;
    t.height = d.height;
    t.wrapU = d.wrapU;
    t.wrapV = d.wrapV;
    t.texels.resize(count);
    const std::byte* p = mip->data.data();
    for (size_t i = 0; i < count; ++i) {
        float raw[4] = {0, 0, 0, 1};
        for (int c = 0; c < channels; ++c) {
            const std::byte* q = p + (i * size_t(channels) + size_t(c)) * size_t(bytes);
            if (bytes == 1) {
                raw[c] = float(uint8_t(*q)) / 255.0f;
                if (d.colorSpace == ColorSpace::Srgb && c < 3) raw[c] = srgbToLinear(raw[c]);
            } else if (bytes == 2) {
                uint16_t h;
                std::memcpy(&h, q, 2);
                raw[c] = glm::unpackHalf1x16(h);
            } else {
                std::memcpy(&raw[c], q, 4);
            }
        }
        glm::vec4 texel;
        for (int k = 0; k < 4; ++k) {
            switch (d.swizzle[size_t(k)]) {
            case Swizzle::R: texel[k] = raw[0]; break;
            case Swizzle::G: texel[k] = raw[1]; break;
            case Swizzle::B: texel[k] = raw[2]; break;
            case Swizzle::A: texel[k] = raw[3]; break;
            case Swizzle::Zero: texel[k] = 0.0f; break;
            default: texel[k] = 1.0f; break;
            }
        }
        t.texels[i] = texel;
    }
    return t;
}

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
    float offset[2] = {0, 0}, scale[2] = {1, 1}, rotation = 0;
};

struct LightInfo {
    LightType type = LightType::Directional;
    glm::vec3 radiance{0.0f};   // colour x intensity
    glm::vec3 position{0.0f};   // origin-relative
    glm::vec3 toward{0.0f, 1.0f, 0.0f}; // directional: toward the light
    glm::vec3 travel{0.0f, -1.0f, 0.0f}; // spot: the direction it shines in
    float range = 0, cosOuter = 0, coneScale = 1;
};

// lights.glsl's rangeAttenuation.
float rangeAttenuation(float d2, float range) {
    float inverseSquare = 1.0f / std::max(d2, 1e-4f);
    if (range <= 0.0f) return inverseSquare;
    float r = d2 / (range * range);
    float window = std::clamp(1.0f - r * r, 0.0f, 1.0f);
    return window * window * inverseSquare;
}

uint64_t mix(uint64_t x) { // splitmix64
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}
float unit(uint64_t x) { return float(x >> 40) * (1.0f / 16777216.0f); }

// An orthonormal basis around n (Duff et al. 2017).
void basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float c = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

} // namespace

struct IndirectTracer::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<std::unique_ptr<std::vector<float>>> tolerances; // the filter's per-triangle bands
    std::vector<Instance> instances;                              // by Embree geometry id
    std::vector<MaterialInfo> materials;
    std::vector<LinearTexture> textures;
    std::vector<LightInfo> lights;
    std::unique_ptr<ShadowTracer> shadows;
    int sun = -1; // index into lights
    double worldBand = 0;

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

IndirectTracer::IndirectTracer() : mImpl(std::make_unique<Impl>()) {}
IndirectTracer::~IndirectTracer() = default;

TracerResult<std::unique_ptr<IndirectTracer>> IndirectTracer::build(const Scene& scene, glm::dvec3 origin) {
    auto start = std::chrono::steady_clock::now();
    auto shadows = ShadowTracer::build(scene, origin); // also validates nodes, meshes, indices
    if (!shadows) return shadows.error();
    std::unique_ptr<IndirectTracer> tracer(new IndirectTracer);
    Impl& impl = *tracer->mImpl;
    IndirectStats& stats = tracer->mStats;
    impl.shadows = std::move(*shadows);
    impl.device = rtcNewDevice(nullptr);
    if (!impl.device) return TracerError{TracerErrorKind::Embree, "Embree could not create a device"};
    impl.scene = rtcNewScene(impl.device);
    rtcSetSceneFlags(impl.scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(impl.scene, RTC_BUILD_QUALITY_HIGH);

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
                auto decoded = decodeTexture(scene, slot.texture);
                if (decoded) {
                    t = int(impl.textures.size());
                    impl.textures.push_back(std::move(*decoded));
                } else {
                    t = -1;
                    ++stats.texturesFactorOnly;
                }
            }
            info.texture = t;
            info.offset[0] = slot.offset.x, info.offset[1] = slot.offset.y;
            info.scale[0] = slot.scale.x, info.scale[1] = slot.scale.y;
            info.rotation = slot.rotationRadians;
            stats.texturedMaterials += t >= 0;
        }
        impl.materials.push_back(info);
    }

    // Reflectors and lights, world transforms in double (pnb/node_transform.h).
    const std::vector<Matrix4d> worldMatrices = nodeWorldMatrices(scene.nodes);
    std::vector<std::vector<glm::dvec4>> positions(scene.meshes.size()), uvs[2], colors(scene.meshes.size());
    uvs[0].resize(scene.meshes.size());
    uvs[1].resize(scene.meshes.size());
    std::vector<bool> decoded(scene.meshes.size(), false);
    int firstDirectional = -1;
    for (size_t i = 0; i < scene.nodes.nodes.size(); ++i) {
        const Node& n = scene.nodes.nodes[i];
        const glm::dmat4 world = glm::make_mat4(worldMatrices[i].data());
        if (n.light != kNone && n.light < scene.lights.lights.size()) {
            const Light& l = scene.lights.lights[n.light];
            LightInfo info;
            info.type = l.type;
            info.radiance = glm::vec3(l.color.x, l.color.y, l.color.z) * l.intensity;
            info.position = glm::vec3(glm::dvec3(world[3]) - origin);
            info.travel = glm::vec3(glm::normalize(glm::dmat3(world) * glm::dvec3(0, 0, -1)));
            info.toward = -info.travel;
            info.range = l.range;
            info.cosOuter = std::cos(l.outerConeRadians);
            info.coneScale = 1.0f / std::max(std::cos(l.innerConeRadians) - info.cosOuter, 1e-4f);
            if (l.type == LightType::Directional) {
                if (impl.sun < 0 && l.castsShadows) impl.sun = int(impl.lights.size());
                if (firstDirectional < 0) firstDirectional = int(impl.lights.size());
            }
            impl.lights.push_back(info);
        }
        if (n.mesh == kNone || n.mesh >= scene.meshes.size()) continue;
        const Mesh& mesh = fullDetailMesh(scene, n.mesh); // the MDET detail, not a proxy
        if (mesh.primitive != Primitive::Triangles) continue;
        for (const Submesh& sm : mesh.submeshes) {
            if (sm.lod != 0 || sm.material >= scene.materials.size()) continue;
            const Material& m = scene.materials[sm.material];
            if (m.alphaMode == AlphaMode::Blend) continue;
            if (!decoded[n.mesh]) {
                auto p = detail::decodeStream(scene, n.mesh, VertexSemantic::Position, true);
                if (!p) return p.error();
                positions[n.mesh] = std::move(*p);
                for (int set = 0; set < 2; ++set) {
                    auto uv = detail::decodeStream(scene, n.mesh,
                                                   set ? VertexSemantic::TexCoord1 : VertexSemantic::TexCoord0, false);
                    if (!uv) return uv.error();
                    uvs[set][n.mesh] = std::move(*uv);
                }
                auto c = detail::decodeStream(scene, n.mesh, VertexSemantic::Color0, false);
                if (!c) return c.error();
                colors[n.mesh] = std::move(*c);
                decoded[n.mesh] = true;
            }
            Instance inst;
            inst.material = sm.material;
            const uint64_t end = uint64_t(sm.firstIndex) + sm.indexCount / 3 * 3;
            for (uint64_t k = sm.firstIndex; k < end; ++k) inst.indices.push_back(detail::readIndex(mesh, k));
            if (inst.indices.empty()) continue;
            const auto& pos = positions[n.mesh];
            const auto& uvSet = uvs[std::min<int>(m.textures[size_t(TextureSlotKind::BaseColor)].texCoord, 1)][n.mesh];
            for (const glm::dvec4& u : uvSet) inst.uv.push_back(glm::vec2(u));
            for (const glm::dvec4& c : colors[n.mesh]) inst.color.push_back(glm::vec3(c));

            RTCGeometry geometry = rtcNewGeometry(impl.device, RTC_GEOMETRY_TYPE_TRIANGLE);
            auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
                geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), pos.size()));
            auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
                geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), inst.indices.size() / 3));
            if (!vertices || !indices) {
                rtcReleaseGeometry(geometry);
                return TracerError{TracerErrorKind::Embree, "Embree: allocating geometry buffers failed"};
            }
            std::vector<double> magnitude(pos.size());
            for (size_t v = 0; v < pos.size(); ++v) {
                glm::dvec3 ws = glm::dvec3(world * glm::dvec4(glm::dvec3(pos[v]), 1.0));
                glm::dvec3 rel = ws - origin;
                vertices[v * 3] = float(rel.x), vertices[v * 3 + 1] = float(rel.y), vertices[v * 3 + 2] = float(rel.z);
                magnitude[v] = glm::length(rel);
                impl.worldBand = std::max(impl.worldBand, kWorldRelativeError * glm::length(ws));
            }
            std::memcpy(indices, inst.indices.data(), inst.indices.size() * sizeof(uint32_t));
            auto tolerance = std::make_unique<std::vector<float>>(inst.indices.size() / 3);
            for (size_t t = 0; t < tolerance->size(); ++t)
                (*tolerance)[t] = float(kVertexRelativeError * std::max({magnitude[inst.indices[t * 3]],
                                                                         magnitude[inst.indices[t * 3 + 1]],
                                                                         magnitude[inst.indices[t * 3 + 2]]}));
            rtcSetGeometryUserData(geometry, tolerance.get());
            rtcSetGeometryIntersectFilterFunction(geometry, detail::rejectOwnSurface);
            rtcCommitGeometry(geometry);
            unsigned id = rtcAttachGeometry(impl.scene, geometry);
            rtcReleaseGeometry(geometry);
            if (impl.instances.size() <= id) impl.instances.resize(id + 1);
            stats.triangles += inst.indices.size() / 3;
            impl.instances[id] = std::move(inst);
            impl.tolerances.push_back(std::move(tolerance));
            ++stats.instances;
        }
    }
    if (impl.sun < 0) impl.sun = firstDirectional;
    stats.lights = uint32_t(impl.lights.size());
    rtcCommitScene(impl.scene);
    if (rtcGetDeviceError(impl.device) != RTC_ERROR_NONE)
        return TracerError{TracerErrorKind::Embree, "Embree: building the reflector scene failed"};
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
    const size_t batch = std::max<size_t>(1, (1u << 18) / samples); // points per batch
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());

    std::vector<glm::vec3> hitPosition, hitNormal, hitAlbedo;
    std::vector<float> visibility;
    std::vector<glm::vec3> contribution;
    for (size_t first = 0; first < count; first += batch) {
        const size_t points = std::min(batch, count - first);
        const size_t rays = points * samples;
        hitPosition.assign(rays, nan);
        hitNormal.assign(rays, glm::vec3(0.0f));
        hitAlbedo.assign(rays, glm::vec3(0.0f));
        // 1. The first surface along each cosine-weighted direction, and its albedo there.
        std::atomic<size_t> next{0};
        auto worker = [&] {
            detail::TraceContext context;
            rtcInitIntersectContext(&context.embree);
            context.eye = eye;
            context.fixedBand = kVertexRelativeError * glm::length(eye) + impl.worldBand;
            for (size_t i = next.fetch_add(1); i < points; i = next.fetch_add(1)) {
                const size_t point = first + i;
                const glm::vec3 p = positions[point], n = normals[point];
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
                    !(glm::length(n) > 0.0f) || !std::isfinite(n.x + n.y + n.z))
                    continue;
                const glm::vec3 nn = glm::normalize(n);
                glm::vec3 t, b;
                basis(nn, t, b);
                const float tnear = float(kPointRelativeError * glm::length(glm::dvec3(p) - eye));
                for (uint32_t s = 0; s < samples; ++s) {
                    uint64_t h = mix(mix(settings.seed ^ (uint64_t(point) << 20)) ^ s);
                    float u1 = unit(h), u2 = unit(mix(h));
                    float r = std::sqrt(u1), phi = float(2.0 * kPi) * u2;
                    glm::vec3 dir = glm::normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) +
                                                   nn * std::sqrt(std::max(0.0f, 1.0f - u1)));
                    RTCRayHit rh;
                    rh.ray.org_x = p.x, rh.ray.org_y = p.y, rh.ray.org_z = p.z;
                    rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
                    rh.ray.tnear = tnear;
                    rh.ray.tfar = std::numeric_limits<float>::infinity();
                    rh.ray.time = 0, rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(impl.scene, &context.embree, &rh);
                    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue; // black sky
                    const Instance& inst = impl.instances[rh.hit.geomID];
                    const MaterialInfo& m = impl.materials[inst.material];
                    const size_t k = i * samples + s;
                    glm::vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
                    if (!(glm::length(ng) > 0.0f)) continue;
                    ng = glm::normalize(ng);
                    if (glm::dot(ng, dir) > 0.0f) ng = -ng; // the side the ray arrives on
                    hitPosition[k] = p + dir * rh.ray.tfar;
                    hitNormal[k] = ng;
                    const float w = 1.0f - rh.hit.u - rh.hit.v;
                    const uint32_t* tri = &inst.indices[size_t(rh.hit.primID) * 3];
                    glm::vec3 albedo = m.albedo;
                    if (!inst.color.empty())
                        albedo *= inst.color[tri[0]] * w + inst.color[tri[1]] * rh.hit.u + inst.color[tri[2]] * rh.hit.v;
                    if (m.texture >= 0 && !inst.uv.empty()) {
                        glm::vec2 uv = inst.uv[tri[0]] * w + inst.uv[tri[1]] * rh.hit.u + inst.uv[tri[2]] * rh.hit.v;
                        // KHR_texture_transform as material.glsl's slotUv: rotate(scale * uv) + offset.
                        float c = std::cos(m.rotation), sn = std::sin(m.rotation);
                        glm::vec2 su(uv.x * m.scale[0], uv.y * m.scale[1]);
                        uv = glm::vec2(c * su.x - sn * su.y, sn * su.x + c * su.y) + glm::vec2(m.offset[0], m.offset[1]);
                        albedo *= glm::vec3(impl.textures[size_t(m.texture)].sample(uv));
                    }
                    hitAlbedo[k] = albedo;
                }
            }
        };
        std::vector<std::thread> pool;
        for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
        worker();
        for (std::thread& t : pool) t.join();

        // 2. Direct irradiance at every hit from each light, with shadow rays (batched: the
        //    shadow tracer parallelises each call).
        contribution.assign(rays, glm::vec3(0.0f));
        visibility.resize(rays);
        for (int li : lights) {
            const LightInfo& l = impl.lights[size_t(li)];
            if (l.type == LightType::Directional)
                impl.shadows->visibility(hitPosition, l.toward, visibility, eye);
            else
                impl.shadows->visibilityToPoint(hitPosition, l.position, visibility, eye);
            for (size_t k = 0; k < rays; ++k) {
                if (!(visibility[k] > 0.0f)) continue;
                glm::vec3 toLight = l.toward;
                float attenuation = 1.0f;
                if (l.type != LightType::Directional) {
                    glm::vec3 d = l.position - hitPosition[k];
                    float d2 = glm::dot(d, d);
                    toLight = d2 > 0.0f ? d / std::sqrt(d2) : glm::vec3(0, 0, 1);
                    attenuation = rangeAttenuation(d2, l.range);
                    if (l.type == LightType::Spot) {
                        float cd = glm::dot(l.travel, -toLight);
                        float t = std::clamp((cd - l.cosOuter) * l.coneScale, 0.0f, 1.0f);
                        attenuation *= t * t;
                    }
                }
                float cosine = std::max(0.0f, glm::dot(hitNormal[k], toLight));
                contribution[k] += hitAlbedo[k] * l.radiance * (attenuation * cosine);
            }
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

} // namespace pnb::reference
