// The whole-frame tracer's scene: geometry, materials, lights, environment (frame_scene.h).
#include "frame_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "mesh_decode.h"
#include "placed_lights.h"
#include "pnb/texture_transform.h"
#include "translucency.h"

namespace pnb::reference::detail {

namespace {

template <class T, class F> std::vector<T> convert(const std::vector<glm::dvec4>& in, F&& f) {
    std::vector<T> out;
    out.reserve(in.size());
    for (const glm::dvec4& v : in) out.push_back(f(v));
    return out;
}

// A stream the tracer can do without (normals, tangents): absent or octahedral-encoded gives an
// empty vector (flat normals / the player's default tangent), other errors stop the build.
TracerResult<std::vector<glm::dvec4>> optionalStream(const Scene& scene, uint32_t mesh, VertexSemantic s,
                                                     bool& unsupported) {
    auto decoded = decodeStream(scene, mesh, s, false);
    if (!decoded && decoded.error().kind == TracerErrorKind::Unsupported) {
        unsupported = true;
        return std::vector<glm::dvec4>{};
    }
    return decoded;
}

} // namespace

TracerResult<std::unique_ptr<FrameScene>> FrameScene::build(const Scene& scene, glm::dvec3 origin,
                                                            const FramePose& at, FrameStats& stats) {
    auto out = std::make_unique<FrameScene>();
    out->mOrigin = origin;
    auto posed = PosedScene::make(scene, at); // the instant traced: geometry and lights
    if (!posed) return posed.error();

    // Materials, each texture decoded once (block-compressed ones: the factor alone, counted).
    std::vector<int> decodedTexture(scene.textures.size(), -2); // -2 not tried, -1 undecodable
    for (const Material& m : scene.materials) {
        MaterialInfo info;
        info.baseColor = glm::vec4(m.baseColorFactor.x, m.baseColorFactor.y, m.baseColorFactor.z, m.baseColorFactor.w);
        info.metallic = m.metallicFactor;
        info.roughness = m.roughnessFactor;
        info.normalScale = m.normalScale;
        info.alphaCutoff = m.alphaCutoff;
        info.emissive = glm::vec3(m.emissiveFactor.x, m.emissiveFactor.y, m.emissiveFactor.z) * m.emissiveStrength;
        info.alphaMode = m.alphaMode;
        info.doubleSided = m.doubleSided;
        info.unlit = m.unlit;
        info.castsShadows = m.castsShadows;
        for (size_t k = 0; k < size_t(TextureSlotKind::Count); ++k) {
            const TextureSlot& slot = m.textures[k];
            info.slots[k].transform = slot;
            // The occlusion texture is not applied: a path tracer computes occlusion.
            if (k == size_t(TextureSlotKind::Occlusion) || slot.texture == kNone || slot.texture >= scene.textures.size())
                continue;
            int& t = decodedTexture[slot.texture];
            if (t == -2) {
                auto decoded = decodeTexture(scene, slot.texture);
                t = decoded ? int(out->mTextures.size()) : -1;
                if (decoded) out->mTextures.push_back(std::move(*decoded));
                else ++stats.texturesFactorOnly;
            }
            info.slots[k].texture = t;
        }
        out->mMaterials.push_back(info);
    }
    stats.textures = uint32_t(out->mTextures.size());

    // Lights, as every tracer places them (placed_lights.h).
    out->mLights = placeLights(scene, posed->world(), origin);
    stats.lights = uint32_t(out->mLights.size());

    // The environment's radiance image (as SkyTracer reads it): wraps in azimuth, clamps at the poles.
    if (scene.environment && scene.environment->radiance < scene.textures.size()) {
        const TextureDesc& d = scene.textures[scene.environment->radiance];
        if (d.dimension == TextureDimension::Tex2D &&
            (d.format == TextureFormat::RGBA16F || d.format == TextureFormat::RGBA32F))
            if (auto decoded = decodeTexture(scene, scene.environment->radiance)) {
                decoded->wrapU = Wrap::Repeat;
                decoded->wrapV = Wrap::ClampToEdge;
                out->mEnvironment.emplace(std::move(*decoded));
            }
    }
    stats.environment = out->mEnvironment.has_value();

    // Geometry: every level-0 surface, Blend included; per mesh what shading reads, per node for
    // a deformed one (its own positions, normals and tangents, in its drawing space).
    std::vector<int> meshSlot(scene.meshes.size(), -1), deformedSlot(scene.nodes.nodes.size(), -1);
    std::vector<std::pair<unsigned, Instance>> placed;
    auto triangles = buildTriangleScene(
        scene, *posed, origin,
        [&](unsigned id, uint32_t node, uint32_t mesh, const Submesh& sm,
            std::vector<uint32_t>&& indices) -> std::optional<TracerError> {
            const DeformedVertices* deformed = posed->deformed(node);
            int& slot = deformed ? deformedSlot[node] : meshSlot[mesh];
            if (slot < 0) {
                Mesh m;
                bool flat = false;
                if (deformed) {
                    for (const Vec3& v : deformed->positions) m.position.emplace_back(v.x, v.y, v.z);
                    for (const Vec3& v : deformed->normals) m.normal.emplace_back(v.x, v.y, v.z);
                    for (const Vec4& v : deformed->tangents) m.tangent.emplace_back(v.x, v.y, v.z, v.w);
                } else {
                    auto p = decodeStream(scene, mesh, VertexSemantic::Position, true);
                    if (!p) return p.error();
                    m.position = convert<glm::vec3>(*p, [](const glm::dvec4& v) { return glm::vec3(v); });
                    auto nrm = optionalStream(scene, mesh, VertexSemantic::Normal, flat);
                    if (!nrm) return nrm.error();
                    m.normal = convert<glm::vec3>(*nrm, [](const glm::dvec4& v) { return glm::vec3(v); });
                    bool ignored = false;
                    auto tan = optionalStream(scene, mesh, VertexSemantic::Tangent, ignored);
                    if (!tan) return tan.error();
                    m.tangent = convert<glm::vec4>(*tan, [](const glm::dvec4& v) { return glm::vec4(v); });
                }
                if (m.normal.empty()) flat = true;
                stats.meshesWithoutNormals += flat;
                for (int set = 0; set < 2; ++set) {
                    auto uv = decodeStream(scene, mesh, set ? VertexSemantic::TexCoord1 : VertexSemantic::TexCoord0, false);
                    if (!uv) return uv.error();
                    m.uv[size_t(set)] = convert<glm::vec2>(*uv, [](const glm::dvec4& v) { return glm::vec2(v); });
                }
                auto c = decodeStream(scene, mesh, VertexSemantic::Color0, false);
                if (!c) return c.error();
                m.color = convert<glm::vec4>(*c, [](const glm::dvec4& v) { return glm::vec4(v); });
                slot = int(out->mMeshes.size());
                out->mMeshes.push_back(std::move(m));
            }
            Instance inst;
            inst.material = sm.material;
            inst.mesh = uint32_t(slot);
            inst.indices = std::move(indices);
            placed.emplace_back(id, std::move(inst));
            return std::nullopt;
        },
        BlendSurfaces::Opaque);
    if (!triangles) return triangles.error();
    out->mScene = std::move(*triangles);
    for (auto& [id, inst] : placed) {
        const glm::dmat3 model(out->mScene->worldOfGeometry[id]);
        inst.model = glm::mat3(model);
        inst.normalMatrix = glm::mat3(glm::transpose(glm::inverse(model)));
        inst.mirror = glm::determinant(model) < 0.0 ? -1.0f : 1.0f;
        if (out->mInstances.size() <= id) out->mInstances.resize(id + 1);
        out->mInstances[id] = std::move(inst);
    }
    stats.triangles = out->mScene->triangles;
    stats.instances = out->mScene->instances;
    return out;
}

TraceContext FrameScene::context(glm::dvec3 eye) const {
    TraceContext context;
    rtcInitIntersectContext(&context.embree);
    context.eye = eye;
    context.fixedBand = kVertexRelativeError * glm::length(eye) + mScene->worldBand;
    return context;
}

glm::vec4 FrameScene::sampleSlot(const MaterialInfo& m, TextureSlotKind kind, const glm::vec2 uv[2],
                                 glm::vec4 otherwise) const {
    const Slot& slot = m.slots[size_t(kind)];
    if (slot.texture < 0) return otherwise;
    const glm::vec2 in = uv[std::min<int>(slot.transform.texCoord, 1)];
    const Vec2 t = textureTransformUv(slot.transform, Vec2{in.x, in.y});
    return mTextures[size_t(slot.texture)].sample(glm::vec2(t.x, t.y));
}

FrameScene::HitPoint FrameScene::hitPoint(const RTCRayHit& rh, glm::vec3 dir, float bary[3], glm::vec2 uv[2]) const {
    HitPoint h;
    h.instance = &mInstances[rh.hit.geomID];
    h.material = &mMaterials[h.instance->material];
    const Mesh& mesh = mMeshes[h.instance->mesh];
    const uint32_t* tri = &h.instance->indices[size_t(rh.hit.primID) * 3];
    bary[0] = 1.0f - rh.hit.u - rh.hit.v, bary[1] = rh.hit.u, bary[2] = rh.hit.v;
    for (int set = 0; set < 2; ++set) {
        const auto& s = mesh.uv[size_t(set)];
        uv[set] = s.empty() ? glm::vec2(0.0f) : s[tri[0]] * bary[0] + s[tri[1]] * bary[1] + s[tri[2]] * bary[2];
    }
    glm::vec4 color(1.0f);
    if (!mesh.color.empty())
        color = mesh.color[tri[0]] * bary[0] + mesh.color[tri[1]] * bary[1] + mesh.color[tri[2]] * bary[2];
    h.baseColor = h.material->baseColor * color * sampleSlot(*h.material, TextureSlotKind::BaseColor, uv, glm::vec4(1.0f));
    // The front face is the counter-clockwise side (glTF), whatever the placement: the normal
    // matrix carries the object's winding normal to the world's side the player calls front.
    const glm::vec3 p0 = mesh.position[tri[0]], p1 = mesh.position[tri[1]], p2 = mesh.position[tri[2]];
    const glm::vec3 front = h.instance->normalMatrix * glm::cross(p1 - p0, p2 - p0);
    h.frontFacing = glm::dot(front, dir) < 0.0f;
    return h;
}

FrameSurface FrameScene::shade(const HitPoint& hit, const RTCRayHit& rh, glm::vec3 org, glm::vec3 dir,
                               const float bary[3], const glm::vec2 uv[2]) const {
    const MaterialInfo& m = *hit.material;
    const Instance& inst = *hit.instance;
    const Mesh& mesh = mMeshes[inst.mesh];
    const uint32_t* tri = &inst.indices[size_t(rh.hit.primID) * 3];
    FrameSurface s;
    s.distance = rh.ray.tfar;
    s.position = org + dir * rh.ray.tfar;
    const glm::vec3 p0 = mesh.position[tri[0]], p1 = mesh.position[tri[1]], p2 = mesh.position[tri[2]];
    glm::vec3 g = inst.normalMatrix * glm::cross(p1 - p0, p2 - p0);
    g = glm::length(g) > 0.0f ? glm::normalize(g) : -dir;
    if (glm::dot(g, dir) > 0.0f) g = -g;
    s.geometric = g;
    glm::vec3 n = g;
    if (!mesh.normal.empty()) {
        const glm::vec3 interpolated = inst.normalMatrix * (mesh.normal[tri[0]] * bary[0] + mesh.normal[tri[1]] * bary[1] +
                                                            mesh.normal[tri[2]] * bary[2]);
        if (glm::length(interpolated) > 0.0f) n = glm::normalize(interpolated) * (hit.frontFacing ? 1.0f : -1.0f);
    }
    if (m.slots[size_t(TextureSlotKind::Normal)].texture >= 0) {
        // material.glsl's normal mapping, with surface.vert's tangent (model x xyz, w x mirror)
        // or its default (+X, +1) where the mesh has none.
        glm::vec4 tangent(1.0f, 0.0f, 0.0f, 1.0f);
        if (!mesh.tangent.empty()) {
            const glm::vec4 tl = mesh.tangent[tri[0]] * bary[0] + mesh.tangent[tri[1]] * bary[1] + mesh.tangent[tri[2]] * bary[2];
            tangent = glm::vec4(inst.model * glm::vec3(tl), mesh.tangent[tri[0]].w * inst.mirror);
        }
        glm::vec3 t = glm::vec3(tangent) - n * glm::dot(n, glm::vec3(tangent));
        if (glm::length(t) > 0.0f) {
            t = glm::normalize(t);
            glm::vec3 b = glm::cross(n, t) * (tangent.w < 0.0f ? -1.0f : 1.0f);
            const float rn = m.slots[size_t(TextureSlotKind::Normal)].transform.rotationRadians;
            if (rn != 0.0f) {
                const float cr = std::cos(rn), sr = std::sin(rn);
                const glm::vec3 tr = cr * t - sr * b;
                b = sr * t + cr * b;
                t = tr;
            }
            glm::vec3 tn = glm::vec3(sampleSlot(m, TextureSlotKind::Normal, uv, glm::vec4(0.5f, 0.5f, 1.0f, 1.0f))) * 2.0f - 1.0f;
            tn.x *= m.normalScale, tn.y *= m.normalScale;
            const glm::vec3 mapped = glm::mat3(t, b, n) * tn;
            if (glm::length(mapped) > 0.0f) n = glm::normalize(mapped);
        }
    }
    s.normal = n;
    s.baseColor = glm::vec3(hit.baseColor);
    const glm::vec4 mr = sampleSlot(m, TextureSlotKind::MetallicRoughness, uv, glm::vec4(1.0f));
    s.roughness = std::clamp(m.roughness * mr.g, 0.03f, 1.0f); // material.glsl's clamp
    s.metallic = std::clamp(m.metallic * mr.b, 0.0f, 1.0f);
    s.emissive = m.emissive * glm::vec3(sampleSlot(m, TextureSlotKind::Emissive, uv, glm::vec4(1.0f)));
    s.unlit = m.unlit;
    return s;
}

namespace {

RTCRayHit makeRay(glm::vec3 org, glm::vec3 dir, float tnear, float tfar) {
    RTCRayHit rh;
    rh.ray.org_x = org.x, rh.ray.org_y = org.y, rh.ray.org_z = org.z;
    rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.time = 0, rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

// More surfaces passed than this along one ray ends it (a pathological stack of holes).
constexpr int kMaxPassed = 256;

} // namespace

std::optional<FrameSurface> FrameScene::trace(TraceContext& context, glm::vec3 org, glm::vec3 dir, float tnear,
                                              FrameRandom& rng, uint64_t& rays) const {
    context.lightBand = -1;
    context.translucentHits = nullptr;
    for (int passed = 0; passed < kMaxPassed; ++passed) {
        RTCRayHit rh = makeRay(org, dir, tnear, std::numeric_limits<float>::infinity());
        rtcIntersect1(mScene->scene, &context.embree, &rh);
        ++rays;
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.geomID >= mInstances.size()) return std::nullopt;
        float bary[3];
        glm::vec2 uv[2];
        const HitPoint hit = hitPoint(rh, dir, bary, uv);
        const MaterialInfo& m = *hit.material;
        bool pass = !m.doubleSided && !hit.frontFacing; // culled, as the player culls it
        if (!pass && m.alphaMode == AlphaMode::Mask) pass = hit.baseColor.a < m.alphaCutoff;
        if (!pass && m.alphaMode == AlphaMode::Blend) pass = rng.next() >= std::clamp(hit.baseColor.a, 0.0f, 1.0f);
        if (!pass) return shade(hit, rh, org, dir, bary, uv);
        // Go on from the surface passed: the own-surface filter keeps it from being met again.
        org = org + dir * rh.ray.tfar;
        tnear = float(kPointRelativeError * glm::length(glm::dvec3(org) - context.eye));
    }
    return std::nullopt;
}

glm::vec3 FrameScene::transmittance(TraceContext& context, glm::vec3 org, glm::vec3 dir, float tnear, bool toPoint,
                                    double lightBand, uint64_t& rays) const {
    context.translucentHits = nullptr;
    context.lightBand = toPoint ? lightBand : -1.0;
    const glm::vec3 light = org + dir; // toPoint only
    glm::vec3 through(1.0f);
    for (int passed = 0; passed < kMaxPassed; ++passed) {
        const float length = glm::length(dir);
        if (!(length > 0.0f)) return through;
        const float tfar = toPoint ? float(1.0 - lightBand / double(length)) : std::numeric_limits<float>::infinity();
        if (!(tfar > tnear)) return through;
        RTCRayHit rh = makeRay(org, dir, tnear, tfar);
        rtcIntersect1(mScene->scene, &context.embree, &rh);
        ++rays;
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.geomID >= mInstances.size()) return through;
        float bary[3];
        glm::vec2 uv[2];
        const HitPoint hit = hitPoint(rh, dir, bary, uv);
        const MaterialInfo& m = *hit.material;
        if (m.castsShadows) {
            if (m.alphaMode == AlphaMode::Opaque) return glm::vec3(0.0f);
            if (m.alphaMode == AlphaMode::Mask && hit.baseColor.a >= m.alphaCutoff) return glm::vec3(0.0f);
            if (m.alphaMode == AlphaMode::Blend) through *= transmittanceOf(hit.baseColor);
            if (!(through.x > 0.0f || through.y > 0.0f || through.z > 0.0f)) return glm::vec3(0.0f);
        }
        org = org + dir * rh.ray.tfar;
        if (toPoint) dir = light - org;
        const double band = kPointRelativeError * glm::length(glm::dvec3(org) - context.eye);
        tnear = float(toPoint ? band / std::max(double(glm::length(dir)), 1e-30) : band);
    }
    return through;
}

} // namespace pnb::reference::detail
