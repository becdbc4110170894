// End-to-end conversion: source → pnb-convert's core → container → reader. Geometric fidelity
// against the importer's view of the source, determinism across job counts, sidecars, depfiles,
// "only what the scene requires", and the error paths.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <unordered_map>

#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/procedural_scenes.h"
#include "pnb_converter/convert.h"
#include "pnb_converter/importers.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;

const char* kBoxTextured = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";

class Convert : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_convert_" + std::string(info->name()) + "_" + std::to_string(getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    fs::path writeScene(const char* name, const assets::gltf::Document& doc) {
        fs::path p = dir / (std::string(name) + ".glb");
        auto bytes = assets::gltf::encodeGlb(doc);
        std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                 std::streamsize(bytes.size()));
        return p;
    }

    ConvertSettings settings(const fs::path& in, const char* out) {
        ConvertSettings s;
        s.input = in.string();
        s.output = (dir / out).string();
        return s;
    }

    static std::vector<char> bytesOf(const std::string& path) {
        std::ifstream f(path, std::ios::binary);
        return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
    }
};

// [SECTION] decoding a container mesh back to floats (FORMAT.md §4.3)

float halfToFloat(uint16_t h) {
    uint32_t sign = uint32_t(h >> 15) << 31, exp = (h >> 10) & 31, mant = h & 1023;
    if (exp == 0) return (sign ? -1.0f : 1.0f) * std::ldexp(float(mant), -24);
    if (exp == 31) return mant ? NAN : (sign ? -INFINITY : INFINITY);
    uint32_t bits = sign | ((exp + 112) << 23) | (mant << 13);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

float componentAt(const VertexStream& s, size_t index) {
    const std::byte* p = s.data.data() + index * componentSizeBytes(s.componentType);
    switch (s.componentType) {
    case ComponentType::F32: { float v; std::memcpy(&v, p, 4); return v; }
    case ComponentType::F16: { uint16_t v; std::memcpy(&v, p, 2); return halfToFloat(v); }
    case ComponentType::U16: { uint16_t v; std::memcpy(&v, p, 2); return s.normalized ? v / 65535.0f : v; }
    case ComponentType::I16: {
        int16_t v;
        std::memcpy(&v, p, 2);
        return s.normalized ? std::max(v / 32767.0f, -1.0f) : v;
    }
    case ComponentType::U8: return s.normalized ? uint8_t(*p) / 255.0f : float(uint8_t(*p));
    default: ADD_FAILURE() << "unexpected component type"; return 0;
    }
}

// Attribute `semantic` of vertex v as xyz(w) floats, decoded as the player would.
std::vector<float> attribute(const Mesh& m, VertexSemantic semantic, uint32_t v) {
    for (const VertexStream& s : m.streams) {
        if (s.semantic != semantic) continue;
        std::vector<float> out;
        for (uint8_t c = 0; c < s.componentCount; ++c)
            out.push_back(componentAt(s, size_t(v) * s.componentCount + c));
        if (s.encoding == VertexEncoding::Octahedral) {
            float x = out[0], y = out[1], z = 1 - std::fabs(x) - std::fabs(y);
            if (z < 0) {
                float ox = (1 - std::fabs(y)) * (x >= 0 ? 1 : -1);
                float oy = (1 - std::fabs(x)) * (y >= 0 ? 1 : -1);
                x = ox, y = oy;
            }
            float l = std::sqrt(x * x + y * y + z * z);
            out = {x / l, y / l, z / l};
        }
        const float* scale = &s.dequantScale.x;
        const float* offset = &s.dequantOffset.x;
        if (semantic == VertexSemantic::Position)
            for (size_t c = 0; c < 3 && c < out.size(); ++c) out[c] = out[c] * scale[c] + offset[c];
        return out;
    }
    return {};
}

uint32_t indexAt(const Mesh& m, size_t k) {
    if (m.indexType == IndexType::U16) {
        uint16_t v;
        std::memcpy(&v, m.indices.data() + k * 2, 2);
        return v;
    }
    uint32_t v;
    std::memcpy(&v, m.indices.data() + k * 4, 4);
    return v;
}

struct Corner {
    float p[3], n[3], uv[2];
};
using Triangle = std::array<Corner, 3>;

// Level-0 triangles of a container mesh.
std::vector<Triangle> containerTriangles(const Mesh& m) {
    std::vector<Triangle> tris;
    for (const Submesh& sm : m.submeshes) {
        if (sm.lod != 0) continue;
        for (uint32_t k = sm.firstIndex; k + 2 < sm.firstIndex + sm.indexCount + 0u; k += 3) {
            Triangle t;
            for (int c = 0; c < 3; ++c) {
                uint32_t v = indexAt(m, k + c);
                auto p = attribute(m, VertexSemantic::Position, v);
                auto n = attribute(m, VertexSemantic::Normal, v);
                auto uv = attribute(m, VertexSemantic::TexCoord0, v);
                for (int i = 0; i < 3; ++i) t[c].p[i] = p[i], t[c].n[i] = n.empty() ? 0 : n[i];
                t[c].uv[0] = uv.empty() ? 0 : uv[0];
                t[c].uv[1] = uv.empty() ? 0 : uv[1];
            }
            tris.push_back(t);
        }
    }
    return tris;
}

// Triangles of an IR mesh (the importer's view of the source).
std::vector<Triangle> sourceTriangles(const IrMesh& mesh) {
    std::vector<Triangle> tris;
    for (const IrPrimitive& p : mesh.primitives)
        for (size_t k = 0; k + 2 < p.indices.size(); k += 3) {
            Triangle t;
            for (int c = 0; c < 3; ++c) {
                uint32_t v = p.indices[k + c];
                for (int i = 0; i < 3; ++i) {
                    t[c].p[i] = p.positions[v * 3 + i];
                    t[c].n[i] = p.normals.empty() ? 0 : p.normals[v * 3 + i];
                }
                t[c].uv[0] = p.uv0.empty() ? 0 : p.uv0[v * 2];
                t[c].uv[1] = p.uv0.empty() ? 0 : p.uv0[v * 2 + 1];
            }
            tris.push_back(t);
        }
    return tris;
}

// Every container triangle matches a distinct source triangle (same corners in the same cyclic
// order, so winding is kept) within the tolerances; returns how many matched.
size_t matchTriangles(const std::vector<Triangle>& source, const std::vector<Triangle>& out,
                      float posTol, float normalTol, float uvTol, bool compareNormals,
                      bool compareUvs) {
    auto cell = [&](const Triangle& t) {
        float c[3];
        for (int i = 0; i < 3; ++i) c[i] = (t[0].p[i] + t[1].p[i] + t[2].p[i]) / 3;
        float size = std::max(posTol * 8, 1e-3f);
        return std::array<long, 3>{long(std::floor(c[0] / size)), long(std::floor(c[1] / size)),
                                   long(std::floor(c[2] / size))};
    };
    std::map<std::array<long, 3>, std::vector<size_t>> grid;
    for (size_t i = 0; i < source.size(); ++i) grid[cell(source[i])].push_back(i);
    std::vector<bool> used(source.size(), false);
    auto close = [](const float* a, const float* b, int n, float tol) {
        for (int i = 0; i < n; ++i)
            if (!(std::fabs(a[i] - b[i]) <= tol)) return false;
        return true;
    };
    size_t matched = 0;
    for (const Triangle& t : out) {
        auto c = cell(t);
        bool found = false;
        for (long dx = -1; dx <= 1 && !found; ++dx)
            for (long dy = -1; dy <= 1 && !found; ++dy)
                for (long dz = -1; dz <= 1 && !found; ++dz) {
                    auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == grid.end()) continue;
                    for (size_t si : it->second) {
                        if (used[si]) continue;
                        for (int rot = 0; rot < 3 && !found; ++rot) {
                            bool all = true;
                            for (int k = 0; k < 3 && all; ++k) {
                                const Corner& a = source[si][(k + rot) % 3];
                                const Corner& b = t[k];
                                all = close(a.p, b.p, 3, posTol) &&
                                      (!compareNormals || close(a.n, b.n, 3, normalTol)) &&
                                      (!compareUvs || close(a.uv, b.uv, 2, uvTol));
                            }
                            if (all) {
                                used[si] = true;
                                found = true;
                            }
                        }
                        if (found) break;
                    }
                }
        matched += found;
    }
    return matched;
}

// [SECTION] fidelity

void checkFidelity(const fs::path& input, const fs::path& output, bool quantize) {
    auto ir = importScene(input.string());
    ASSERT_TRUE(ir.ok()) << ir.error().message;
    ConvertSettings s;
    s.input = input.string();
    s.output = output.string();
    s.mesh.quantize = quantize;
    auto summary = convertScene(s);
    ASSERT_TRUE(summary.ok()) << summary.error().message;
    auto c = Container::open(s.output);
    ASSERT_TRUE(c.ok());
    ASSERT_TRUE(isOk(c->verifyAll()));
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    ASSERT_EQ(scene->meshes.size(), ir->meshes.size());
    uint64_t sourceTris = 0, outTris = 0;
    for (size_t i = 0; i < ir->meshes.size(); ++i) {
        auto src = sourceTriangles(ir->meshes[i]);
        auto out = containerTriangles(scene->meshes[i]);
        sourceTris += src.size();
        outTris += out.size();
        // Bounds: the summary's quantisation error, or float exactness.
        float posTol = quantize ? summary->maxPositionError * 1.01f + 1e-6f : 0.0f;
        bool hasNormals = !ir->meshes[i].primitives[0].normals.empty();
        bool hasUvs = !scene->meshes[i].streams.empty() &&
                      !attribute(scene->meshes[i], VertexSemantic::TexCoord0, 0).empty();
        float normalTol = quantize ? 2e-4f : 1e-6f; // renormalised source normals
        float uvTol = quantize ? 1e-3f : 0.0f;      // half floats: 11-bit mantissa on [0, 2)
        size_t matched = matchTriangles(src, out, posTol, normalTol, uvTol, hasNormals, hasUvs);
        EXPECT_EQ(matched, out.size()) << "mesh " << i << ": output triangles without a source "
                                       << "triangle within the bounds";
    }
    EXPECT_EQ(outTris, sourceTris - summary->degenerateTriangles - summary->nonFiniteTriangles);
    EXPECT_EQ(summary->outputTriangles, outTris);
}

TEST_F(Convert, GltfGeometryMatchesTheSourceExactlyUnquantized) {
    checkFidelity(kBoxTextured, dir / "box.pnb", false);
}

TEST_F(Convert, GltfGeometryMatchesTheSourceWithinTheQuantizationBound) {
    checkFidelity(kBoxTextured, dir / "box_q.pnb", true);
}

TEST_F(Convert, ProceduralSceneGeometryMatchesTheSource) {
    fs::path in = writeScene("canyon", assets::buildStreetCanyon({.targetTriangles = 3000}));
    checkFidelity(in, dir / "canyon.pnb", false);
    checkFidelity(in, dir / "canyon_q.pnb", true);
}

TEST_F(Convert, ObjGeometryMatchesTheSource) {
    checkFidelity("/usr/share/assimp/models/OBJ/spider.obj", dir / "spider.pnb", false);
}

// [SECTION] determinism, streams, programs, sidecar, depfile

TEST_F(Convert, OutputIsIdenticalForAnyJobCount) {
    fs::path in = writeScene("room", assets::buildBoxRoomGltf({}));
    ConvertSettings one = settings(in, "one.pnb"), eight = settings(in, "eight.pnb");
    one.jobs = 1;
    eight.jobs = 8;
    one.texture.compress = eight.texture.compress = true;
    ASSERT_TRUE(convertScene(one).ok());
    ASSERT_TRUE(convertScene(eight).ok());
    EXPECT_EQ(bytesOf(one.output), bytesOf(eight.output));
}

TEST_F(Convert, OnlyWhatTheSceneRequiresIsWritten) {
    auto summary = convertScene(settings(kBoxTextured, "box.pnb"));
    ASSERT_TRUE(summary.ok()) << summary.error().message;
    auto c = Container::open((dir / "box.pnb").string());
    ASSERT_TRUE(c.ok());
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok());
    for (const Mesh& m : scene->meshes)
        for (const VertexStream& s : m.streams) {
            EXPECT_NE(s.semantic, VertexSemantic::Tangent) << "no normal map: no tangents";
            EXPECT_NE(s.semantic, VertexSemantic::TexCoord1);
            EXPECT_NE(s.semantic, VertexSemantic::Color0);
        }
    for (const Program& p : scene->programs) {
        EXPECT_NE(scene->str(p.name), "forward") << "no forward material";
        for (StringRef d : p.defines) EXPECT_NE(scene->str(d), "HAS_NORMAL_MAP");
    }
    // The one material samples base colour through UV0: that variant, and only it, exists.
    const Material& m = scene->materials.at(0);
    ASSERT_NE(m.program, kNone);
    std::vector<std::string> defines;
    for (StringRef d : scene->programs[m.program].defines) defines.emplace_back(scene->str(d));
    EXPECT_EQ(defines, (std::vector<std::string>{"HAS_BASE_COLOR_MAP", "HAS_UV0"}));
    EXPECT_FALSE(summary->omitted.empty());
    EXPECT_TRUE(summary->defaultSun) << "BoxTextured has no light";
    ASSERT_EQ(scene->lights.lights.size(), 1u);
    EXPECT_TRUE(scene->lights.lights[0].generated);
}

TEST_F(Convert, SidecarNextToTheSourceIsAppliedAndDepfileListsInputs) {
    fs::path src = fs::path(kBoxTextured).parent_path();
    for (const auto& e : fs::directory_iterator(src)) fs::copy(e.path(), dir / e.path().filename());
    std::ofstream(dir / "BoxTextured.pnb.json")
        << R"({"materials": {"*": {"shading_path": "forward", "layer_priority": 3}}})";
    ConvertSettings s = settings(dir / "BoxTextured.gltf", "box.pnb");
    s.depfile = (dir / "box.pnb.d").string();
    auto summary = convertScene(s);
    ASSERT_TRUE(summary.ok()) << summary.error().message;
    auto c = Container::open(s.output);
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok());
    EXPECT_EQ(scene->materials[0].shadingPath, ShadingPath::Forward);
    EXPECT_EQ(scene->materials[0].layerPriority, 3);
    std::ifstream d(s.depfile);
    std::string dep((std::istreambuf_iterator<char>(d)), std::istreambuf_iterator<char>());
    for (const char* needed : {"box.pnb:", "BoxTextured.gltf", "BoxTextured0.bin",
                               "CesiumLogoFlat.png", "BoxTextured.pnb.json"})
        EXPECT_NE(dep.find(needed), std::string::npos) << needed << " missing from\n" << dep;
}

TEST_F(Convert, NodeBoundsContainTheirMeshInstances) {
    fs::path in = writeScene("canyon", assets::buildStreetCanyon({.targetTriangles = 2000}));
    ASSERT_TRUE(convertScene(settings(in, "canyon.pnb")).ok());
    auto c = Container::open((dir / "canyon.pnb").string());
    ASSERT_TRUE(c.ok());
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok());
    // World transforms (parents precede children), in double.
    const auto& nodes = scene->nodes.nodes;
    std::vector<std::array<double, 12>> world(nodes.size()); // 3x4, column-major
    size_t checked = 0;
    for (size_t i = 0; i < nodes.size(); ++i) {
        const Node& n = nodes[i];
        double x = n.rotation.x, y = n.rotation.y, z = n.rotation.z, w = n.rotation.w;
        std::array<double, 12> local = {
            (1 - 2 * (y * y + z * z)) * n.scale.x, 2 * (x * y + z * w) * n.scale.x,
            2 * (x * z - y * w) * n.scale.x,       2 * (x * y - z * w) * n.scale.y,
            (1 - 2 * (x * x + z * z)) * n.scale.y, 2 * (y * z + x * w) * n.scale.y,
            2 * (x * z + y * w) * n.scale.z,       2 * (y * z - x * w) * n.scale.z,
            (1 - 2 * (x * x + y * y)) * n.scale.z, n.translation.x, n.translation.y,
            n.translation.z};
        if (n.parent == kNone) {
            world[i] = local;
        } else {
            const auto& p = world[n.parent];
            for (int col = 0; col < 4; ++col)
                for (int row = 0; row < 3; ++row) {
                    double v = col == 3 ? p[9 + row] : 0;
                    for (int k = 0; k < 3; ++k) v += p[k * 3 + row] * local[col * 3 + k];
                    world[i][col * 3 + row] = v;
                }
        }
        if (n.mesh == kNone) continue;
        const Mesh& m = scene->meshes[n.mesh];
        ASSERT_GT(n.worldSphere.radius, 0.0f) << "node " << i;
        for (uint32_t v = 0; v < m.vertexCount; ++v) {
            auto p = attribute(m, VertexSemantic::Position, v);
            double q[3];
            for (int row = 0; row < 3; ++row)
                q[row] = world[i][row] * p[0] + world[i][3 + row] * p[1] +
                         world[i][6 + row] * p[2] + world[i][9 + row];
            double dx = q[0] - n.worldSphere.center.x, dy = q[1] - n.worldSphere.center.y,
                   dz = q[2] - n.worldSphere.center.z;
            double slack = 1e-4 * (1 + n.worldSphere.radius);
            EXPECT_LE(std::sqrt(dx * dx + dy * dy + dz * dz), n.worldSphere.radius + slack);
            EXPECT_GE(q[0], n.worldBounds.min.x - slack);
            EXPECT_LE(q[1], n.worldBounds.max.y + slack);
        }
        ++checked;
    }
    EXPECT_GT(checked, 2u);
}

// [SECTION] errors

TEST_F(Convert, ErrorsNameTheProblemAndNeverLeaveAPartialFile) {
    ConvertSettings missing = settings(dir / "nope.gltf", "out.pnb");
    auto r = convertScene(missing);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, ConvertErrorKind::Input);
    EXPECT_NE(r.error().message.find("nope.gltf"), std::string::npos) << r.error().message;
    EXPECT_FALSE(fs::exists(dir / "out.pnb"));

    // An existing output survives a failed conversion byte for byte.
    std::ofstream(dir / "keep.pnb") << "previous contents";
    std::ofstream(dir / "broken.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 9\n";
    auto broken = convertScene(settings(dir / "broken.obj", "keep.pnb"));
    ASSERT_FALSE(broken.ok());
    auto kept = bytesOf((dir / "keep.pnb").string());
    EXPECT_EQ(std::string(kept.begin(), kept.end()), "previous contents");

    // Unwritable destination: an output error.
    auto unwritable = convertScene(settings(kBoxTextured, "no-such-dir/out.pnb"));
    ASSERT_FALSE(unwritable.ok());
    EXPECT_EQ(unwritable.error().kind, ConvertErrorKind::Output);

    // A required extension we lack: unsupported.
    auto webgl = convertScene(settings(
        "/usr/share/assimp/models/glTF2/BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", "w.pnb"));
    ASSERT_FALSE(webgl.ok());
    EXPECT_EQ(webgl.error().kind, ConvertErrorKind::Unsupported);
}

} // namespace
