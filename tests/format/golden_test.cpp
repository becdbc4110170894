// Golden bytes of format version 1.0 (docs/STYLE.md §9.3, after meshoptimizer's per-version test
// vectors): a tiny container committed as tests/format/golden/v1.0_minimal.pnb.
//
// (a) The writer must still produce it byte for byte: any change to the layout (field order,
//     padding, header fields, chunk order, TOC, footer) fails here, so it cannot happen by
//     accident. (b) The reader must still decode the committed bytes to the known values: old
//     files keep reading after the code moves on.
//
// To change the golden file deliberately (a format version bump, recorded in docs/FORMAT.md's
// revision history; for a new version add a new file instead of rewriting this one):
//     PNB_UPDATE_GOLDEN=1 build/<dir>/tests/format/pnb_format_tests --gtest_filter='Golden*'
// then review the diff of the .pnb file and commit it.
//
// Note: the SHDR chunk is zstd-compressed, so its stored bytes come from libzstd (1.5.4 when the
// file was generated). If a libzstd upgrade alone makes (a) fail, the message names that chunk;
// check that (b) still passes, then regenerate.

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "format_test_util.h"
#include "pnb/chunks.h"

#ifndef PNB_GOLDEN_DIR
#error "PNB_GOLDEN_DIR must name tests/format/golden (set in tests/format/CMakeLists.txt)"
#endif

namespace {

using namespace pnb;
using namespace pnb::test;

const std::string kGoldenPath = std::string(PNB_GOLDEN_DIR) + "/v1.0_minimal.pnb";

// [SECTION] the golden scene's inputs (also the expected values of the decode test)

// Repetitive on purpose, so zstd shrinks it and the chunk is stored compressed.
constexpr char kShaderSource[] =
    "layout(location = 0) out vec4 outColor;\n"
    "uniform vec4 baseColor;\n"
    "void main() {\n"
    "    vec4 c = baseColor;\n"
    "    c.rgb = c.rgb * 0.5 + c.rgb * 0.5;\n"
    "    c.rgb = c.rgb * 0.5 + c.rgb * 0.5;\n"
    "    c.rgb = c.rgb * 0.5 + c.rgb * 0.5;\n"
    "    c.rgb = c.rgb * 0.5 + c.rgb * 0.5;\n"
    "    outColor = c;\n"
    "}\n";
const std::vector<float> kPositions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
const std::vector<uint16_t> kIndices = {0, 1, 2};
const std::vector<std::string> kStrings = {"golden-minimal", "penumbra golden_test", "unit",
                                           "flat.frag", "red", "triangle"};

Aabb unitTriangleBounds() { return Aabb{{0, 0, 0}, {1, 1, 0}}; }

// The deterministic helper that produces the golden file: STRS, INFO, SHDR (zstd), MATL, MESH,
// in the order of FORMAT.md 4.1, through the ordinary Writer.
std::vector<std::byte> buildGolden() {
    SceneBuilder b;
    for (const std::string& s : kStrings) b.intern(s);
    Scene& s = b.scene;
    s.info.name = b.intern("golden-minimal");
    s.info.generator = b.intern("penumbra golden_test");
    s.info.source = b.intern("unit");
    s.info.metersPerUnit = 0.01f;
    s.info.bounds = unitTriangleBounds();

    ShaderSource shader{b.intern("flat.frag"), ShaderStage::Fragment,
                        b.keep(std::string_view(kShaderSource))};

    // Non-default values in every kind of field (float, enum, u16, bool, fixed array).
    Material m;
    m.name = b.intern("red");
    m.baseColorFactor = {1.0f, 0.25f, 0.0f, 1.0f};
    m.metallicFactor = 0.0f;
    m.roughnessFactor = 0.5f;
    m.alphaMode = AlphaMode::Mask;
    m.alphaCutoff = 0.25f;
    m.shadingPath = ShadingPath::Forward;
    m.layerPriority = 3;
    m.doubleSided = true;

    Mesh mesh;
    mesh.name = b.intern("triangle");
    mesh.indexType = IndexType::U16;
    mesh.vertexCount = 3;
    VertexStream positions;
    positions.data = b.keep(kPositions);
    mesh.streams.push_back(positions);
    mesh.indices = b.keep(kIndices);
    mesh.submeshes.push_back(Submesh{.material = 0, .firstIndex = 0, .indexCount = 3, .lod = 0,
                                     .lodError = 0, .bounds = unitTriangleBounds()});
    mesh.bounds = unitTriangleBounds();
    mesh.boundingSphere = Sphere{{0.5f, 0.5f, 0}, 0.70710677f};

    std::vector<std::byte> bytes;
    Writer w = Writer::toMemory(&bytes);
    // STRS uncompressed: this tiny table barely compresses, so whether zstd shrinks it by a
    // byte would otherwise depend on the libzstd version. SHDR is the one zstd chunk.
    EXPECT_TRUE(isOk(writeChunk(w, s.strings, Compression::None)));
    EXPECT_TRUE(isOk(writeChunk(w, s.info)));
    EXPECT_TRUE(isOk(writeChunk(w, shader)));
    EXPECT_TRUE(isOk(writeChunk(w, m)));
    EXPECT_TRUE(isOk(writeChunk(w, mesh)));
    EXPECT_TRUE(isOk(w.commit()));
    return bytes;
}

// [SECTION] helpers

bool updateRequested() {
    const char* v = std::getenv("PNB_UPDATE_GOLDEN");
    return v != nullptr && std::string(v) == "1";
}

bool readFile(const std::string& path, std::vector<std::byte>& out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    out.resize(chars.size());
    if (!chars.empty()) std::memcpy(out.data(), chars.data(), chars.size());
    return true;
}

// Names the structure holding byte `off` of a valid file, for mismatch messages.
std::string whereIs(std::span<const std::byte> bytes, uint64_t off) {
    if (off < kFileHeaderSize) return "the file header";
    auto c = Container::fromMemory(bytes);
    if (!c.ok()) return "an unreadable file (" + c.error().describe() + ")";
    for (const ChunkInfo& ci : c->chunks()) {
        uint64_t end = alignUp(ci.payloadOffset + ci.header.storedSize);
        if (off < ci.headerOffset || off >= end) {
            continue;
        }
        std::string chunk = "chunk " + std::to_string(ci.header.sequence) + " '" +
                            ci.header.tag.str() + "'";
        if (off < ci.payloadOffset) return chunk + " header";
        return chunk + " payload or padding" +
               (ci.header.compression() == Compression::Zstd ? " (zstd output)" : "");
    }
    return off + kFooterSize >= bytes.size() ? "the footer" : "the table of contents";
}

// [SECTION] tests

TEST(GoldenV1_0, RegeneratedBytesMatchTheCommittedFile) {
    const std::vector<std::byte> fresh = buildGolden();
    ASSERT_LT(fresh.size(), 4096u) << "the golden file should stay tiny";
    if (updateRequested()) {
        std::ofstream out(kGoldenPath, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(fresh.data()), std::streamsize(fresh.size()));
        ASSERT_TRUE(out.good()) << "cannot write " << kGoldenPath;
        GTEST_SKIP() << "PNB_UPDATE_GOLDEN=1: rewrote " << kGoldenPath << " (" << fresh.size()
                     << " bytes); review and commit it";
    }
    std::vector<std::byte> committed;
    ASSERT_TRUE(readFile(kGoldenPath, committed))
        << "missing " << kGoldenPath << "; generate it with PNB_UPDATE_GOLDEN=1";
    if (fresh == committed) return;
    size_t first = 0;
    while (first < fresh.size() && first < committed.size() && fresh[first] == committed[first])
        ++first;
    FAIL() << "the writer no longer produces the v1.0 golden bytes: " << fresh.size()
           << " bytes vs " << committed.size() << " committed; first difference at byte "
           << first << ", in " << whereIs(committed, first)
           << ". A layout change needs a format version bump (docs/FORMAT.md).";
}

TEST(GoldenV1_0, CommittedFileDecodesToKnownValues) {
    std::vector<std::byte> raw;
    ASSERT_TRUE(readFile(kGoldenPath, raw)) << "missing " << kGoldenPath;
    // A few layout facts read straight from the bytes, independent of the decoder.
    ASSERT_GE(raw.size(), kFileHeaderSize + kFooterSize);
    EXPECT_EQ(std::memcmp(raw.data(), kFileMagic.data(), 8), 0);
    const uint8_t version10LittleEndian[8] = {1, 0, 0, 0, 0x04, 0x03, 0x02, 0x01};
    EXPECT_EQ(std::memcmp(raw.data() + 8, version10LittleEndian, 8), 0);
    EXPECT_EQ(std::memcmp(raw.data() + raw.size() - kFooterSize, kFooterMagic.data(), 8), 0);
    EXPECT_EQ(std::memcmp(raw.data() + kFileHeaderSize, "STRS", 4), 0);

    auto c = Container::open(kGoldenPath);
    ASSERT_TRUE(c.ok()) << c.error().describe();
    EXPECT_EQ(c->header().versionMajor, 1);
    EXPECT_EQ(c->header().versionMinor, 0);
    EXPECT_TRUE(isOk(c->verifyAll()));
    const Tag order[] = {tags::kStrings, tags::kSceneInfo, tags::kShader, tags::kMaterial,
                         tags::kMesh};
    ASSERT_EQ(c->chunks().size(), std::size(order));
    for (size_t i = 0; i < std::size(order); ++i) {
        const ChunkHeader& h = c->chunks()[i].header;
        EXPECT_TRUE(h.tag == order[i]) << "chunk " << i << " is '" << h.tag.str() << "'";
        // Format 1.0's later chunk versions (docs/FORMAT.md §3.5): MATL 2 (`unlit`).
        EXPECT_EQ(h.version, h.tag == tags::kMaterial ? 2 : 1);
        EXPECT_TRUE(h.hasChecksum());
        EXPECT_EQ(c->chunks()[i].headerOffset % kAlignment, 0u);
    }
    EXPECT_EQ(c->chunks()[0].header.compression(), Compression::None);
    const ChunkHeader& shdr = c->chunks()[2].header;
    EXPECT_EQ(shdr.compression(), Compression::Zstd) << "the golden must cover a zstd chunk";
    EXPECT_LT(shdr.storedSize, shdr.rawSize);

    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    const Scene& s = *scene;
    ASSERT_EQ(s.strings.strings.size(), kStrings.size());
    for (size_t i = 0; i < kStrings.size(); ++i) EXPECT_EQ(s.strings.strings[i], kStrings[i]);
    EXPECT_EQ(s.str(s.info.name), "golden-minimal");
    EXPECT_EQ(s.str(s.info.generator), "penumbra golden_test");
    EXPECT_EQ(s.str(s.info.source), "unit");
    EXPECT_EQ(s.info.metersPerUnit, 0.01f);
    EXPECT_EQ(s.info.bounds.max.y, 1.0f);

    ASSERT_EQ(s.shaders.size(), 1u);
    EXPECT_EQ(s.str(s.shaders[0].name), "flat.frag");
    EXPECT_EQ(s.shaders[0].stage, ShaderStage::Fragment);
    EXPECT_EQ(std::string_view(reinterpret_cast<const char*>(s.shaders[0].source.data()),
                               s.shaders[0].source.size()),
              std::string_view(kShaderSource));

    ASSERT_EQ(s.materials.size(), 1u);
    const Material& m = s.materials[0];
    EXPECT_EQ(s.str(m.name), "red");
    EXPECT_EQ(m.program, kNone);
    EXPECT_EQ(m.baseColorFactor.y, 0.25f);
    EXPECT_EQ(m.metallicFactor, 0.0f);
    EXPECT_EQ(m.roughnessFactor, 0.5f);
    EXPECT_EQ(m.alphaMode, AlphaMode::Mask);
    EXPECT_EQ(m.alphaCutoff, 0.25f);
    EXPECT_EQ(m.shadingPath, ShadingPath::Forward);
    EXPECT_EQ(m.layerPriority, 3);
    EXPECT_TRUE(m.doubleSided);
    EXPECT_TRUE(m.castsShadows);
    EXPECT_EQ(m.textures[0].texture, kNone);

    ASSERT_EQ(s.meshes.size(), 1u);
    const Mesh& mesh = s.meshes[0];
    EXPECT_EQ(s.str(mesh.name), "triangle");
    EXPECT_EQ(mesh.indexType, IndexType::U16);
    EXPECT_EQ(mesh.vertexCount, 3u);
    ASSERT_EQ(mesh.streams.size(), 1u);
    EXPECT_EQ(mesh.streams[0].semantic, VertexSemantic::Position);
    ASSERT_EQ(mesh.streams[0].data.size(), kPositions.size() * sizeof(float));
    EXPECT_EQ(std::memcmp(mesh.streams[0].data.data(), kPositions.data(),
                          kPositions.size() * sizeof(float)),
              0);
    ASSERT_EQ(mesh.indices.size(), kIndices.size() * sizeof(uint16_t));
    EXPECT_EQ(std::memcmp(mesh.indices.data(), kIndices.data(), mesh.indices.size()), 0);
    ASSERT_EQ(mesh.submeshes.size(), 1u);
    EXPECT_EQ(mesh.submeshes[0].material, 0u);
    EXPECT_EQ(mesh.submeshes[0].indexCount, 3u);
    EXPECT_EQ(mesh.boundingSphere.radius, 0.70710677f);

    // Streaming the committed bytes yields the same five chunks.
    std::vector<SeenChunk> streamed;
    ASSERT_TRUE(isOk(streamThroughPipe(raw, {}, collectInto(streamed))));
    ASSERT_EQ(streamed.size(), std::size(order));
    for (size_t i = 0; i < streamed.size(); ++i) EXPECT_TRUE(streamed[i].header.tag == order[i]);
    EXPECT_EQ(streamed[2].raw, encodeChunk(s.shaders[0])) << "inflated SHDR payload differs";
}

} // namespace
