// The glTF writer and the PNG encoder on small hand-made inputs: container layout, alignment,
// index widths, document validation, atomic writes, and a PNG decoded back by an independent
// stored-deflate inflater.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>

#include "glb_check.h"
#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/png_writer.h"

namespace {

using namespace pnb::assets;
using namespace pnb::assets::gltf;

std::span<const uint8_t> bytesOf(std::string_view s) {
    return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// One triangle fan of `vertices` vertices (a strip of n - 2 triangles), in the XY plane.
Document fanDocument(uint32_t vertices) {
    Document doc;
    doc.materials.push_back({.name = "m"});
    Primitive p;
    for (uint32_t i = 0; i < vertices; ++i) {
        float a = float(i) * 0.001f;
        p.positions.push_back({std::cos(a), std::sin(a), 0.1f});
        p.normals.push_back({0, 0, 1});
    }
    for (uint32_t i = 1; i + 1 < vertices; ++i)
        p.indices.insert(p.indices.end(), {0, i, i + 1});
    doc.meshes.push_back({.name = "fan", .primitives = {std::move(p)}});
    doc.nodes.push_back({.name = "n", .mesh = 0});
    return doc;
}

pnb::test::ParsedGlb parseValid(const std::vector<uint8_t>& bytes) {
    pnb::test::ParsedGlb g;
    EXPECT_EQ(pnb::test::parseGlb(bytes, g), "");
    EXPECT_EQ(pnb::test::validateGltf(g), "");
    return g;
}

TEST(GltfWriter, IndicesAreU16UpTo65535VerticesElseU32) {
    for (uint32_t n : {3u, 65535u, 65536u}) {
        pnb::test::ParsedGlb g = parseValid(encodeGlb(fanDocument(n)));
        size_t idx = g.json["meshes"][0]["primitives"][0]["indices"];
        EXPECT_EQ(g.json["accessors"][idx]["componentType"], n <= 65535 ? 5123 : 5125) << n;
        EXPECT_EQ(pnb::test::renderedTriangles(g), n - 2);
    }
}

TEST(GltfWriter, ChunksAndViewsArePaddedToFourBytes) {
    // 3 vertices, 3 u16 indices (6 bytes): the view after the indices must still start aligned.
    Document doc = fanDocument(3);
    doc.meshes.push_back(doc.meshes[0]);
    doc.nodes.push_back({.name = "odd-length-name", .mesh = 1});
    std::vector<uint8_t> bytes = encodeGlb(doc);
    EXPECT_EQ(bytes.size() % 4, 0u);
    pnb::test::ParsedGlb g = parseValid(bytes);
    for (const auto& v : g.json["bufferViews"])
        EXPECT_EQ(v["byteOffset"].get<size_t>() % 4, 0u);
    EXPECT_EQ(g.json["buffers"][0]["byteLength"].get<size_t>(), g.bin.size());
}

TEST(GltfWriter, EmptyDocumentHasNoBinChunkAndNoEmptyArrays) {
    std::vector<uint8_t> bytes = encodeGlb(Document{});
    pnb::test::ParsedGlb g = parseValid(bytes);
    EXPECT_TRUE(g.bin.empty());
    EXPECT_FALSE(g.json.contains("buffers"));
    EXPECT_FALSE(g.json.contains("nodes"));
    EXPECT_EQ(g.json["asset"]["version"], "2.0");
}

TEST(GltfWriter, FloatsRoundTripExactly) {
    Document doc = fanDocument(3);
    doc.meshes[0].primitives[0].positions[1] = {0.1f, -1e-7f, 12345.678f};
    pnb::test::ParsedGlb g = parseValid(encodeGlb(doc));
    std::vector<double> p = pnb::test::readAccessor(g, 0);
    EXPECT_EQ(float(p[3]), 0.1f);
    EXPECT_EQ(g.json["accessors"][0]["max"][2].get<float>(), 12345.678f);
}

TEST(GltfWriter, InstancesAndChildrenCountTowardsRenderedTriangles) {
    Document doc = fanDocument(5); // 3 triangles
    doc.nodes.push_back({.name = "child", .mesh = 0});
    doc.nodes.push_back({.name = "parent", .mesh = 0, .children = {1}});
    EXPECT_EQ(countRenderedTriangles(doc), 9u);
    GlbStats stats;
    pnb::test::ParsedGlb g = parseValid(encodeGlb(doc, &stats));
    EXPECT_EQ(stats.renderedTriangles, 9u);
    EXPECT_EQ(stats.uniqueTriangles, 3u);
    EXPECT_EQ(pnb::test::renderedTriangles(g), 9u);
    EXPECT_EQ(g.json["scenes"][0]["nodes"], nlohmann::json::array({0, 2}));
}

TEST(GltfWriter, ValidateDocumentNamesTheProblem) {
    EXPECT_EQ(validateDocument(fanDocument(4)), "");
    Document d = fanDocument(4);
    d.meshes[0].primitives[0].indices[2] = 4;
    EXPECT_NE(validateDocument(d).find("index out of range"), std::string::npos);
    d = fanDocument(4);
    d.meshes[0].primitives[0].normals[0] = {0, 0, 2};
    EXPECT_NE(validateDocument(d).find("non-unit normal"), std::string::npos);
    d = fanDocument(4);
    d.meshes[0].primitives[0].material = 3;
    EXPECT_NE(validateDocument(d).find("material"), std::string::npos);
    d = fanDocument(4);
    d.materials[0].normalImage = 0; // no images
    EXPECT_NE(validateDocument(d).find("normalImage out of range"), std::string::npos);
    d = fanDocument(4);
    d.nodes.push_back({.name = "a", .children = {0}});
    d.nodes.push_back({.name = "b", .children = {0}});
    EXPECT_NE(validateDocument(d).find("more than one parent"), std::string::npos);
    d = fanDocument(4);
    d.nodes.push_back({.name = "a", .children = {2}});
    d.nodes.push_back({.name = "b", .children = {1}});
    EXPECT_NE(validateDocument(d).find("cycle"), std::string::npos);
}

// KHR_lights_punctual spots: type "spot", the cone under "spot" and the range, exactly as given;
// cones the extension forbids (inner >= outer, outer > pi/2) are named by validateDocument.
TEST(GltfWriter, SpotLightsCarryTheirConeAndRange) {
    Document d = fanDocument(4);
    d.lights.push_back({.name = "spot",
                        .type = LightType::Spot,
                        .intensity = 30.0f,
                        .range = 9.5f,
                        .innerConeRadians = 0.4f,
                        .outerConeRadians = 0.6f});
    d.lights.push_back(
        {.name = "bulb", .type = LightType::Point, .intensity = 5.0f, .range = 7.0f});
    d.nodes[0].light = 0;
    const pnb::test::ParsedGlb g = parseValid(encodeGlb(d));
    const nlohmann::json& lights = g.json["extensions"]["KHR_lights_punctual"]["lights"];
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_EQ(lights[0]["type"], "spot");
    EXPECT_EQ(lights[0]["range"].get<float>(), 9.5f);
    EXPECT_EQ(lights[0]["spot"]["innerConeAngle"].get<float>(), 0.4f);
    EXPECT_EQ(lights[0]["spot"]["outerConeAngle"].get<float>(), 0.6f);
    EXPECT_EQ(lights[1]["type"], "point");
    EXPECT_EQ(lights[1]["range"].get<float>(), 7.0f);
    EXPECT_FALSE(lights[1].contains("spot"));

    d.lights[0].innerConeRadians = 0.6f; // inner == outer
    EXPECT_NE(validateDocument(d).find("spot cone"), std::string::npos);
    d.lights[0].innerConeRadians = 0.1f;
    d.lights[0].outerConeRadians = 1.6f; // past pi/2
    EXPECT_NE(validateDocument(d).find("spot cone"), std::string::npos);
}

TEST(GltfWriter, LookRotationTurnsMinusZToForwardAndKeepsUpUp) {
    const Float3 directions[] = {
        {0, 0, -1}, {1, 0, 0}, {0, -0.5f, 0.8f}, {0.3f, -0.95f, 0.1f}, {0, 0, 1}};
    for (const Float3& f : directions) {
        Float4 q = lookRotation(f);
        Float3 got = rotate(q, {0, 0, -1});
        float len = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], f[c] / len, 1e-5f);
        EXPECT_GT(rotate(q, {0, 1, 0})[1], 0.0f) << "camera up stays above the horizon";
        EXPECT_NEAR(std::fabs(rotate(q, {1, 0, 0})[1]), 0.0f, 1e-5f) << "no roll";
    }
    Float4 identity = lookRotation({0, 0, -1});
    EXPECT_NEAR(identity[3], 1.0f, 1e-7f);
}

TEST(GltfWriter, WriteFileAtomicReplacesTheFileAndLeavesNoTemporary) {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("pnb_gltf_writer_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string path = (dir / "scene.glb").string();
    std::vector<uint8_t> first = encodeGlb(fanDocument(3)), second = encodeGlb(fanDocument(7));
    ASSERT_TRUE(pnb::isOk(pnb::writeFileAtomic(path, first)));
    ASSERT_TRUE(pnb::isOk(pnb::writeFileAtomic(path, second)));
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> read((std::istreambuf_iterator<char>(in)), {});
    EXPECT_TRUE(read == second);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);

    pnb::Status s = pnb::writeFileAtomic((dir / "missing" / "x.glb").string(), first);
    EXPECT_EQ(s.code, pnb::FormatError::IoError);
    EXPECT_NE(s.message.find("missing"), std::string::npos);
    fs::remove_all(dir);
}

// --- PNG --------------------------------------------------------------------------------------

TEST(PngWriter, ChecksumsMatchTheirCheckValues) {
    EXPECT_EQ(crc32(bytesOf("123456789")), 0xCBF43926u);
    EXPECT_EQ(crc32(bytesOf("")), 0u);
    EXPECT_EQ(crc32(bytesOf("6789"), crc32(bytesOf("12345"))), 0xCBF43926u) << "continuation";
    EXPECT_EQ(adler32(bytesOf("Wikipedia")), 0x11E60398u);
    EXPECT_EQ(adler32(bytesOf("")), 1u);
    // Long input: exercises the deferred modulo (more than 5552 bytes of 0xFF).
    std::vector<uint8_t> ff(100000, 0xFF);
    uint32_t a = 1, b = 0;
    for (uint8_t v : ff) {
        a = (a + v) % 65521;
        b = (b + a) % 65521;
    }
    EXPECT_EQ(adler32(ff), (b << 16) | a);
}

uint32_t be32(const uint8_t* p) {
    return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

// Decodes a PNG made of stored deflate blocks, checking every CRC, the zlib header and the
// Adler-32 trailer. Returns the pixels, or an empty vector on any error.
std::vector<uint8_t> decodeStoredPng(const std::vector<uint8_t>& png, uint32_t& w, uint32_t& h,
                                     uint32_t& channels) {
    const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (png.size() < 8 || std::memcmp(png.data(), sig, 8) != 0) return {};
    std::vector<uint8_t> zlib;
    bool sawEnd = false;
    for (size_t at = 8; at < png.size();) {
        if (png.size() - at < 12) return {};
        uint32_t len = be32(&png[at]);
        if (png.size() - at - 12 < len) return {};
        std::string type(png.begin() + long(at + 4), png.begin() + long(at + 8));
        const uint8_t* data = &png[at + 8];
        if (crc32({&png[at + 4], len + 4}) != be32(data + len)) return {};
        if (type == "IHDR") {
            w = be32(data);
            h = be32(data + 4);
            if (data[8] != 8 || (data[9] != 2 && data[9] != 6) || data[10] || data[11] || data[12])
                return {};
            channels = data[9] == 6 ? 4 : 3;
        } else if (type == "IDAT") {
            zlib.insert(zlib.end(), data, data + len);
        } else if (type == "IEND") {
            sawEnd = at + 12 == png.size();
        }
        at += 12 + len;
    }
    if (!sawEnd || zlib.size() < 6 || (zlib[0] * 256 + zlib[1]) % 31 != 0 || (zlib[0] & 15) != 8)
        return {};
    std::vector<uint8_t> raw;
    size_t at = 2;
    for (bool last = false; !last;) {
        if (zlib.size() - at < 5 || (zlib[at] & 6) != 0) return {}; // stored blocks only
        last = zlib[at] & 1;
        uint16_t len = uint16_t(zlib[at + 1] | zlib[at + 2] << 8);
        uint16_t nlen = uint16_t(zlib[at + 3] | zlib[at + 4] << 8);
        if (uint16_t(~nlen) != len || zlib.size() - at - 5 < len) return {};
        raw.insert(raw.end(), &zlib[at + 5], &zlib[at + 5] + len);
        at += 5 + size_t(len);
    }
    if (zlib.size() - at != 4 || be32(&zlib[at]) != adler32(raw)) return {};
    const size_t row = size_t(w) * channels;
    if (raw.size() != (row + 1) * h) return {};
    std::vector<uint8_t> pixels;
    for (uint32_t y = 0; y < h; ++y) {
        if (raw[y * (row + 1)] != 0) return {}; // filter type None
        pixels.insert(pixels.end(), raw.begin() + long(y * (row + 1) + 1),
                      raw.begin() + long((y + 1) * (row + 1)));
    }
    return pixels;
}

TEST(PngWriter, EncodedImagesDecodeBackExactly) {
    struct Case {
        uint32_t w, h, channels;
    };
    // 200 x 120 RGBA is 96 120 bytes of scanlines: two stored blocks.
    for (Case c : {Case{1, 1, 3}, Case{3, 2, 3}, Case{64, 64, 3}, Case{200, 120, 4}}) {
        std::vector<uint8_t> pixels(size_t(c.w) * c.h * c.channels);
        for (size_t i = 0; i < pixels.size(); ++i)
            pixels[i] = uint8_t(i * 7 + i / 13);
        std::vector<uint8_t> png = encodePng(c.w, c.h, c.channels, pixels);
        uint32_t w = 0, h = 0, ch = 0;
        std::vector<uint8_t> back = decodeStoredPng(png, w, h, ch);
        EXPECT_EQ(w, c.w);
        EXPECT_EQ(h, c.h);
        EXPECT_EQ(ch, c.channels);
        EXPECT_TRUE(back == pixels) << c.w << "x" << c.h;
        EXPECT_TRUE(encodePng(c.w, c.h, c.channels, pixels) == png) << "deterministic";
    }
}

} // namespace
