// The glTF writer and the PNG encoder on small hand-made inputs: container layout, alignment,
// index widths, document validation, atomic writes, and PNGs decoded back by an independent
// decoder (libpng).

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>
#include <vector>

#include <png.h>

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

// Decodes a PNG with libpng (an independent decoder: it checks every critical chunk's CRC, and
// zlib the Adler-32 trailer) into the file's own sample layout. Returns the pixels, or an empty
// vector on any error; `channels` from the colour type (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA).
std::vector<uint8_t> decodePng(const std::vector<uint8_t>& png, uint32_t& w, uint32_t& h,
                               uint32_t& channels) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&image, png.data(), png.size())) {
        ADD_FAILURE() << "libpng: " << image.message;
        return {};
    }
    w = image.width;
    h = image.height;
    channels = PNG_IMAGE_SAMPLE_CHANNELS(image.format);
    if (image.format & (PNG_FORMAT_FLAG_LINEAR | PNG_FORMAT_FLAG_COLORMAP)) {
        ADD_FAILURE() << "not an 8-bit direct-colour PNG (format " << image.format << ")";
        png_image_free(&image);
        return {};
    }
    std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr)) {
        ADD_FAILURE() << "libpng: " << image.message;
        return {};
    }
    return pixels;
}

std::vector<uint8_t> testPixels(size_t n) {
    std::vector<uint8_t> pixels(n);
    for (size_t i = 0; i < n; ++i) pixels[i] = uint8_t(i * 7 + i / 13);
    return pixels;
}

TEST(PngWriter, EncodedImagesDecodeBackExactly) {
    struct Case {
        uint32_t w, h, channels;
    };
    for (Case c : {Case{1, 1, 3}, Case{3, 2, 3}, Case{64, 64, 3}, Case{200, 120, 4},
                   Case{5, 7, 1}, Case{9, 4, 2}, Case{1024, 3, 4}}) {
        SCOPED_TRACE(testing::Message() << c.w << "x" << c.h << "x" << c.channels);
        std::vector<uint8_t> pixels = testPixels(size_t(c.w) * c.h * c.channels);
        std::vector<uint8_t> png = encodePng(c.w, c.h, c.channels, pixels);
        uint32_t w = 0, h = 0, ch = 0;
        std::vector<uint8_t> back = decodePng(png, w, h, ch);
        EXPECT_EQ(w, c.w);
        EXPECT_EQ(h, c.h);
        EXPECT_EQ(ch, c.channels);
        EXPECT_TRUE(back == pixels);
        EXPECT_TRUE(encodePng(c.w, c.h, c.channels, pixels) == png) << "deterministic";
    }
}

TEST(PngWriter, TexturesAreCompressed) {
    // A checker like the procedural scenes' (64 x 64 RGB, 8-texel squares): a real deflate
    // stream, far below the 12 KiB of its raw scanlines.
    const uint32_t size = 64;
    std::vector<uint8_t> pixels;
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const uint8_t v = ((x / 8 + y / 8) & 1) ? 200 : 60;
            pixels.insert(pixels.end(), {v, v, uint8_t(v / 2)});
        }
    std::vector<uint8_t> png = encodePng(size, size, 3, pixels);
    EXPECT_LT(png.size(), pixels.size() / 20) << png.size() << " bytes";
    uint32_t w = 0, h = 0, ch = 0;
    EXPECT_TRUE(decodePng(png, w, h, ch) == pixels);
}

TEST(PngWriterDeathTest, BadImagesAbortWithTheReason) {
    std::vector<uint8_t> pixels(4 * 4 * 3, 1);
    EXPECT_DEATH(encodePng(4, 4, 4, pixels), "expected 4x4x4");
    EXPECT_DEATH(encodePng(0, 4, 3, pixels), "non-zero");
    EXPECT_DEATH(encodePng(4, 4, 5, pixels), "channels must be 1..4");
}

} // namespace
