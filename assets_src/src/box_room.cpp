// The bundled box-room scene (see box_room.h).

#include "pnb_assets/box_room.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "sample_shaders.h" // generated from shaders/sample/ at build time

namespace pnb::assets {

namespace {

struct MeshData {
    std::vector<float> positions, normals, uvs;
    std::vector<uint32_t> indices;
    std::vector<Submesh> submeshes;
};

Vec3 add(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 mul(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// A planar grid of n x n quads at `origin` spanning edges u and v; the face normal is u x v
// (counter-clockwise winding seen from the front).
void addQuad(MeshData& m, Vec3 origin, Vec3 u, Vec3 v, uint32_t n, Aabb& bounds) {
    Vec3 normal = cross(u, v);
    float len = std::sqrt(normal.x * normal.x + normal.y * normal.y + normal.z * normal.z);
    normal = mul(normal, 1.0f / len);
    uint32_t base = uint32_t(m.positions.size() / 3);
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            float s = float(i) / float(n), t = float(j) / float(n);
            Vec3 p = add(origin, add(mul(u, s), mul(v, t)));
            m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
            m.normals.insert(m.normals.end(), {normal.x, normal.y, normal.z});
            m.uvs.insert(m.uvs.end(), {s, t});
            bounds.grow(p);
        }
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
}

void beginSubmesh(MeshData& m, uint32_t material) {
    Submesh s;
    s.material = material;
    s.firstIndex = uint32_t(m.indices.size());
    m.submeshes.push_back(s);
}

void endSubmesh(MeshData& m, const Aabb& bounds) {
    m.submeshes.back().indexCount = uint32_t(m.indices.size()) - m.submeshes.back().firstIndex;
    m.submeshes.back().bounds = bounds;
}

// An axis-aligned box from `lo` to `hi`, outward faces, one submesh.
void addBox(MeshData& m, Vec3 lo, Vec3 hi, uint32_t n, uint32_t material) {
    beginSubmesh(m, material);
    Aabb b;
    Vec3 d = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
    Vec3 X{d.x, 0, 0}, Y{0, d.y, 0}, Z{0, 0, d.z};
    addQuad(m, lo, Y, X, n, b);                       // -Z
    addQuad(m, add(lo, Z), X, Y, n, b);               // +Z
    addQuad(m, lo, Z, Y, n, b);                       // -X
    addQuad(m, add(lo, X), Y, Z, n, b);               // +X
    addQuad(m, lo, X, Z, n, b);                       // -Y
    addQuad(m, add(lo, Y), Z, X, n, b);               // +Y
    endSubmesh(m, b);
}

Mesh finishMesh(SceneBuilder& sb, const char* name, MeshData& m) {
    Mesh mesh;
    mesh.name = sb.intern(name);
    mesh.vertexCount = uint32_t(m.positions.size() / 3);
    mesh.indexType = mesh.vertexCount <= 65535 ? IndexType::U16 : IndexType::U32;
    if (mesh.indexType == IndexType::U16) {
        std::vector<uint16_t> small(m.indices.begin(), m.indices.end());
        mesh.indices = sb.keep(small);
    } else {
        mesh.indices = sb.keep(m.indices);
    }
    VertexStream pos{.semantic = VertexSemantic::Position, .componentCount = 3,
                     .data = sb.keep(m.positions)};
    VertexStream nrm{.semantic = VertexSemantic::Normal, .componentCount = 3,
                     .data = sb.keep(m.normals)};
    VertexStream uv{.semantic = VertexSemantic::TexCoord0, .componentCount = 2,
                    .data = sb.keep(m.uvs)};
    mesh.streams = {pos, nrm, uv};
    mesh.submeshes = m.submeshes;
    for (const Submesh& s : m.submeshes) {
        mesh.bounds.grow(s.bounds.min);
        mesh.bounds.grow(s.bounds.max);
    }
    Vec3 c = mul(add(mesh.bounds.min, mesh.bounds.max), 0.5f);
    Vec3 e = mul(add(mesh.bounds.max, mul(mesh.bounds.min, -1)), 0.5f);
    mesh.boundingSphere = {c, std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z)};
    return mesh;
}


std::string_view sampleShader(std::string_view name) {
    for (const EmbeddedFile& f : kSampleShaders)
        if (f.name == name) return f.text;
    return {}; // unreachable: the build embeds both files
}

// A two-tone checker with a box-filtered mip chain (RGBA8, sRGB).
void addCheckerTexture(SceneBuilder& sb, uint32_t size) {
    TextureDesc t;
    t.name = sb.intern("checker");
    t.format = TextureFormat::RGBA8;
    t.colorSpace = ColorSpace::Srgb;
    t.width = t.height = size;
    t.mipCount = 1;
    for (uint32_t d = size; d > 1; d >>= 1) ++t.mipCount;
    sb.scene.textures.push_back(t);

    std::vector<uint8_t> level(size_t(size) * size * 4);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            bool light = ((x / 8) + (y / 8)) % 2 == 0;
            uint8_t* p = &level[(size_t(y) * size + x) * 4];
            p[0] = light ? 230 : 60;
            p[1] = light ? 220 : 70;
            p[2] = light ? 200 : 90;
            p[3] = 255;
        }
    uint32_t w = size;
    for (uint32_t l = 0; l < t.mipCount; ++l) {
        sb.scene.textureMips.push_back(TextureMip{.texture = 0, .level = l, .width = w,
                                                  .height = w, .data = sb.keep(level)});
        if (w == 1) break;
        uint32_t h = w / 2;
        std::vector<uint8_t> next(size_t(h) * h * 4);
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < h; ++x)
                for (int c = 0; c < 4; ++c) {
                    auto at = [&](uint32_t xx, uint32_t yy) {
                        return uint32_t(level[(size_t(yy) * w + xx) * 4 + c]);
                    };
                    uint32_t sum = at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) +
                                   at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1);
                    next[(size_t(y) * h + x) * 4 + c] = uint8_t((sum + 2) / 4);
                }
        level = std::move(next);
        w = h;
    }
}

uint32_t addMaterial(SceneBuilder& sb, const char* name, Vec4 color, uint32_t texture) {
    Material m;
    m.name = sb.intern(name);
    m.program = 0;
    m.baseColorFactor = color;
    m.metallicFactor = 0;
    m.roughnessFactor = 0.8f;
    m.textures[size_t(TextureSlotKind::BaseColor)].texture = texture;
    sb.scene.materials.push_back(m);
    return uint32_t(sb.scene.materials.size() - 1);
}

} // namespace

namespace {

// ENVM and its three textures, every texel the same (half 1.0 = 0x3C00): see BoxRoomOptions.
void addSampleEnvironment(SceneBuilder& sb) {
    Scene& s = sb.scene;
    auto texture = [&](const char* name, TextureDimension dim, TextureFormat format, uint32_t w, uint32_t h,
                       uint32_t mips, uint32_t channels) {
        TextureDesc t;
        t.name = sb.intern(name);
        t.dimension = dim;
        t.format = format;
        t.colorSpace = ColorSpace::Linear;
        t.width = w;
        t.height = h;
        t.layers = dim == TextureDimension::Cube ? 6 : 1;
        t.mipCount = mips;
        t.minFilter = mips > 1 ? MinFilter::LinearMipLinear : MinFilter::Linear;
        t.wrapU = dim == TextureDimension::Tex2D && channels == 4 ? Wrap::Repeat : Wrap::ClampToEdge;
        t.wrapV = Wrap::ClampToEdge;
        const uint32_t index = uint32_t(s.textures.size());
        s.textures.push_back(t);
        for (uint32_t l = 0; l < mips; ++l) {
            const uint32_t lw = std::max(1u, w >> l), lh = std::max(1u, h >> l);
            std::vector<uint16_t> texels(size_t(lw) * lh * t.layers * channels, uint16_t(0x3C00));
            s.textureMips.push_back(TextureMip{.texture = index, .level = l, .width = lw, .height = lh,
                                               .data = sb.keep(texels)});
        }
        return index;
    };
    Environment e;
    e.name = sb.intern("sample");
    e.radiance = texture("environment", TextureDimension::Tex2D, TextureFormat::RGBA16F, 4, 2, 3, 4);
    e.specular = texture("environment_specular", TextureDimension::Cube, TextureFormat::RGBA16F, 2, 2, 2, 4);
    e.brdfLut = texture("environment_brdf", TextureDimension::Tex2D, TextureFormat::RG16F, 2, 2, 1, 2);
    // A constant radiance of 1 nit: irradiance pi, band 0 only (pi / Y0 = 2 pi sqrt(pi)).
    e.irradianceSh[0] = Vec3{11.1366f, 11.1366f, 11.1366f};
    s.environment = e;
}

} // namespace

void buildBoxRoom(SceneBuilder& sb, const BoxRoomOptions& o) {
    Scene& s = sb.scene;
    const float r = o.roomSize;
    const uint32_t n = std::max(1u, o.boxSubdivisions);

    s.info.name = sb.intern("box-room");
    s.info.generator = sb.intern("penumbra assets_src/box_room");
    s.info.source = sb.intern("procedural");
    s.info.metersPerUnit = 1.0f;
    s.settings.entries = {
        {sb.intern("shadows.technique"), sb.intern("sdsm")},
        {sb.intern("shadows.cascades"), sb.intern("4")},
        {sb.intern("gi.enabled"), sb.intern("false")},
    };

    s.shaders.push_back({sb.intern("basic.vert"), ShaderStage::Vertex,
                         sb.keep(sampleShader("basic.vert"))});
    s.shaders.push_back({sb.intern("basic.frag"), ShaderStage::Fragment,
                         sb.keep(sampleShader("basic.frag"))});
    s.programs.push_back({sb.intern("basic"), {0, 1}, {}});
    s.programs.push_back({sb.intern("basic+texture"), {0, 1}, {sb.intern("HAS_BASE_COLOR_TEXTURE")}});

    addCheckerTexture(sb, std::max(1u, o.textureSize));

    uint32_t white = addMaterial(sb, "white-wall", {0.73f, 0.73f, 0.73f, 1}, kNone);
    uint32_t red = addMaterial(sb, "red-wall", {0.63f, 0.065f, 0.05f, 1}, kNone);
    uint32_t green = addMaterial(sb, "green-wall", {0.14f, 0.45f, 0.091f, 1}, kNone);
    uint32_t floorMat = addMaterial(sb, "checker-floor", {1, 1, 1, 1}, 0);
    s.materials[floorMat].program = 1;
    uint32_t glass = addMaterial(sb, "tinted-glass", {0.2f, 0.4f, 0.9f, 0.35f}, kNone);
    s.materials[glass].alphaMode = AlphaMode::Blend;
    s.materials[glass].shadingPath = ShadingPath::Forward;
    s.materials[glass].layerPriority = 1;
    s.materials[glass].doubleSided = true;
    s.materials[glass].castsShadows = false;

    // Room: inward-facing walls, open at +Z (the camera side).
    MeshData room;
    Vec3 X{r, 0, 0}, Y{0, r, 0}, Z{0, 0, r};
    Vec3 lo{-r / 2, 0, -r / 2};
    struct Wall { uint32_t material; Vec3 origin, u, v; };
    const Wall walls[] = {
        {floorMat, lo, Z, X},                           // floor, normal +Y
        {white, add(lo, Y), X, Z},                      // ceiling, normal -Y
        {white, lo, X, Y},                              // back, normal +Z
        {red, lo, Y, Z},                                // left, normal +X
        {green, add(lo, X), Z, Y},                      // right, normal -X
    };
    for (const Wall& w : walls) {
        beginSubmesh(room, w.material);
        Aabb b;
        addQuad(room, w.origin, w.u, w.v, n, b);
        endSubmesh(room, b);
    }
    s.meshes.push_back(finishMesh(sb, "room", room));

    MeshData boxes;
    addBox(boxes, {-0.35f * r, 0, -0.3f * r}, {-0.05f * r, 0.6f * r, 0.0f}, n, white);
    addBox(boxes, {0.05f * r, 0, -0.1f * r}, {0.35f * r, 0.3f * r, 0.2f * r}, n, white);
    s.meshes.push_back(finishMesh(sb, "boxes", boxes));

    MeshData pane;
    beginSubmesh(pane, glass);
    Aabb pb;
    addQuad(pane, {-0.3f * r, 0.05f * r, 0.3f * r}, {0.6f * r, 0, 0}, {0, 0.5f * r, 0}, 1, pb);
    endSubmesh(pane, pb);
    s.meshes.push_back(finishMesh(sb, "glass-pane", pane));

    s.lights.lights.push_back(Light{.name = sb.intern("sun"), .type = LightType::Directional,
                                    .color = {1.0f, 0.95f, 0.85f}, .intensity = 3.0f});
    s.lights.lights.push_back(Light{.name = sb.intern("ceiling-lamp"), .type = LightType::Point,
                                    .color = {1, 1, 1}, .intensity = 40.0f, .range = 2 * r});
    s.cameras.cameras.push_back(Camera{.name = sb.intern("main"), .yfovRadians = 0.9f,
                                       .znear = 0.05f, .zfar = 0});

    auto addNode = [&](const char* name, Vec3 t, Vec4 q, uint32_t mesh, uint32_t light,
                       uint32_t camera) {
        Node node;
        node.name = sb.intern(name);
        node.parent = 0;
        node.translation = t;
        node.rotation = q;
        node.mesh = mesh;
        node.light = light;
        node.camera = camera;
        if (mesh != kNone) { // identity transforms: world bounds are the mesh's
            node.worldBounds = s.meshes[mesh].bounds;
            node.worldSphere = s.meshes[mesh].boundingSphere;
        }
        s.nodes.nodes.push_back(node);
    };
    Node root;
    root.name = sb.intern("root");
    s.nodes.nodes.push_back(root);
    addNode("room", {}, {0, 0, 0, 1}, 0, kNone, kNone);
    addNode("boxes", {}, {0, 0, 0, 1}, 1, kNone, kNone);
    addNode("glass-pane", {}, {0, 0, 0, 1}, 2, kNone, kNone);
    // Sun pointing down and into the room: -Z rotated 60 degrees about +X.
    addNode("sun", {0, 2 * r, 2 * r}, {-0.5f, 0, 0, 0.8660254f}, kNone, 0, kNone);
    addNode("ceiling-lamp", {0, 0.9f * r, 0}, {0, 0, 0, 1}, kNone, 1, kNone);
    addNode("camera", {0, 0.5f * r, 1.4f * r}, {0, 0, 0, 1}, kNone, kNone, 0);
    for (const Mesh& m : s.meshes) {
        s.info.bounds.grow(m.bounds.min);
        s.info.bounds.grow(m.bounds.max);
    }

    CameraPath path;
    path.name = sb.intern("orbit");
    path.loop = true;
    for (int k = 0; k < 8; ++k) {
        float a = float(k) / 8.0f * 1.5707964f - 0.7853982f; // sweep -45..+34 degrees
        CameraKey key;
        key.timeSeconds = float(k) * 1.5f;
        key.position = {1.2f * r * std::sin(a), 0.5f * r, 1.2f * r * std::cos(a)};
        key.rotation = {0, std::sin(a / 2), 0, std::cos(a / 2)};
        path.keys.push_back(key);
    }
    s.cameraPaths.push_back(path);
    if (o.environment) addSampleEnvironment(sb);
}

} // namespace pnb::assets
