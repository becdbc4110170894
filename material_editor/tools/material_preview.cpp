#include "material_preview.h"

#include <cmath>
#include <cstring>

namespace pnb::editor {

namespace {

template <class T> Blob blobOf(std::vector<std::vector<std::byte>>& storage, const std::vector<T>& v) {
    storage.emplace_back(v.size() * sizeof(T));
    std::memcpy(storage.back().data(), v.data(), storage.back().size());
    return {storage.back().data(), storage.back().size()};
}

} // namespace

player::PlayResult<player::Done> MaterialPreview::refresh(const Scene& doc, uint32_t material) {
    const Material& now = doc.materials[material];
    bool sameTextures = true;
    for (size_t i = 0; i < now.textures.size(); ++i)
        sameTextures &= now.textures[i].texture == mShown.textures[i].texture;
    if (!mGpu || material != mMaterial || !sameTextures || now.program != mShown.program ||
        doc.programs.size() != mScene.programs.size())
        return show(doc, material);
    // Same textures and program: copy the values, keep the preview's texture numbering.
    Material m = now;
    m.name = mScene.materials[0].name;
    for (size_t i = 0; i < m.textures.size(); ++i) m.textures[i].texture = mScene.materials[0].textures[i].texture;
    mScene.materials[0] = m;
    mShown = now;
    mRenderedSize = 0;
    return player::updateMaterials(*mGpu, mScene);
}

void MaterialPreview::clear() {
    mRenderer.reset();
    mGpu.reset();
    mScene = Scene{};
    mStorage.clear();
    mMaterial = kNone;
    mRenderedSize = 0;
}

player::PlayResult<player::Done> MaterialPreview::show(const Scene& doc, uint32_t material) {
    mMaterial = material;
    mShown = doc.materials[material];
    mRenderedSize = 0;
    mRenderer.reset();
    mGpu.reset();
    mStorage.clear();
    mStrings = {"preview", "sphere", "sun"};
    mScene = Scene{};
    for (const std::string& s : mStrings) mScene.strings.strings.push_back(s);
    // The document's shaders and programs, as they are: the preview uses the same permutations.
    auto strOffset = uint32_t(mScene.strings.strings.size());
    for (std::string_view s : doc.strings.strings) mScene.strings.strings.push_back(s);
    auto shift = [&](StringRef r) { return r == kNone ? kNone : r + strOffset; };
    for (ShaderSource s : doc.shaders) {
        s.name = shift(s.name);
        mScene.shaders.push_back(s);
    }
    for (Program p : doc.programs) {
        p.name = shift(p.name);
        for (StringRef& d : p.defines) d = shift(d);
        mScene.programs.push_back(p);
    }
    // Only the material's own textures, renumbered.
    Material m = doc.materials[material];
    m.name = shift(m.name);
    for (TextureSlot& slot : m.textures) {
        if (slot.texture == kNone) continue;
        uint32_t original = slot.texture;
        slot.texture = uint32_t(mScene.textures.size());
        TextureDesc d = doc.textures[original];
        d.name = shift(d.name);
        mScene.textures.push_back(d);
        for (TextureMip mip : doc.textureMips)
            if (mip.texture == original) {
                mip.texture = slot.texture;
                mScene.textureMips.push_back(mip);
            }
    }
    mScene.materials.push_back(m);

    // A UV sphere of radius 1 with tangents, so every permutation finds its streams.
    const int rings = 32, segments = 64;
    std::vector<float> pos, nrm, uv, tan;
    std::vector<uint32_t> idx;
    for (int r = 0; r <= rings; ++r) {
        float v = float(r) / rings, theta = v * 3.14159265f;
        for (int s = 0; s <= segments; ++s) {
            float u = float(s) / segments, phi = u * 6.2831853f;
            float x = std::sin(theta) * std::cos(phi), y = std::cos(theta), z = -std::sin(theta) * std::sin(phi);
            pos.insert(pos.end(), {x, y, z});
            nrm.insert(nrm.end(), {x, y, z});
            uv.insert(uv.end(), {u * 2.0f, v});
            tan.insert(tan.end(), {-std::sin(phi), 0.0f, -std::cos(phi), 1.0f});
        }
    }
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            uint32_t a = uint32_t(r * (segments + 1) + s), b = a + uint32_t(segments + 1);
            idx.insert(idx.end(), {a, b, a + 1, a + 1, b, b + 1});
        }
    Mesh mesh;
    mesh.name = 1;
    mesh.vertexCount = uint32_t(pos.size() / 3);
    auto stream = [&](VertexSemantic sem, uint8_t n, const std::vector<float>& data) {
        VertexStream vs;
        vs.semantic = sem;
        vs.componentCount = n;
        vs.data = blobOf(mStorage, data);
        mesh.streams.push_back(vs);
    };
    stream(VertexSemantic::Position, 3, pos);
    stream(VertexSemantic::Normal, 3, nrm);
    stream(VertexSemantic::Tangent, 4, tan);
    stream(VertexSemantic::TexCoord0, 2, uv);
    stream(VertexSemantic::TexCoord1, 2, uv);
    mesh.indices = blobOf(mStorage, idx);
    Submesh sm;
    sm.material = 0;
    sm.indexCount = uint32_t(idx.size());
    sm.bounds.min = {-1, -1, -1};
    sm.bounds.max = {1, 1, 1};
    mesh.submeshes.push_back(sm);
    mesh.bounds = sm.bounds;
    mesh.boundingSphere.radius = 1;
    mScene.meshes.push_back(mesh);
    mScene.info.name = 0;
    mScene.info.bounds = sm.bounds;

    Light sun;
    sun.name = 2;
    sun.intensity = 3;
    mScene.lights.lights.push_back(sun);
    Node sphere;
    sphere.name = 1;
    sphere.mesh = 0;
    sphere.worldBounds = sm.bounds;
    sphere.worldSphere.radius = 1;
    Node light;
    light.name = 2;
    light.light = 0;
    glm::quat q = glm::quatLookAt(glm::normalize(glm::vec3(-0.5f, -0.8f, -0.6f)), glm::vec3(0, 1, 0));
    light.rotation = {q.x, q.y, q.z, q.w};
    mScene.nodes.nodes = {sphere, light};

    if (Status s = validateScene(mScene); !isOk(s)) return player::inputError(s);
    auto gpu = player::uploadScene(mScene);
    if (!gpu) return gpu.error();
    mGpu = std::move(*gpu);
    player::RenderSettings settings = player::settingsForCurrentDriver();
    settings.ambient = 0.1f;
    auto renderer = player::Renderer::create(*mGpu, settings);
    if (!renderer) return renderer.error();
    mRenderer = std::move(*renderer);
    return player::Done{};
}

GLuint MaterialPreview::render(uint32_t size) {
    if (!mRenderer) return 0;
    if (mRenderedSize == size) return mRenderer->outputTexture(); // nothing changed
    player::CameraState cam;
    cam.position = {0, 0.6, 3.2};
    cam.rotation = glm::quatLookAt(glm::normalize(-cam.position), glm::dvec3(0, 1, 0));
    cam.yfovRadians = 0.7f;
    cam.znear = 0.05f;
    if (!mRenderer->render(cam, size, size)) return 0;
    mRenderedSize = size;
    mRenderer->timer().completed().clear();
    return mRenderer->outputTexture();
}

} // namespace pnb::editor
