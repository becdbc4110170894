// make_stream_scene_geometry.cpp — pnb-make-stream-scene's meshes: the panel box, the ground,
// their container meshes and world boxes, and the --lod-rocks rocks (made from their index, then
// through the converter's mesh pipeline). A part of its own: shapes, not layout
// (make_stream_scene.h).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "make_stream_scene.h"
#include "pnb_converter/mesh_processing.h"

namespace stream_scene {

// [SECTION] geometry

// The rotation taking unit vector a to unit vector b (not antiparallel).
Vec4 rotationBetween(Vec3 a, Vec3 b) {
    Vec3 c = cross(a, b);
    Vec4 q{c.x, c.y, c.z, 1 + dot(a, b)};
    float n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return {q.x / n, q.y / n, q.z / n, q.w / n};
}

// A box centred on the origin with half extents h; every face shows the whole texture upright
// as seen from outside (v = 0 at the top, glTF convention).
MeshData makeBox(Vec3 h) {
    MeshData m;
    const std::array<Vec3, 6> normals = {{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
    for (Vec3 n : normals) {
        Vec3 up = n.y != 0 ? Vec3{0, 0, -1} : Vec3{0, 1, 0};
        Vec3 right = cross(scale(n, -1), up);
        auto extent = [&](Vec3 axis) {
            return std::abs(axis.x) * h.x + std::abs(axis.y) * h.y + std::abs(axis.z) * h.z;
        };
        Vec3 centre{n.x * h.x, n.y * h.y, n.z * h.z};
        float er = extent(right), eu = extent(up);
        uint16_t first = uint16_t(m.positions.size() / 3);
        for (int corner = 0; corner < 4; ++corner) {
            float u = float(corner & 1), v = float(corner >> 1); // TL, TR, BL, BR
            Vec3 p = add(centre, add(scale(right, (2 * u - 1) * er), scale(up, (1 - 2 * v) * eu)));
            m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
            m.normals.insert(m.normals.end(), {n.x, n.y, n.z});
            m.uvs.insert(m.uvs.end(), {u, v});
            m.bounds.grow(p);
        }
        // Counter-clockwise seen from outside: BL BR TR, BL TR TL.
        for (uint16_t i : {2, 3, 1, 2, 1, 0}) m.indices.push_back(uint16_t(first + i));
    }
    return m;
}

MeshData makeGround(float x0, float x1, float z0, float z1) {
    MeshData m;
    for (int corner = 0; corner < 4; ++corner) {
        Vec3 p{corner & 1 ? x1 : x0, 0, corner >> 1 ? z1 : z0};
        m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
        m.normals.insert(m.normals.end(), {0, 1, 0});
        m.bounds.grow(p);
    }
    // Corners: 0 (x0,z0) 1 (x1,z0) 2 (x0,z1) 3 (x1,z1), z1 < z0; counter-clockwise from +Y.
    m.indices = {0, 1, 2, 1, 3, 2};
    return m;
}

Mesh toMesh(SceneBuilder& b, const std::string& name, const MeshData& d, uint32_t material) {
    Mesh m;
    m.name = b.intern(name);
    m.indexType = IndexType::U16;
    m.vertexCount = uint32_t(d.positions.size() / 3);
    auto stream = [&](VertexSemantic s, uint8_t components, const std::vector<float>& data) {
        VertexStream v;
        v.semantic = s;
        v.componentCount = components;
        v.data = b.keep(data);
        m.streams.push_back(v);
    };
    stream(VertexSemantic::Position, 3, d.positions);
    stream(VertexSemantic::Normal, 3, d.normals);
    if (!d.uvs.empty()) stream(VertexSemantic::TexCoord0, 2, d.uvs);
    m.indices = b.keep(d.indices);
    m.submeshes.push_back(Submesh{material, 0, uint32_t(d.indices.size()), 0, 0.0f, d.bounds});
    m.bounds = d.bounds;
    Vec3 e = scale(add(d.bounds.max, scale(d.bounds.min, -1)), 0.5f);
    m.boundingSphere = {scale(add(d.bounds.max, d.bounds.min), 0.5f), std::sqrt(dot(e, e))};
    return m;
}

// The world box of `local` turned by `yaw` about +Y, then moved by t.
Aabb placed(Aabb local, float yaw, Vec3 t) {
    Aabb out;
    const float c = std::cos(yaw), s = std::sin(yaw);
    for (int corner = 0; corner < 8; ++corner) {
        Vec3 p{corner & 1 ? local.max.x : local.min.x, corner & 2 ? local.max.y : local.min.y,
               corner & 4 ? local.max.z : local.min.z};
        out.grow(add(Vec3{c * p.x + s * p.z, p.y, -s * p.x + c * p.z}, t));
    }
    return out;
}

// [SECTION] rocks (--lod-rocks)

namespace {

// splitmix64: a tiny deterministic generator, the same numbers on every platform.
class Random {
public:
    explicit Random(uint64_t seed) : mState(seed) {}
    uint64_t next() {
        uint64_t z = (mState += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform(float lo, float hi) {
        return lo + (hi - lo) * float(next() >> 40) / float(1 << 24);
    }
    Vec3 direction() { // uniform on the unit sphere
        float z = uniform(-1, 1), a = uniform(0, 6.2831853f), r = std::sqrt(1 - z * z);
        return {r * std::cos(a), r * std::sin(a), z};
    }

private:
    uint64_t mState;
};

// Grid rows of a rock of about `triangles` triangles: a latitude-longitude sphere of r rows and
// 2r columns has 4r(r - 1) (one triangle a column in each polar row, two elsewhere).
uint32_t rockRows(uint32_t triangles) {
    return std::max(3u, uint32_t(std::lround((1 + std::sqrt(1.0 + double(triangles))) / 2)));
}

// Rock `index`: a sphere cut by a handful of random planes (flat facets, which simplify well,
// beside curved parts, which do not), roughened by low-amplitude waves, flattened and stretched
// a little; about 1 to 1.5 m across, centred on the origin. Everything comes from the index, so
// the output does not depend on which thread made the rock.
// Positions and normals are computed once per grid point, so the seam column and the poles,
// whose vertices are repeated for their uvs, get identical ones (nothing cracks or shades apart
// there). uv0: longitude and latitude, v = 0 at the top, the texture upright seen from outside.
converter::IrMesh makeRock(uint32_t index, uint32_t triangles, uint32_t material) {
    Random rnd(0x5EED0000ull + index);
    const float radius = rnd.uniform(0.5f, 0.62f);
    const Vec3 stretch{rnd.uniform(1.0f, 1.18f), rnd.uniform(0.7f, 0.85f), rnd.uniform(0.9f, 1.1f)};
    struct Cut {
        Vec3 normal;
        float distance;
    };
    std::vector<Cut> cuts(size_t(7 + rnd.next() % 5));
    for (Cut& c : cuts) c = {rnd.direction(), radius * rnd.uniform(0.74f, 0.95f)};
    struct Wave {
        Vec3 axis;
        float frequency, phase, amplitude;
    };
    std::array<Wave, 4> waves;
    for (size_t k = 0; k < waves.size(); ++k)
        waves[k] = {rnd.direction(), rnd.uniform(5, 13), rnd.uniform(0, 6.2831853f),
                    0.012f / float(k + 1)};
    auto surface = [&](Vec3 d) {
        float r = radius;
        for (const Cut& c : cuts) {
            float facing = dot(d, c.normal);
            if (facing > 1e-3f) r = std::min(r, c.distance / facing);
        }
        float rough = 1;
        for (const Wave& w : waves)
            rough += w.amplitude * std::sin(w.frequency * dot(d, w.axis) + w.phase);
        r *= rough;
        return Vec3{d.x * r * stretch.x, d.y * r * stretch.y, d.z * r * stretch.z};
    };

    // Grid points: the north pole, (rows - 1) rings of `columns`, the south pole.
    const uint32_t rows = rockRows(triangles), columns = 2 * rows;
    const uint32_t points = 2 + (rows - 1) * columns;
    auto point = [&](uint32_t row, uint32_t column) -> uint32_t {
        if (row == 0) return 0;
        if (row == rows) return points - 1;
        return 1 + (row - 1) * columns + column % columns;
    };
    std::vector<Vec3> position(points), normal(points, Vec3{0, 0, 0});
    position[0] = surface({0, 1, 0});
    position[points - 1] = surface({0, -1, 0});
    for (uint32_t row = 1; row < rows; ++row) {
        const float theta = 3.14159265f * float(row) / float(rows);
        for (uint32_t column = 0; column < columns; ++column) {
            const float phi = 6.2831853f * float(column) / float(columns);
            position[point(row, column)] = surface({std::sin(theta) * std::cos(phi),
                                                    std::cos(theta),
                                                    std::sin(theta) * std::sin(phi)});
        }
    }
    // Triangles as grid points, counter-clockwise seen from outside; area-weighted normals.
    std::vector<std::array<uint32_t, 2>> corners; // (row, column) of every triangle corner
    using Corner = std::array<uint32_t, 2>;
    auto triangle = [&](Corner a, Corner b, Corner c) {
        corners.insert(corners.end(), {a, b, c});
        Vec3 pa = position[point(a[0], a[1])], pb = position[point(b[0], b[1])],
             pc = position[point(c[0], c[1])];
        Vec3 n = cross(add(pb, scale(pa, -1)), add(pc, scale(pa, -1)));
        for (Corner k : {a, b, c}) normal[point(k[0], k[1])] = add(normal[point(k[0], k[1])], n);
    };
    for (uint32_t row = 0; row < rows; ++row)
        for (uint32_t column = 0; column < columns; ++column) {
            if (row != 0) triangle({row, column}, {row, column + 1}, {row + 1, column});
            if (row != rows - 1)
                triangle({row, column + 1}, {row + 1, column + 1}, {row + 1, column});
        }

    // Vertices: a grid point once per uv it is seen with (the seam column twice, the poles once
    // per column, at the middle of the column).
    converter::IrPrimitive p;
    p.material = int(material);
    std::vector<uint32_t> vertexOf(size_t(rows + 1) * (columns + 1), UINT32_MAX);
    for (auto [row, column] : corners) {
        uint32_t& v = vertexOf[size_t(row) * (columns + 1) + column];
        if (v == UINT32_MAX) {
            v = uint32_t(p.positions.size() / 3);
            Vec3 x = position[point(row, column)], n = normal[point(row, column)];
            n = scale(n, 1 / std::sqrt(dot(n, n)));
            float u = float(column) / float(columns);
            if (row == 0) u -= 0.5f / float(columns); // a top pole corner is at column + 1
            if (row == rows) u += 0.5f / float(columns);
            p.positions.insert(p.positions.end(), {x.x, x.y, x.z});
            p.normals.insert(p.normals.end(), {n.x, n.y, n.z});
            p.uv0.insert(p.uv0.end(), {1 - u, float(row) / float(rows)});
        }
        p.indices.push_back(v);
    }
    converter::IrMesh m;
    m.name = "rock" + std::to_string(index);
    m.primitives.push_back(std::move(p));
    return m;
}

} // namespace

// Rock `index` through the converter's mesh pipeline with pnb-convert's --lods 4 settings.
ProcessedRock
processRock(uint32_t index, uint32_t triangles, uint32_t material) {
    converter::StreamNeeds needs;
    needs.uv0 = true; // the panel's material samples its texture
    converter::MeshSettings settings;
    settings.lodCount = 4;
    settings.lodRatio = 0.5f;
    converter::MeshStats stats;
    return converter::processMesh(makeRock(index, triangles, material), needs, settings, stats);
}

} // namespace stream_scene
