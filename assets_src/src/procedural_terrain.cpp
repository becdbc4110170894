// assets_src/src/procedural_terrain.cpp — the terrain scene: a tiled fractal heightfield with
// floating rock slabs and arches, and a camera looking across it to a far plane kilometres away
// (procedural_scenes.h). A file of its own: its height field is used by nothing else.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "procedural_scenes_internal.h"

namespace pnb::assets {

using namespace procedural_detail;

// [SECTION] terrain -----------------------------------------------------------------------------

namespace {

// The terrain's height function: fBm of value noise with a 1024 m base period, remapped so the
// lowlands flatten out and the peaks sharpen.
struct TerrainField {
    uint32_t seed;
    uint32_t octaves;
    float heightMeters;

    float operator()(float x, float z) const {
        float sum = 0, norm = 0, amplitude = 1, frequency = 1.0f / 1024.0f;
        for (uint32_t o = 0; o < octaves; ++o) {
            sum += amplitude * valueNoise(x * frequency, z * frequency, seed + o * 0x9E3779B9u);
            norm += amplitude;
            amplitude *= 0.5f;
            frequency *= 2.0f;
        }
        float n = std::clamp((sum / norm - 0.2f) / 0.6f, 0.0f, 1.0f);
        return heightMeters * std::pow(n, 1.8f);
    }
};

} // namespace

gltf::Document buildTerrain(const TerrainOptions& o) {
    Document doc;
    doc.sceneName = "terrain";
    const uint32_t quads = std::max(1u, o.quadsPerSide);
    const uint32_t tileQuads = std::clamp(o.tileQuads, 1u, quads);
    const float size = o.sizeMeters, half = size / 2, step = size / float(quads);
    const TerrainField field{foldSeed(o.seed), std::max(1u, o.octaves), o.heightMeters};

    const uint32_t ground = addMaterial(doc, makeMaterial("terrain", {0.28f, 0.33f, 0.18f}, 0.95f));
    const uint32_t rock = addMaterial(doc, makeMaterial("rock", {0.42f, 0.38f, 0.33f}, 0.9f));

    // Heights on the grid plus a one-sample border, for central-difference normals that agree
    // across tile seams.
    const uint32_t stride = quads + 3;
    std::vector<float> heights(size_t(stride) * stride);
    auto gridX = [&](int64_t i) { return -half + float(i) * step; };
    for (uint32_t j = 0; j < stride; ++j)
        for (uint32_t i = 0; i < stride; ++i)
            heights[size_t(j) * stride + i] = field(gridX(int64_t(i) - 1), gridX(int64_t(j) - 1));
    // i, j in [-1, quads + 1] (the border included).
    auto heightAt = [&](int64_t i, int64_t j) {
        return heights[size_t(j + 1) * stride + size_t(i + 1)];
    };

    const uint32_t tiles = (quads + tileQuads - 1) / tileQuads;
    std::vector<uint32_t> tileNodes;
    for (uint32_t tj = 0; tj < tiles; ++tj)
        for (uint32_t ti = 0; ti < tiles; ++ti) {
            const uint32_t i0 = ti * tileQuads, i1 = std::min(quads, i0 + tileQuads);
            const uint32_t j0 = tj * tileQuads, j1 = std::min(quads, j0 + tileQuads);
            const Float3 origin{gridX(i0), 0, gridX(j0)};
            Primitive p;
            p.material = ground;
            for (uint32_t j = j0; j <= j1; ++j)
                for (uint32_t i = i0; i <= i1; ++i) {
                    // Tile-local positions (the node carries the tile origin) keep the float
                    // precision of vertices independent of the terrain size.
                    p.positions.push_back(
                        {gridX(i) - origin[0], heightAt(i, j), gridX(j) - origin[2]});
                    const int64_t si = i, sj = j;
                    float dx = (heightAt(si + 1, sj) - heightAt(si - 1, sj)) / (2 * step);
                    float dz = (heightAt(si, sj + 1) - heightAt(si, sj - 1)) / (2 * step);
                    p.normals.push_back(normalize({-dx, 1, -dz}));
                }
            const uint32_t w = i1 - i0 + 1;
            for (uint32_t j = 0; j < j1 - j0; ++j)
                for (uint32_t i = 0; i < i1 - i0; ++i) {
                    uint32_t a = j * w + i, b = a + 1, c = a + w, d = c + 1;
                    // (c - a) x (d - a) = +z x (+x+z) = +Y: counter-clockwise from above.
                    p.indices.insert(p.indices.end(), {a, c, d, a, d, b});
                }
            Mesh m;
            m.name = "terrain-" + std::to_string(ti) + "-" + std::to_string(tj);
            m.primitives.push_back(std::move(p));
            std::string name = m.name;
            tileNodes.push_back(addNode(doc, meshNode(name, addMesh(doc, std::move(m)), origin)));
        }

    // Overhangs, along the camera's diagonal view so they are seen against the terrain: rock
    // slabs floating 12-35 m above the highest ground under them, and arches whose pillars are
    // sunk 40 m (scaled) below the higher foot so they never float on a slope.
    Pcg32 rng(o.seed, kStreamTerrainProps);
    auto alongView = [&](float t, float lateral) {
        // From the camera corner (-0.42, +0.42) towards (+0.42, -0.42), in units of size.
        float d = -0.42f + 0.84f * t;
        return Float2{(d + lateral * 0.7071f) * size, (-d + lateral * 0.7071f) * size};
    };
    for (uint32_t k = 0; k < o.slabs; ++k) {
        const float wx = rng.uniform(25, 50), thickness = rng.uniform(4, 8),
                    wz = rng.uniform(12, 25);
        const Float2 c = alongView(rng.uniform(0.12f, 0.6f), rng.uniform(-0.08f, 0.08f));
        const float yaw = rng.uniform(0, 2 * kPi), lift = rng.uniform(12, 35);
        const float radius = 0.5f * std::sqrt(wx * wx + wz * wz);
        float highest = -1e30f;
        for (int b = -4; b <= 4; ++b)
            for (int a = -4; a <= 4; ++a)
                highest = std::max(
                    highest, field(c[0] + float(a) * radius / 4, c[1] + float(b) * radius / 4));
        Mesh m = boxesMesh("rock-slab-" + std::to_string(k),
                           {{{-wx / 2, -thickness / 2, -wz / 2}, {wx / 2, thickness / 2, wz / 2}}},
                           8.0f, rock, rock);
        std::string name = m.name;
        addNode(doc, meshNode(name, addMesh(doc, std::move(m)),
                              {c[0], highest + lift + thickness / 2, c[1]}, gltf::rotationY(yaw)));
    }
    if (o.arches > 0) {
        // Local frame: pillars 10 x 10 m at x = +-25, from y = -40 (sunk) to 30; lintel 30-38.
        const int32_t arch = addMesh(doc, boxesMesh("rock-arch",
                                                    {{{-30, -40, -5}, {-20, 30, 5}},
                                                     {{20, -40, -5}, {30, 30, 5}},
                                                     {{-30, 30, -5}, {30, 38, 5}}},
                                                    8.0f, rock, rock));
        for (uint32_t k = 0; k < o.arches; ++k) {
            Float2 c{};
            float yaw = 0, scale = 1, base = 0;
            for (int attempt = 0; attempt < 32; ++attempt) {
                c = alongView(rng.uniform(0.2f, 0.7f), rng.uniform(-0.1f, 0.1f));
                yaw = rng.uniform(0, 2 * kPi);
                scale = rng.uniform(0.8f, 1.25f);
                const float px = std::cos(yaw) * 25 * scale, pz = -std::sin(yaw) * 25 * scale;
                const float ha = field(c[0] + px, c[1] + pz), hb = field(c[0] - px, c[1] - pz);
                base = std::max(ha, hb);
                // Both feet well buried, and the opening clear of the ground between them.
                if (base - std::min(ha, hb) < 40 * scale - 8 &&
                    field(c[0], c[1]) < base + 20 * scale)
                    break;
            }
            Node n = meshNode("rock-arch-" + std::to_string(k), arch, {c[0], base, c[1]},
                              gltf::rotationY(yaw));
            n.scale = {scale, scale, scale};
            addNode(doc, std::move(n));
        }
    }

    // Camera 2 m above a grid vertex (where the mesh equals the height function exactly) at the
    // corner, looking across the whole terrain to the far corner, 1 degree below the horizon.
    const auto ci = uint32_t(std::lround(0.08f * float(quads)));
    const auto cj = uint32_t(std::lround(0.92f * float(quads)));
    const Float3 eye{gridX(ci), heightAt(ci, cj) + 2.0f, gridX(cj)};
    const float pitch = radians(-1.0f);
    addCamera(doc, "ground-camera", eye,
              {std::cos(pitch) * 0.7071f, std::sin(pitch), -std::cos(pitch) * 0.7071f}, radians(60),
              16.0f / 9.0f, 0.5f, 2.0f * size);
    addSun(doc, sunDirection(radians(o.sunElevationDegrees), radians(60)), {0, 0, 0}, size,
           {1.0f, 0.95f, 0.88f}, 3.0f);
    return doc;
}

} // namespace pnb::assets
