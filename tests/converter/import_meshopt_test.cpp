// Tests of EXT_meshopt_compression + KHR_mesh_quantization import (converter/src/gltf_meshopt.cpp
// and import_gltf.cpp), on files Debian's gltfpack writes at test time from an uncompressed
// source scene: every compressed variant must import to the source's triangles, within the
// quantisation gltfpack applied. Also the errors: corrupt or truncated compressed streams, and
// image-format extensions we cannot decode. Skipped when gltfpack is not installed.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/png_writer.h"
#include "pnb_converter/convert.h"
#include "pnb_converter/importers.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;
namespace gltf = pnb::assets::gltf;

// [SECTION] the source scene

// An 8x8 RGB checker, so textured materials carry a real PNG through gltfpack.
gltf::Image checker(const char* name, uint8_t tint) {
    std::vector<uint8_t> pixels;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const uint8_t v = (x + y) % 2 ? 230 : 20;
            pixels.insert(pixels.end(), {v, uint8_t(v / 2 + tint), tint});
        }
    return {name, assets::encodePng(8, 8, 3, pixels)};
}

// A bumpy n x n grid over [-2, 2]^2 with analytic smooth normals and UVs 0..1: shared
// vertices, curved normals and a textured material, unlike the box.
gltf::Primitive terrain(int n, uint32_t material) {
    gltf::Primitive p;
    p.material = material;
    auto height = [](float x, float z) { return 0.4f * std::sin(1.7f * x) * std::cos(1.3f * z); };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float u = float(i) / float(n), v = float(j) / float(n);
            const float x = -2 + 4 * u, z = -2 + 4 * v;
            p.positions.push_back({x, height(x, z), z});
            const float dx = 0.4f * 1.7f * std::cos(1.7f * x) * std::cos(1.3f * z);
            const float dz = -0.4f * 1.3f * std::sin(1.7f * x) * std::sin(1.3f * z);
            const float len = std::sqrt(dx * dx + 1 + dz * dz);
            p.normals.push_back({-dx / len, 1 / len, -dz / len});
            p.uv0.push_back({u, v});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1),
                           d = c + 1;
            p.indices.insert(p.indices.end(), {a, c, b, b, c, d}); // counter-clockwise from +Y
        }
    return p;
}

// A box with flat normals (duplicated corners), untextured.
gltf::Primitive box(float sx, float sy, float sz, uint32_t material) {
    gltf::Primitive p;
    p.material = material;
    const float h[3] = {sx / 2, sy / 2, sz / 2};
    for (int axis = 0; axis < 3; ++axis)
        for (int sign = -1; sign <= 1; sign += 2) {
            gltf::Float3 normal{0, 0, 0};
            normal[size_t(axis)] = float(sign);
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            const auto base = uint32_t(p.positions.size());
            for (int c = 0; c < 4; ++c) {
                gltf::Float3 q{0, 0, 0};
                q[size_t(axis)] = float(sign) * h[axis];
                q[size_t(u)] = (c == 1 || c == 2 ? 1.0f : -1.0f) * h[u];
                q[size_t(v)] = (c >= 2 ? 1.0f : -1.0f) * h[v];
                p.positions.push_back(q);
                p.normals.push_back(normal);
            }
            if (sign > 0)
                p.indices.insert(p.indices.end(),
                                 {base, base + 1, base + 2, base, base + 2, base + 3});
            else
                p.indices.insert(p.indices.end(),
                                 {base, base + 2, base + 1, base, base + 3, base + 2});
        }
    return p;
}

// A textured quad facing +Z.
gltf::Primitive quad(uint32_t material) {
    gltf::Primitive p;
    p.material = material;
    p.positions = {{-1, -0.5f, 0}, {1, -0.5f, 0}, {1, 0.5f, 0}, {-1, 0.5f, 0}};
    p.normals.assign(4, {0, 0, 1});
    p.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    p.indices = {0, 1, 2, 0, 2, 3};
    return p;
}

// Three named objects with rotations and translations (no scale: world distances equal mesh
// distances, which the tolerance derivation below relies on), two textured materials.
gltf::Document sourceScene() {
    gltf::Document doc;
    doc.images = {checker("ground", 40), checker("poster", 200)};
    gltf::Material ground, poster, paint;
    ground.name = "ground";
    ground.baseColorImage = 0;
    poster.name = "poster";
    poster.baseColorImage = 1;
    paint.name = "paint";
    paint.baseColorFactor = {0.8f, 0.2f, 0.1f, 1};
    doc.materials = {ground, poster, paint};
    auto add = [&](const char* name, gltf::Primitive p, gltf::Float3 t, gltf::Float4 r) {
        doc.meshes.push_back({name, {std::move(p)}});
        gltf::Node node;
        node.name = name;
        node.mesh = int32_t(doc.meshes.size() - 1);
        node.translation = t;
        node.rotation = r;
        doc.nodes.push_back(node);
    };
    const float s = std::sin(0.3f), c = std::cos(0.3f);
    add("Terrain", terrain(24, 0), {0, -1, 0}, {0, 0, 0, 1});
    add("Poster", quad(1), {0.5f, 1, -2.5f}, {0, s, 0, c});
    add("Crate", box(1, 0.6f, 0.8f, 2), {-1.2f, 0.2f, 0.7f}, {s, 0, 0, c});
    return doc;
}

// [SECTION] world-space triangles

struct Vertex {
    std::array<double, 3> position{}, normal{};
    std::array<double, 2> uv{};
    bool hasNormal = false, hasUv = false;
};
using Triangle = std::array<Vertex, 3>;

struct Affine {                                         // column-major 3x3 plus translation
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; // m[column][row]
    double t[3] = {0, 0, 0};

    std::array<double, 3> apply(const float* p) const {
        std::array<double, 3> r{};
        for (int row = 0; row < 3; ++row)
            r[size_t(row)] = m[0][row] * p[0] + m[1][row] * p[1] + m[2][row] * p[2] + t[row];
        return r;
    }
    Affine operator*(const Affine& b) const {
        Affine r;
        for (int col = 0; col < 3; ++col)
            for (int row = 0; row < 3; ++row)
                r.m[col][row] =
                    m[0][row] * b.m[col][0] + m[1][row] * b.m[col][1] + m[2][row] * b.m[col][2];
        for (int row = 0; row < 3; ++row)
            r.t[row] = m[0][row] * b.t[0] + m[1][row] * b.t[1] + m[2][row] * b.t[2] + t[row];
        return r;
    }
};

Affine trs(const IrNode& n) {
    const double x = n.rotation.x, y = n.rotation.y, z = n.rotation.z, w = n.rotation.w;
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)},
                            {2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)},
                            {2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)}};
    const double s[3] = {n.scale.x, n.scale.y, n.scale.z};
    Affine a;
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row)
            a.m[col][row] = r[col][row] * s[col];
    a.t[0] = n.translation.x;
    a.t[1] = n.translation.y;
    a.t[2] = n.translation.z;
    return a;
}

// Normals transform with the cofactor matrix (the inverse transpose times the determinant),
// which stays right under gltfpack's non-uniform dequantisation scales.
std::array<double, 3> transformNormal(const Affine& a, const float* n) {
    auto at = [&](int row, int col) { return a.m[col][row]; };
    double cof[3][3];
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) {
            const int r1 = (row + 1) % 3, r2 = (row + 2) % 3, c1 = (col + 1) % 3,
                      c2 = (col + 2) % 3;
            cof[row][col] = at(r1, c1) * at(r2, c2) - at(r1, c2) * at(r2, c1);
        }
    const double det = at(0, 0) * cof[0][0] + at(0, 1) * cof[0][1] + at(0, 2) * cof[0][2];
    std::array<double, 3> r{};
    for (int row = 0; row < 3; ++row)
        r[size_t(row)] =
            (cof[row][0] * n[0] + cof[row][1] * n[1] + cof[row][2] * n[2]) * (det < 0 ? -1 : 1);
    const double len = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (double& v : r)
        v /= len > 0 ? len : 1;
    return r;
}

// Every triangle the scene draws, in world space. UVs go through the base colour texture's
// KHR_texture_transform (offset and scale: gltfpack's UV dequantisation) and are kept only for
// textured materials, the only ones whose UVs gltfpack must preserve.
std::vector<Triangle> worldTriangles(const IrScene& s) {
    std::vector<Affine> world(s.nodes.size());
    std::vector<Triangle> out;
    for (size_t i = 0; i < s.nodes.size(); ++i) {
        const IrNode& node = s.nodes[i];
        world[i] = node.parent < 0 ? trs(node) : world[size_t(node.parent)] * trs(node);
        if (node.mesh < 0) continue;
        for (const IrPrimitive& p : s.meshes[size_t(node.mesh)].primitives) {
            const IrTextureRef* tex = nullptr;
            if (p.material >= 0) {
                const IrTextureRef& t =
                    s.materials[size_t(p.material)].textures[size_t(TextureSlotKind::BaseColor)];
                if (t.image >= 0) tex = &t;
            }
            for (size_t k = 0; k + 2 < p.indices.size(); k += 3) {
                Triangle tri;
                for (size_t c = 0; c < 3; ++c) {
                    const size_t v = p.indices[k + c];
                    Vertex& vertex = tri[c];
                    vertex.position = world[i].apply(&p.positions[v * 3]);
                    if (!p.normals.empty()) {
                        vertex.normal = transformNormal(world[i], &p.normals[v * 3]);
                        vertex.hasNormal = true;
                    }
                    if (tex && !p.uv0.empty()) {
                        vertex.uv = {tex->offset.x + tex->scale.x * p.uv0[v * 2],
                                     tex->offset.y + tex->scale.y * p.uv0[v * 2 + 1]};
                        vertex.hasUv = true;
                    }
                }
                out.push_back(tri);
            }
        }
    }
    return out;
}

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
}

struct Tolerance {
    double position = 0;  // world units, Euclidean
    double normalCos = 1; // minimum dot product of unit normals
    double uv = 0;        // per component
};

struct Comparison {
    size_t matched = 0;
    double worstPosition = 0, worstNormalCos = 1, worstUv = 0;
    std::string firstMiss;
};

// Pairs every source triangle with a distinct decoded triangle whose vertices, in the same
// winding (any rotation), lie within the position tolerance; then checks normals and UVs of the
// paired vertices.
Comparison compare(const std::vector<Triangle>& source, const std::vector<Triangle>& decoded,
                   const Tolerance& tol) {
    Comparison r;
    std::vector<bool> used(decoded.size(), false);
    for (const Triangle& s : source) {
        bool found = false;
        for (size_t d = 0; d < decoded.size() && !found; ++d) {
            if (used[d]) continue;
            for (int rot = 0; rot < 3 && !found; ++rot) {
                double worst = 0;
                for (int c = 0; c < 3; ++c)
                    worst = std::max(worst, distance(s[size_t(c)].position,
                                                     decoded[d][size_t((c + rot) % 3)].position));
                if (worst > tol.position) continue;
                found = true;
                used[d] = true;
                ++r.matched;
                r.worstPosition = std::max(r.worstPosition, worst);
                for (int c = 0; c < 3; ++c) {
                    const Vertex& a = s[size_t(c)];
                    const Vertex& b = decoded[d][size_t((c + rot) % 3)];
                    if (a.hasNormal && b.hasNormal) {
                        const double dot = a.normal[0] * b.normal[0] + a.normal[1] * b.normal[1] +
                                           a.normal[2] * b.normal[2];
                        r.worstNormalCos = std::min(r.worstNormalCos, dot);
                    } else if (a.hasNormal != b.hasNormal) {
                        r.worstNormalCos = -2; // lost or invented normals
                    }
                    if (a.hasUv && b.hasUv) {
                        r.worstUv = std::max(
                            {r.worstUv, std::abs(a.uv[0] - b.uv[0]), std::abs(a.uv[1] - b.uv[1])});
                    } else if (a.hasUv != b.hasUv) {
                        r.worstUv = 1e9; // lost or invented UVs
                    }
                }
            }
        }
        if (!found && r.firstMiss.empty()) {
            const auto& p = s[0].position;
            r.firstMiss = "(" + std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " +
                          std::to_string(p[2]) + ")";
        }
    }
    return r;
}

// [SECTION] gltfpack and GLB surgery

const char* gltfpack() {
#ifdef PNB_GLTFPACK
    return PNB_GLTFPACK;
#else
    return "";
#endif
}

#define PNB_REQUIRE_GLTFPACK()                                                                     \
    do {                                                                                           \
        if (!*gltfpack()) GTEST_SKIP() << "gltfpack is not installed";                             \
    } while (0)

struct Glb {
    nlohmann::json json;
    std::vector<uint8_t> bin;
};

std::vector<uint8_t> readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

uint32_t u32(const uint8_t* p) {
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

Glb readGlb(const fs::path& p) {
    const std::vector<uint8_t> b = readBytes(p);
    Glb g;
    const uint32_t jsonLength = u32(&b[12]);
    g.json = nlohmann::json::parse(b.begin() + 20, b.begin() + 20 + jsonLength);
    const size_t binAt = 20 + jsonLength;
    if (binAt + 8 <= b.size()) {
        const uint32_t binLength = u32(&b[binAt]);
        g.bin.assign(b.begin() + std::ptrdiff_t(binAt + 8),
                     b.begin() + std::ptrdiff_t(binAt + 8 + binLength));
    }
    return g;
}

void writeGlb(const fs::path& p, const Glb& g) {
    std::string json = g.json.dump();
    while (json.size() % 4)
        json.push_back(' ');
    std::vector<uint8_t> bin = g.bin;
    while (bin.size() % 4)
        bin.push_back(0);
    std::vector<uint8_t> out;
    auto put = [&](uint32_t v) {
        for (int i = 0; i < 4; ++i)
            out.push_back(uint8_t(v >> (8 * i)));
    };
    out.insert(out.end(), {'g', 'l', 'T', 'F'});
    put(2);
    put(uint32_t(28 + json.size() + bin.size()));
    put(uint32_t(json.size()));
    put(0x4E4F534Au);
    out.insert(out.end(), json.begin(), json.end());
    put(uint32_t(bin.size()));
    put(0x004E4942u);
    out.insert(out.end(), bin.begin(), bin.end());
    std::ofstream(p, std::ios::binary)
        .write(reinterpret_cast<const char*>(out.data()), std::streamsize(out.size()));
}

class Meshopt : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_meshopt_" + std::to_string(getpid()) + "_" + info->name());
        fs::create_directories(dir);
        source = dir / "source.glb";
        const std::vector<uint8_t> bytes = gltf::encodeGlb(sourceScene());
        std::ofstream(source, std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }

    // Runs gltfpack on the source scene; false (with a test failure) if it fails.
    bool pack(const std::string& options, const fs::path& out) {
        const std::string cmd = std::string(gltfpack()) + " -i '" + source.string() + "' -o '" +
                                out.string() + "' " + options + " > '" + (dir / "log").string() +
                                "' 2>&1";
        const int rc = std::system(cmd.c_str());
        EXPECT_EQ(rc, 0) << cmd;
        return rc == 0 && fs::exists(out);
    }

    fs::path dir, source;
};

// The largest axis extent of the union of the primitives' bounding boxes, taken both in mesh
// space and in world space: gltfpack 0.18 quantises positions with one uniform scale, the
// largest extent of the union of the meshes' boxes in the space it stores them in (mesh space
// for meshes it keeps on their nodes, world space when it bakes transforms). Either way its
// step is at most this extent / (2^bits - 1).
double quantisationExtent(const IrScene& s, const std::vector<Triangle>& world) {
    double lo[2][3], hi[2][3];
    for (int k = 0; k < 2; ++k)
        for (int c = 0; c < 3; ++c)
            lo[k][c] = 1e30, hi[k][c] = -1e30;
    for (const IrMesh& m : s.meshes)
        for (const IrPrimitive& p : m.primitives)
            for (size_t i = 0; i < p.positions.size(); ++i) {
                lo[0][i % 3] = std::min(lo[0][i % 3], double(p.positions[i]));
                hi[0][i % 3] = std::max(hi[0][i % 3], double(p.positions[i]));
            }
    for (const Triangle& t : world)
        for (const Vertex& v : t)
            for (size_t c = 0; c < 3; ++c) {
                lo[1][c] = std::min(lo[1][c], v.position[c]);
                hi[1][c] = std::max(hi[1][c], v.position[c]);
            }
    double extent = 0;
    for (int k = 0; k < 2; ++k)
        for (int c = 0; c < 3; ++c)
            extent = std::max(extent, hi[k][c] - lo[k][c]);
    return extent;
}

struct Variant {
    const char* options;
    const char* file;
    int positionBits, normalBits, uvBits;
};

// [SECTION] gltfpack output imports as the source

TEST_F(Meshopt, GltfpackVariantsImportAsTheSourceWithinTheQuantisationStep) {
    PNB_REQUIRE_GLTFPACK();
    auto src = importGltf(source.string());
    ASSERT_TRUE(src.ok()) << src.error().message;
    const std::vector<Triangle> expected = worldTriangles(*src);
    ASSERT_EQ(expected.size(), 24u * 24 * 2 + 2 + 12);
    const double extent = quantisationExtent(*src, expected);

    const Variant variants[] = {
        {"-c", "c.glb", 14, 8, 12},         // meshopt + quantisation (gltfpack's defaults)
        {"-cc", "cc.glb", 14, 8, 12},       // + filters (octahedral normals, ...)
        {"-cf", "cf.glb", 14, 8, 12},       // compressed with an uncompressed fallback
        {"-c -kn", "kn.glb", 14, 8, 12},    // named nodes kept: per-node dequantisation
        {"-cc -vpn", "vpn.glb", 14, 8, 12}, // normalized positions
        {"-cc -vp 16 -vn 12 -vt 16", "hi.glb", 16, 12, 16}, // 16-bit streams, 16-bit oct normals
        {"-c", "c.gltf", 14, 8, 12}, // .gltf + .bin: a fallback buffer with no uri
    };
    for (const Variant& v : variants) {
        SCOPED_TRACE(std::string("gltfpack ") + v.options + " -> " + v.file);
        const fs::path out = dir / v.file;
        if (!pack(v.options, out)) continue;
        if (fs::path(v.file).extension() == ".glb") { // what is being tested is really there
            const Glb g = readGlb(out);
            auto lists = [&](const char* list, const char* extension) {
                const auto& names = g.json.value(list, nlohmann::json::array());
                return std::find(names.begin(), names.end(), extension) != names.end();
            };
            EXPECT_TRUE(lists("extensionsRequired", "KHR_mesh_quantization"));
            EXPECT_TRUE(lists("extensionsUsed", "EXT_meshopt_compression"));
            // -cf's fallback makes the extension optional; everything else requires it.
            EXPECT_EQ(lists("extensionsRequired", "EXT_meshopt_compression"),
                      std::string(v.options) != "-cf");
        }
        auto r = importGltf(out.string());
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(r->images.size(), 2u); // the PNGs are carried through as they were
        for (const IrImage& image : r->images)
            EXPECT_EQ(image.mimeType, "image/png");
        const std::vector<Triangle> decoded = worldTriangles(*r);
        ASSERT_EQ(decoded.size(), expected.size());

        // Positions: half a step per axis, so half the step's diagonal, plus float rounding.
        const double step = extent / double((1 << v.positionBits) - 1);
        // Normals: snorm with `normalBits` bits, octahedral or not, is within 2 steps of
        // 1 / (2^(bits-1) - 1) per component of the unit vector (octahedral decoding at most
        // doubles the error of its two stored components); angle = that chord.
        const double normalChord = 2 * std::sqrt(3.0) / double((1 << (v.normalBits - 1)) - 1);
        Tolerance tol;
        tol.position = std::sqrt(3.0) * step / 2 + 1e-6 * extent;
        tol.normalCos = 1 - normalChord * normalChord / 2;
        // UVs span [0, 1] per material, quantised to `uvBits` over that range.
        tol.uv = 0.5 / double((1 << v.uvBits) - 1) + 1e-6;
        const Comparison c = compare(expected, decoded, tol);
        EXPECT_EQ(c.matched, expected.size())
            << "first unmatched source triangle at " << c.firstMiss << " (tolerance "
            << tol.position << ")";
        EXPECT_LE(c.worstPosition, tol.position);
        EXPECT_GE(c.worstNormalCos, tol.normalCos);
        EXPECT_LE(c.worstUv, tol.uv);
        std::cout << "[ meshopt ] " << v.options << " " << v.file << ": " << decoded.size()
                  << " triangles, worst position error " << c.worstPosition << " (bound "
                  << tol.position << "), worst normal angle "
                  << std::acos(std::min(1.0, c.worstNormalCos)) * 180 / M_PI << " deg (bound "
                  << std::acos(tol.normalCos) * 180 / M_PI << "), worst uv error " << c.worstUv
                  << " (bound " << tol.uv << ")\n";
    }
}

TEST_F(Meshopt, CompressedFileConvertsEndToEnd) {
    PNB_REQUIRE_GLTFPACK();
    const fs::path packed = dir / "cc.glb";
    ASSERT_TRUE(pack("-cc", packed));
    ConvertSettings s;
    s.input = packed.string();
    s.output = (dir / "cc.pnb").string();
    s.jobs = 1;
    s.noSidecar = true;
    s.validateShaders = false;
    auto r = convertScene(s);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(fs::file_size(s.output) > 0);
}

// gltfpack uses INDICES mode and the QUATERNION and EXPONENTIAL filters only for animation
// data, so this file is written here with meshoptimizer's encoders: positions as EXPONENTIAL
// floats, a QUATERNION-filtered VEC4 (as TANGENT, which takes normalized SHORT), indices as an
// INDICES sequence. Everything sits in a fallback buffer with no data.
TEST_F(Meshopt, IndexSequencesAndQuaternionAndExponentialFiltersDecode) {
    const std::vector<float> positions = {-1.5f, 0,     0.25f, 1,     0,     0.25f,
                                          1,     2.75f, -3,    -1.5f, 2.75f, -3};
    const float h = std::sqrt(0.5f);
    const std::vector<float> quats = {0, 0, 0, 1, h, 0, 0, h, 0, h, 0, -h, 0.5f, 0.5f, 0.5f, 0.5f};
    const std::vector<unsigned> indices = {0, 1, 2, 0, 2, 3};
    const size_t n = 4;

    Glb g;
    nlohmann::json views = nlohmann::json::array();
    size_t fallbackSize = 0;
    // Appends a compressed stream to the BIN chunk and a bufferView decoding to the fallback.
    auto addView = [&](const std::vector<uint8_t>& encoded, size_t count, size_t stride,
                       const char* mode, const char* filter) {
        while (g.bin.size() % 4)
            g.bin.push_back(0);
        nlohmann::json ext = {{"buffer", 0},
                              {"byteOffset", g.bin.size()},
                              {"byteLength", encoded.size()},
                              {"byteStride", stride},
                              {"count", count},
                              {"mode", mode}};
        if (filter) ext["filter"] = filter;
        g.bin.insert(g.bin.end(), encoded.begin(), encoded.end());
        views.push_back({{"buffer", 1},
                         {"byteOffset", fallbackSize},
                         {"byteLength", count * stride},
                         {"extensions", {{"EXT_meshopt_compression", ext}}}});
        fallbackSize += (count * stride + 3) / 4 * 4;
        return views.size() - 1;
    };
    auto encodeVertices = [](const void* data, size_t count, size_t stride) {
        std::vector<uint8_t> out(meshopt_encodeVertexBufferBound(count, stride));
        out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), data, count, stride));
        return out;
    };
    std::vector<uint8_t> expPositions(n * 12);
    meshopt_encodeFilterExp(expPositions.data(), n, 12, 16, positions.data());
    const size_t positionView =
        addView(encodeVertices(expPositions.data(), n, 12), n, 12, "ATTRIBUTES", "EXPONENTIAL");
    std::vector<uint8_t> quatData(n * 8);
    meshopt_encodeFilterQuat(quatData.data(), n, 8, 12, quats.data());
    const size_t quatView =
        addView(encodeVertices(quatData.data(), n, 8), n, 8, "ATTRIBUTES", "QUATERNION");
    std::vector<uint8_t> sequence(meshopt_encodeIndexSequenceBound(indices.size(), n));
    sequence.resize(meshopt_encodeIndexSequence(sequence.data(), sequence.size(), indices.data(),
                                                indices.size()));
    const size_t indexView = addView(sequence, indices.size(), 4, "INDICES", nullptr);
    while (g.bin.size() % 4)
        g.bin.push_back(0);

    g.json = {
        {"asset", {{"version", "2.0"}}},
        {"extensionsUsed", {"EXT_meshopt_compression"}},
        {"extensionsRequired", {"EXT_meshopt_compression"}},
        {"buffers",
         {{{"byteLength", g.bin.size()}},
          {{"byteLength", fallbackSize},
           {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}}},
        {"bufferViews", views},
        {"accessors",
         {{{"bufferView", positionView}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"}},
          {{"bufferView", quatView},
           {"componentType", 5122},
           {"normalized", true},
           {"count", n},
           {"type", "VEC4"}},
          {{"bufferView", indexView}, {"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}}}},
        {"meshes",
         {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TANGENT", 1}}}, {"indices", 2}}}}}}},
        {"nodes", {{{"mesh", 0}}}},
        {"scenes", {{{"nodes", {0}}}}},
        {"scene", 0}};
    writeGlb(dir / "filters.glb", g);
    auto r = importGltf((dir / "filters.glb").string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->meshes.size(), 1u);
    ASSERT_EQ(r->meshes[0].primitives.size(), 1u);
    const IrPrimitive& p = r->meshes[0].primitives[0];
    EXPECT_EQ(p.indices, std::vector<uint32_t>(indices.begin(), indices.end()));
    ASSERT_EQ(p.positions.size(), positions.size());
    // 16-bit mantissas shared per vector: relative error 2^-15 of the vector's largest value.
    for (size_t i = 0; i < positions.size(); ++i)
        EXPECT_NEAR(p.positions[i], positions[i], 3.0 / 32768) << i;
    ASSERT_EQ(p.tangents.size(), quats.size());
    // 12-bit components, then stored as normalized SHORT: q or -q (the same rotation).
    for (size_t v = 0; v < n; ++v) {
        double dot = 0;
        for (size_t c = 0; c < 4; ++c)
            dot += double(p.tangents[v * 4 + c]) * quats[v * 4 + c];
        EXPECT_NEAR(std::abs(dot), 1.0, 1e-3) << "quaternion " << v;
    }
}

// [SECTION] errors

// The first compressed bufferView whose mode is `mode`.
const nlohmann::json* compressedView(const Glb& g, const char* mode, size_t& index) {
    const auto& views = g.json["bufferViews"];
    for (index = 0; index < views.size(); ++index) {
        const auto& v = views[index];
        if (v.contains("extensions") && v["extensions"].contains("EXT_meshopt_compression") &&
            v["extensions"]["EXT_meshopt_compression"]["mode"] == mode)
            return &v["extensions"]["EXT_meshopt_compression"];
    }
    return nullptr;
}

TEST_F(Meshopt, CorruptOrTruncatedStreamsAreErrorsNamingTheBufferView) {
    PNB_REQUIRE_GLTFPACK();
    const fs::path packed = dir / "c.glb";
    ASSERT_TRUE(pack("-c", packed));
    const Glb original = readGlb(packed);

    struct Case {
        const char* what;
        const char* mode;
        void (*damage)(Glb&, const nlohmann::json& ext, size_t view);
        const char* expect;
    };
    const Case cases[] = {
        {"vertex stream header overwritten", "ATTRIBUTES",
         [](Glb& g, const nlohmann::json& ext, size_t) {
             g.bin[ext.value("byteOffset", size_t(0))] = 0x00; // not a vertex codec header
         },
         "truncated or corrupt"},
        {"index stream garbage", "TRIANGLES",
         [](Glb& g, const nlohmann::json& ext, size_t) {
             const size_t at = ext.value("byteOffset", size_t(0));
             const size_t n = ext["byteLength"].get<size_t>();
             for (size_t i = 0; i < n; ++i)
                 g.bin[at + i] = uint8_t(0xFF - i);
         },
         "truncated or corrupt"},
        {"vertex stream truncated", "ATTRIBUTES",
         [](Glb& g, const nlohmann::json& ext, size_t view) {
             g.json["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]["byteLength"] =
                 ext["byteLength"].get<size_t>() / 2;
         },
         "truncated or corrupt"},
        {"compressed range past the buffer", "ATTRIBUTES",
         [](Glb& g, const nlohmann::json&, size_t view) {
             g.json["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]["byteOffset"] =
                 g.bin.size();
         },
         "exceeds buffer"},
        {"count larger than the bufferView", "ATTRIBUTES",
         [](Glb& g, const nlohmann::json& ext, size_t view) {
             g.json["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]["count"] =
                 ext["count"].get<size_t>() * 1000;
         },
         "exceeds the bufferView"},
        {"stride the decoder cannot take", "ATTRIBUTES",
         [](Glb& g, const nlohmann::json&, size_t view) {
             g.json["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]["byteStride"] = 6;
         },
         "byteStride 6"},
        {"unknown filter", "ATTRIBUTES",
         [](Glb& g, const nlohmann::json&, size_t view) {
             g.json["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]["filter"] =
                 "SPIRAL";
         },
         "filter"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        Glb damaged = original;
        size_t view = 0;
        const nlohmann::json* ext = compressedView(damaged, c.mode, view);
        ASSERT_NE(ext, nullptr) << "no " << c.mode << " view in gltfpack's output";
        const nlohmann::json extCopy = *ext;
        c.damage(damaged, extCopy, view);
        const fs::path bad = dir / "damaged.glb";
        writeGlb(bad, damaged);
        auto r = importGltf(bad.string());
        ASSERT_FALSE(r.ok());
        const std::string& msg = r.error().message;
        EXPECT_EQ(r.error().kind, ConvertErrorKind::Input) << msg;
        EXPECT_NE(msg.find("damaged.glb"), std::string::npos) << msg;
        EXPECT_NE(msg.find("bufferView " + std::to_string(view)), std::string::npos) << msg;
        EXPECT_NE(msg.find("EXT_meshopt_compression"), std::string::npos) << msg;
        EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
    }
}

TEST_F(Meshopt, FallbackBufferLargerThanTheBudgetIsRefusedBeforeAllocating) {
    PNB_REQUIRE_GLTFPACK();
    const fs::path packed = dir / "c.glb";
    ASSERT_TRUE(pack("-c", packed));
    Glb g = readGlb(packed);
    bool found = false;
    for (auto& b : g.json["buffers"]) {
        if (b.contains("extensions") && b["extensions"].contains("EXT_meshopt_compression")) {
            b["byteLength"] = uint64_t(1) << 50; // 1 PiB
            found = true;
        }
    }
    ASSERT_TRUE(found);
    writeGlb(dir / "huge.glb", g);
    auto r = importGltf((dir / "huge.glb").string());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("limit"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("huge.glb"), std::string::npos) << r.error().message;
}

// KHR_texture_basisu and EXT_texture_webp: a texture with only the extension's image is an
// Unsupported error naming the file, the extension and the image; one that also names an
// ordinary fallback image uses it.
TEST_F(Meshopt, ImageFormatExtensionsNeedAFallbackImage) {
    for (const char* extension : {"KHR_texture_basisu", "EXT_texture_webp"}) {
        SCOPED_TRACE(extension);
        Glb g = readGlb(source);
        g.json["extensionsUsed"].push_back(extension);
        g.json["extensionsRequired"].push_back(extension);
        auto& texture = g.json["textures"][0];
        texture["extensions"][extension]["source"] = texture["source"];
        g.json["images"][texture["source"].get<size_t>()]["name"] = "ground-compressed";

        writeGlb(dir / "fallback.glb", g);
        auto withFallback = importGltf((dir / "fallback.glb").string());
        ASSERT_TRUE(withFallback.ok()) << withFallback.error().message;
        EXPECT_EQ(withFallback->images.size(), 2u);

        texture.erase("source");
        writeGlb(dir / "nofallback.glb", g);
        auto r = importGltf((dir / "nofallback.glb").string());
        ASSERT_FALSE(r.ok());
        const std::string& msg = r.error().message;
        EXPECT_EQ(r.error().kind, ConvertErrorKind::Unsupported) << msg;
        EXPECT_NE(msg.find("nofallback.glb"), std::string::npos) << msg;
        EXPECT_NE(msg.find(extension), std::string::npos) << msg;
        EXPECT_NE(msg.find("image 'ground-compressed'"), std::string::npos) << msg;
    }
}

} // namespace
