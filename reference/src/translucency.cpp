// Light through blended surfaces (translucency.h).
#include "translucency.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "mesh_decode.h"
#include "pnb/texture_transform.h"

namespace pnb::reference::detail {

glm::vec3 transmittanceOf(glm::vec4 baseColor) {
    const float opacity = std::clamp(baseColor.a, 0.0f, 1.0f);
    return glm::clamp(glm::vec3(baseColor) * (1.0f - opacity), glm::vec3(0.0f), glm::vec3(1.0f));
}

std::optional<TracerError> TranslucentSurfaces::add(const Scene& scene, unsigned geometryId, uint32_t mesh,
                                                    const Submesh& submesh, std::vector<uint32_t> indices) {
    const Material& m = scene.materials[submesh.material];
    const TextureSlot& slot = m.textures[size_t(TextureSlotKind::BaseColor)];
    Surface s;
    s.factor = glm::vec4(m.baseColorFactor.x, m.baseColorFactor.y, m.baseColorFactor.z, m.baseColorFactor.w);
    s.slot = slot;
    s.indices = std::move(indices);
    if (slot.texture != kNone && slot.texture < scene.textures.size()) {
        if (mTextureOfScene.size() != scene.textures.size()) mTextureOfScene.assign(scene.textures.size(), -2);
        int& t = mTextureOfScene[slot.texture];
        if (t == -2) {
            auto decoded = decodeTexture(scene, slot.texture);
            t = decoded ? int(mTextures.size()) : -1;
            if (decoded) mTextures.push_back(std::move(*decoded));
            else ++mTexturesFactorOnly;
        }
        s.texture = t;
    }
    if (s.texture >= 0) { // the UV set the texture is read with, decoded once per mesh and set
        const uint64_t key = uint64_t(mesh) * 2 + std::min<uint64_t>(slot.texCoord, 1);
        auto it = std::find_if(mUvOfMeshSet.begin(), mUvOfMeshSet.end(), [&](const auto& e) { return e.first == key; });
        if (it == mUvOfMeshSet.end()) {
            auto uv = decodeStream(scene, mesh, key % 2 ? VertexSemantic::TexCoord1 : VertexSemantic::TexCoord0, false);
            if (!uv) return uv.error();
            auto kept = std::make_unique<std::vector<glm::vec2>>();
            for (const glm::dvec4& u : *uv) kept->push_back(glm::vec2(u));
            mUvOfMeshSet.emplace_back(key, kept.get());
            mUvs.push_back(std::move(kept));
            it = mUvOfMeshSet.end() - 1;
        }
        s.uv = it->second;
    }
    if (mSurfaceOfGeometry.size() <= geometryId) mSurfaceOfGeometry.resize(size_t(geometryId) + 1, -1);
    mSurfaceOfGeometry[geometryId] = int(mSurfaces.size());
    mSurfaces.push_back(std::move(s));
    return std::nullopt;
}

glm::vec3 TranslucentSurfaces::transmittance(const TranslucentHit& hit) const {
    if (hit.geometry >= mSurfaceOfGeometry.size() || mSurfaceOfGeometry[hit.geometry] < 0) return glm::vec3(1.0f);
    const Surface& s = mSurfaces[size_t(mSurfaceOfGeometry[hit.geometry])];
    glm::vec4 color = s.factor;
    // Without a UV stream the texture is read at (0, 0), as the GPU's vertex fetch of a missing
    // attribute gives.
    if (s.texture >= 0 && size_t(hit.primitive) * 3 + 2 < s.indices.size()) {
        glm::vec2 uv(0.0f);
        if (s.uv && !s.uv->empty()) {
            const uint32_t* tri = &s.indices[size_t(hit.primitive) * 3];
            const std::vector<glm::vec2>& uvs = *s.uv;
            uv = uvs[tri[0]] * (1.0f - hit.u - hit.v) + uvs[tri[1]] * hit.u + uvs[tri[2]] * hit.v;
        }
        const Vec2 t = textureTransformUv(s.slot, Vec2{uv.x, uv.y});
        color *= mTextures[size_t(s.texture)].sample(glm::vec2(t.x, t.y));
    }
    return transmittanceOf(color);
}

glm::vec3 TranslucentSurfaces::product(std::vector<TranslucentHit>& hits, float tMax) const {
    std::sort(hits.begin(), hits.end(), [](const TranslucentHit& a, const TranslucentHit& b) {
        return std::tie(a.geometry, a.t, a.primitive) < std::tie(b.geometry, b.t, b.primitive);
    });
    glm::vec3 t(1.0f);
    const TranslucentHit* counted = nullptr; // the last crossing multiplied in
    for (const TranslucentHit& hit : hits) {
        if (!(hit.t < tMax)) continue;
        // One crossing of one surface: the same triangle offered again, or the neighbouring
        // triangle where the ray passes through their shared edge (a quad's diagonal, a box's
        // crease), at the same distance up to the point's own error band (kPointRelativeError,
        // relative: no constant in scene units).
        if (counted && counted->geometry == hit.geometry &&
            double(hit.t) - double(counted->t) <= kPointRelativeError * std::fabs(double(hit.t)))
            continue;
        t *= transmittance(hit);
        counted = &hit;
    }
    return t;
}

} // namespace pnb::reference::detail
