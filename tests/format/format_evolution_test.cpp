// FORMAT.md 3.5, tested the way it matters: a file written by a *future* writer — MATL at version
// 2 with an appended field and an appended parallel array, plus a chunk kind this reader has never
// heard of — is read by today's code. Without the critical bit today's reader takes the fields it
// knows and skips the rest; with it, it refuses by name instead of misreading.

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "format_test_util.h"
#include "pnb/chunks.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/writer.h"

namespace {

using namespace pnb;

constexpr Tag kFutureTag{{'X', 'F', 'U', 'T'}};
// The MATL version after this reader's (this reader knows ChunkTraits<Material>::version).
constexpr uint16_t kNext = ChunkTraits<Material>::version + 1;

// The next version of MATL as a future writer would define it: today's fields, then an appended
// `float sheen` (default 0) and a parallel array with one u8 per texture slot (say, a UV-set
// override; default 0).
std::vector<std::byte> materialNextVersion(const Material& m, float sheen) {
    std::vector<std::byte> bytes = encodeChunk(m);
    auto append = [&](const void* p, size_t n) {
        auto* b = static_cast<const std::byte*>(p);
        bytes.insert(bytes.end(), b, b + n);
    };
    append(&sheen, sizeof sheen); // little-endian host (the project builds only there)
    const uint32_t count = uint32_t(m.textures.size());
    append(&count, sizeof count);
    for (uint32_t i = 0; i < count; ++i) {
        const uint8_t uvOverride = uint8_t(i % 2);
        append(&uvOverride, 1);
    }
    return bytes;
}

struct FutureOptions {
    bool criticalMaterials = false;
    bool criticalUnknownChunk = false;
};

// Today's sample rewritten by a "next version" writer: every chunk copied as stored, MATL
// re-encoded at the next version, an unknown chunk kind after the materials.
std::vector<std::byte> futureFile(const std::vector<std::byte>& today, const FutureOptions& o) {
    auto source = Container::fromMemory(today);
    EXPECT_TRUE(source.ok());
    std::vector<std::byte> out;
    Writer w = Writer::toMemory(&out);
    bool unknownWritten = false;
    for (const ChunkInfo& info : source->chunks()) {
        if (info.header.tag == tags::kMaterial) {
            auto payload = source->load(info);
            EXPECT_TRUE(payload.ok());
            auto m = decodeChunk<Material>(payload->bytes(), info.header);
            EXPECT_TRUE(m.ok());
            EXPECT_TRUE(isOk(w.addChunk(tags::kMaterial, kNext, materialNextVersion(*m, 0.25f),
                                        Compression::None, o.criticalMaterials)));
            continue;
        }
        if (!unknownWritten && info.header.tag == tags::kMesh) {
            std::vector<std::byte> payload(24, std::byte{0x7E});
            EXPECT_TRUE(isOk(w.addChunk(kFutureTag, 1, payload, Compression::Zstd,
                                        o.criticalUnknownChunk)));
            unknownWritten = true;
        }
        EXPECT_TRUE(isOk(w.copyChunk(*source, info)));
    }
    EXPECT_TRUE(isOk(w.commit()));
    return out;
}

TEST(FormatEvolution, NextVersionFileIsReadByTheFieldsThisReaderKnows) {
    const std::vector<std::byte> today = test::sampleBytes();
    auto todayContainer = Container::fromMemory(today);
    ASSERT_TRUE(todayContainer.ok());
    auto expected = readScene(*todayContainer);
    ASSERT_TRUE(expected.ok()) << expected.error().describe();
    ASSERT_FALSE(expected->materials.empty());

    const std::vector<std::byte> future = futureFile(today, {});
    auto container = Container::fromMemory(future);
    ASSERT_TRUE(container.ok()) << container.error().describe();
    ASSERT_TRUE(isOk(container->verifyAll()));
    auto scene = readScene(*container);
    ASSERT_TRUE(scene.ok()) << scene.error().describe();

    EXPECT_EQ(scene->newerChunks, expected->materials.size());
    EXPECT_EQ(scene->unknownChunks, 1u);
    ASSERT_EQ(scene->materials.size(), expected->materials.size());
    for (size_t i = 0; i < scene->materials.size(); ++i)
        EXPECT_EQ(encodeChunk(scene->materials[i]), encodeChunk(expected->materials[i]))
            << "material " << i << " differs after reading its version-2 chunk";
    EXPECT_EQ(scene->meshes.size(), expected->meshes.size());
    EXPECT_EQ(scene->textureMips.size(), expected->textureMips.size());
}

TEST(FormatEvolution, CriticalNewerVersionIsRefusedByName) {
    const std::vector<std::byte> future =
        futureFile(test::sampleBytes(), {.criticalMaterials = true});
    auto container = Container::fromMemory(future);
    ASSERT_TRUE(container.ok()) << container.error().describe();
    auto scene = readScene(*container);
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.error().code, FormatError::UnsupportedChunkVersion);
    EXPECT_NE(scene.error().message.find("'MATL' chunk version " + std::to_string(kNext) + " (critical)"),
              std::string::npos)
        << scene.error().message;
    EXPECT_NE(scene.error().message.find("update Penumbra"), std::string::npos);
}

TEST(FormatEvolution, CriticalUnknownChunkKindIsRefusedByName) {
    const std::vector<std::byte> future =
        futureFile(test::sampleBytes(), {.criticalUnknownChunk = true});
    auto container = Container::fromMemory(future);
    ASSERT_TRUE(container.ok()) << container.error().describe();
    auto scene = readScene(*container);
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.error().code, FormatError::UnsupportedChunkVersion);
    EXPECT_NE(scene.error().message.find("'XFUT' is critical and unknown"), std::string::npos)
        << scene.error().message;
}

// Leniency is only for versions newer than this reader's: trailing bytes in a version-1 chunk
// are still damage, and version 0 does not exist.
TEST(FormatEvolution, TrailingBytesInAKnownVersionAreStillAnError) {
    Material m;
    std::vector<std::byte> bytes = materialNextVersion(m, 1.0f);
    ChunkHeader v1{.tag = tags::kMaterial, .version = 1};
    auto r1 = decodeChunk<Material>(bytes, v1);
    ASSERT_FALSE(r1.ok());
    EXPECT_EQ(r1.error().code, FormatError::BadPayload);
    EXPECT_NE(r1.error().message.find("left over"), std::string::npos);

    ChunkHeader v0{.tag = tags::kMaterial, .version = 0};
    auto r0 = decodeChunk<Material>(encodeChunk(m), v0);
    ASSERT_FALSE(r0.ok());
    EXPECT_EQ(r0.error().code, FormatError::UnsupportedChunkVersion);

    // A newer version must still carry every field this reader knows.
    std::vector<std::byte> shortened = encodeChunk(m);
    shortened.pop_back();
    ChunkHeader next{.tag = tags::kMaterial, .version = kNext};
    auto r2 = decodeChunk<Material>(shortened, next);
    ASSERT_FALSE(r2.ok());
    EXPECT_EQ(r2.error().code, FormatError::BadPayload);
}

} // namespace
