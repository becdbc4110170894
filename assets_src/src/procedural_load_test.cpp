// assets_src/src/procedural_load_test.cpp — the load-test scene: ~1 M triangles of displaced rock
// spheres with procedural noise textures (base colour and normal maps), the player's load-time
// benchmark (procedural_scenes.h). A file of its own: its textures and rock meshes are used by
// nothing else.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include "pnb_assets/png_writer.h"
#include "procedural_scenes_internal.h"

namespace pnb::assets {

using namespace procedural_detail;

// [SECTION] load-test ---------------------------------------------------------------------------

namespace {

// fBm of tileable value noise over a size x size image: `cells` lattice cells across at the
// first octave (doubling each octave, so every octave tiles), normalised to [0, 1].
std::vector<float> tileableFbm(uint32_t size, int32_t cells, uint32_t octaves, uint32_t seed) {
    std::vector<float> out(size_t(size) * size);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            float sum = 0, norm = 0, amplitude = 1;
            int32_t period = cells;
            for (uint32_t o = 0; o < octaves; ++o) {
                const float scale = float(period) / float(size);
                sum += amplitude * tileableValueNoise(float(x) * scale, float(y) * scale, period,
                                                      seed + o * 0x9E3779B9u);
                norm += amplitude;
                amplitude *= 0.5f;
                period *= 2;
            }
            out[size_t(y) * size + x] = sum / norm;
        }
    return out;
}

uint8_t unorm8(float v) {
    return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

// Base colour: two palette colours mixed by fBm, with darker veins where a second fBm crosses
// its middle value.
std::vector<uint8_t> rockColorPng(uint32_t size, Float3 a, Float3 b, uint32_t seed) {
    const std::vector<float> mix = tileableFbm(size, 8, 5, seed);
    const std::vector<float> veins = tileableFbm(size, 4, 4, seed ^ 0xA511E9B3u);
    std::vector<uint8_t> pixels(size_t(size) * size * 3);
    for (size_t i = 0; i < mix.size(); ++i) {
        const float t = std::clamp((mix[i] - 0.3f) / 0.4f, 0.0f, 1.0f);
        const float vein = std::clamp(std::fabs(veins[i] - 0.5f) * 25.0f, 0.0f, 1.0f);
        const float shade = 0.55f + 0.45f * vein;
        for (int k = 0; k < 3; ++k)
            pixels[i * 3 + size_t(k)] =
                unorm8((a[size_t(k)] + (b[size_t(k)] - a[size_t(k)]) * t) * shade);
    }
    return encodePng(size, size, 3, pixels);
}

// Tangent-space normal map (glTF: +X right, +Y up in texture space, i.e. towards smaller v) of
// a tileable fBm heightfield, by central differences with wrap-around.
std::vector<uint8_t> rockNormalPng(uint32_t size, uint32_t seed) {
    const std::vector<float> h = tileableFbm(size, 16, 5, seed);
    const float strength = float(size) / 16.0f; // slope scale: heights are in [0, 1]
    std::vector<uint8_t> pixels(size_t(size) * size * 3);
    auto at = [&](uint32_t x, uint32_t y) { return h[size_t(y % size) * size + x % size]; };
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const float dx = (at(x + 1, y) - at(x + size - 1, y)) * 0.5f * strength;
            const float dy = (at(x, y + size - 1) - at(x, y + 1)) * 0.5f * strength; // +Y = up
            const Float3 n = normalize({-dx, -dy, 1.0f});
            uint8_t* p = &pixels[(size_t(y) * size + x) * 3];
            for (int k = 0; k < 3; ++k)
                p[k] = unorm8(n[size_t(k)] * 0.5f + 0.5f);
        }
    return encodePng(size, size, 3, pixels);
}

// The rock surface: radius `radius` times 1 +- 0.25 of 3D fBm over the direction.
struct RockShape {
    float radius;
    Float3 offset; // where this rock samples the noise field
    uint32_t seed;

    float radiusAt(Float3 dir) const {
        float sum = 0, norm = 0, amplitude = 1, frequency = 1.5f;
        for (uint32_t o = 0; o < 4; ++o) {
            const Float3 q = dir * frequency + offset;
            sum += amplitude * valueNoise3(q[0], q[1], q[2], seed + o * 0x9E3779B9u);
            norm += amplitude;
            amplitude *= 0.5f;
            frequency *= 2.0f;
        }
        return radius * (1.0f + 0.5f * (sum / norm - 0.5f));
    }
    // Signed distance-like field |p| - r(p / |p|); the surface is its zero set.
    float field(Float3 p) const {
        const float len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        return len - radiusAt(p * (1.0f / len));
    }
};

// A displaced UV sphere: `rings` latitude bands (poles are single triangles), 2 * rings
// segments, so 4 * rings * (rings - 1) triangles. Normals are the field's gradient (central
// differences in 3D), so they agree across the u seam and at the poles.
Primitive rockPrimitive(const RockShape& shape, uint32_t rings, uint32_t material) {
    const uint32_t segments = 2 * rings;
    Primitive p;
    p.material = material;
    const float eps = shape.radius * 1e-3f;
    for (uint32_t j = 0; j <= rings; ++j) {
        const float theta = kPi * float(j) / float(rings);
        for (uint32_t i = 0; i <= segments; ++i) {
            const float phi = 2 * kPi * float(i == segments ? 0 : i) / float(segments);
            // Exact poles and an exact seam (i == segments repeats i == 0's position).
            const float st = j == 0 || j == rings ? 0.0f : std::sin(theta);
            const float ct = j == 0 ? 1.0f : j == rings ? -1.0f : std::cos(theta);
            const Float3 dir{st * std::cos(phi), ct, st * std::sin(phi)};
            const Float3 pos = dir * shape.radiusAt(dir);
            Float3 g{};
            for (size_t k = 0; k < 3; ++k) {
                Float3 d{0, 0, 0};
                d[k] = eps;
                g[k] = shape.field(pos + d) - shape.field(pos - d);
            }
            p.positions.push_back(pos);
            p.normals.push_back(normalize(g));
            p.uv0.push_back({4.0f * float(i) / float(segments), 2.0f * float(j) / float(rings)});
        }
    }
    const uint32_t row = segments + 1;
    for (uint32_t j = 0; j < rings; ++j)
        for (uint32_t i = 0; i < segments; ++i) {
            const uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
            // (a, b, c) and (b, d, c) are counter-clockwise seen from outside; at the north pole
            // (j = 0) a == b in position, at the south pole c == d, so one of each is dropped.
            if (j != 0) p.indices.insert(p.indices.end(), {a, b, c});
            if (j != rings - 1) p.indices.insert(p.indices.end(), {b, d, c});
        }
    return p;
}

} // namespace

gltf::Document buildLoadTest(const LoadTestOptions& o) {
    Document doc;
    doc.sceneName = "load-test";
    const uint32_t objects = std::max(1u, o.objects);
    const uint32_t materials = std::max(1u, o.materials);
    const uint32_t texture = std::max(4u, o.textureSize);
    const uint32_t seed = foldSeed(o.seed);

    // Per-material palettes (pairs of sRGB colours): granite, sandstone, slate, basalt, moss.
    static constexpr Float3 kPalettes[][2] = {
        {{0.55f, 0.52f, 0.50f}, {0.80f, 0.78f, 0.74f}},
        {{0.60f, 0.42f, 0.26f}, {0.85f, 0.70f, 0.50f}},
        {{0.22f, 0.26f, 0.30f}, {0.45f, 0.50f, 0.55f}},
        {{0.12f, 0.11f, 0.11f}, {0.35f, 0.32f, 0.30f}},
        {{0.25f, 0.35f, 0.18f}, {0.55f, 0.60f, 0.40f}},
    };
    constexpr size_t kPaletteCount = std::size(kPalettes);
    for (uint32_t k = 0; k < materials; ++k) {
        const Float3* pal = kPalettes[k % kPaletteCount];
        doc.images.push_back({"rock-color-" + std::to_string(k),
                              rockColorPng(texture, pal[0], pal[1], seed + 1000 * (k + 1))});
    }
    for (uint32_t k = 0; k < materials; ++k)
        doc.images.push_back({"rock-normal-" + std::to_string(k),
                              rockNormalPng(texture, seed + 1000 * (k + 1) + 500)});
    for (uint32_t k = 0; k < materials; ++k) {
        Material m = makeMaterial("rock-material-" + std::to_string(k), {1, 1, 1}, 0.85f);
        m.baseColorImage = int32_t(k);
        m.normalImage = int32_t(materials + k);
        addMaterial(doc, std::move(m));
    }

    // Rocks on a grid, 10 per row (fewer if there are fewer rocks), 12 m apart.
    const uint64_t perRock = std::max<uint64_t>(8, o.targetTriangles / objects);
    const auto rings = uint32_t(
        std::clamp(std::round(0.5 + std::sqrt(0.25 + double(perRock) / 4.0)), 2.0, 4096.0));
    const uint32_t columns = std::min(objects, 10u);
    const uint32_t rows = (objects + columns - 1) / columns;
    constexpr float kSpacing = 12.0f;
    Pcg32 rng(o.seed, kStreamLoadTestRocks);
    for (uint32_t n = 0; n < objects; ++n) {
        const RockShape shape{rng.uniform(3.0f, 5.0f),
                              {rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(0, 100)},
                              seed ^ 0x0C0FFEEu};
        const float yaw = rng.uniform(0, 2 * kPi);
        Mesh m;
        m.name = "rock-" + std::to_string(n);
        m.primitives.push_back(rockPrimitive(shape, rings, n % materials));
        const float x = (float(n % columns) - float(columns - 1) / 2) * kSpacing;
        const float z = (float(n / columns) - float(rows - 1) / 2) * kSpacing;
        std::string name = m.name;
        addNode(doc, meshNode(name, addMesh(doc, std::move(m)), {x, 0.8f * shape.radius, z},
                              gltf::rotationY(yaw)));
    }

    const float halfX = float(columns) * kSpacing / 2, halfZ = float(rows) * kSpacing / 2;
    addCamera(doc, "overview-camera", {0, 0.9f * halfX, halfZ + 1.1f * halfX},
              {0, -0.9f * halfX, -1.1f * halfX}, radians(50), 16.0f / 9.0f, 0.5f,
              8.0f * (halfX + halfZ));
    addSun(doc, sunDirection(radians(45), radians(30)), {0, 0, 0}, 2.0f * (halfX + halfZ),
           {1.0f, 0.96f, 0.9f}, 3.0f);
    return doc;
}

} // namespace pnb::assets
