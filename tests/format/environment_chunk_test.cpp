// ENVM (docs/FORMAT.md "ENVM"): the environment survives a write and a read, sits before the
// progressive section, and validateScene refuses environments that would draw wrong.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/scene_builder.h"
#include "pnb/writer.h"
#include "pnb_assets/box_room.h"

namespace {

using namespace pnb;

// The box room with the asset library's sample environment (a radiance image, a cube and a
// BRDF table), its irradiance given a value in every coefficient.
void buildLitBoxRoom(SceneBuilder& b) {
    assets::BoxRoomOptions options;
    options.environment = true;
    assets::buildBoxRoom(b, options);
    for (int i = 0; i < 9; ++i) b.scene.environment->irradianceSh[i] = {float(i), 0.5f * float(i), 1.0f};
}

Result<Scene> roundTrip(const Scene& scene, std::vector<std::byte>& bytes) {
    Writer w = Writer::toMemory(&bytes, {});
    EXPECT_TRUE(isOk(writeScene(w, scene)));
    EXPECT_TRUE(isOk(w.commit()));
    auto container = Container::fromMemory(bytes);
    if (!container) return container.error();
    return readScene(*container);
}

TEST(EnvironmentChunk, SurvivesWriteAndReadAndComesBeforeTheTexels) {
    SceneBuilder b;
    buildLitBoxRoom(b);
    std::vector<std::byte> bytes;
    auto out = roundTrip(b.scene, bytes);
    ASSERT_TRUE(out.ok()) << out.error().describe();
    ASSERT_TRUE(out->environment.has_value());
    EXPECT_EQ(encodeChunk(*out->environment), encodeChunk(*b.scene.environment));
    EXPECT_EQ(out->unknownChunks, 0u);
    auto container = Container::fromMemory(bytes);
    ASSERT_TRUE(container.ok());
    int envAt = -1, firstTexel = -1, i = 0;
    for (const ChunkInfo& c : container->chunks()) {
        if (c.header.tag == tags::kEnvironment) envAt = i;
        if (c.header.tag == tags::kTextureMip && firstTexel < 0) firstTexel = i;
        ++i;
    }
    EXPECT_GE(envAt, 0);
    EXPECT_LT(envAt, firstTexel) << "a streaming reader knows the environment before any texel";
}

TEST(EnvironmentChunk, ASceneWithoutOneWritesNoChunk) {
    SceneBuilder b;
    assets::buildBoxRoom(b);
    std::vector<std::byte> bytes;
    auto out = roundTrip(b.scene, bytes);
    ASSERT_TRUE(out.ok());
    EXPECT_FALSE(out->environment.has_value());
    auto container = Container::fromMemory(bytes);
    for (const ChunkInfo& c : container->chunks()) EXPECT_FALSE(c.header.tag == tags::kEnvironment);
}

TEST(EnvironmentChunk, ValidationRefusesWhatWouldDrawWrong) {
    auto expectRefused = [](auto change, const char* words) {
        SceneBuilder b;
        buildLitBoxRoom(b);
        change(b.scene);
        Status st = validateScene(b.scene);
        ASSERT_FALSE(isOk(st)) << words;
        EXPECT_NE(st.message.find("environment"), std::string::npos) << st.message;
        EXPECT_NE(st.message.find(words), std::string::npos) << st.message;
    };
    expectRefused([](Scene& s) { s.environment->radiance = s.environment->specular; }, "radiance");
    expectRefused([](Scene& s) { s.environment->specular = s.environment->radiance; }, "specular");
    expectRefused([](Scene& s) { s.environment->brdfLut = 999; }, "brdfLut");
    expectRefused([](Scene& s) { s.textures[s.environment->radiance].colorSpace = ColorSpace::Srgb; },
                  "radiance");
    expectRefused([](Scene& s) { s.textures[s.environment->radiance].format = TextureFormat::RGBA8; },
                  "radiance");
    expectRefused([](Scene& s) { s.environment->brdfLut = kNone; }, "needs the BRDF table");
    expectRefused([](Scene& s) { s.environment->irradianceSh[4].y = std::numeric_limits<float>::quiet_NaN(); },
                  "non-finite");
    expectRefused([](Scene& s) { s.environment->sunDirection.x = INFINITY; }, "non-finite");
    SceneBuilder ok;
    buildLitBoxRoom(ok);
    ok.scene.environment->specular = kNone;
    ok.scene.environment->brdfLut = kNone;
    ok.scene.environment->radiance = kNone; // only diffuse light, black background: allowed
    EXPECT_TRUE(isOk(validateScene(ok.scene)));
}

} // namespace

namespace {

// ENVM version 2 appends `generated` (FORMAT.md "ENVM", §3.5 rules 1 and 3): a version-1 payload
// (the same bytes without it) reads as the source's environment; version 2 keeps the flag; a
// version-1 payload with a byte too many is damage.
TEST(EnvironmentChunk, GeneratedIsVersionTwoAndAVersionOneChunkReadsAsTheSources) {
    pnb::Environment e;
    e.radiance = 1;
    e.irradianceSh[0] = {1, 2, 3};
    e.generated = true;
    const std::vector<std::byte> v2 = encodeChunk(e);
    EXPECT_EQ(ChunkTraits<pnb::Environment>::version, 2);
    ChunkHeader h{};
    h.version = 2;
    auto read2 = decodeChunk<pnb::Environment>(v2, h);
    ASSERT_TRUE(read2.ok()) << read2.error().describe();
    EXPECT_TRUE(read2->generated);

    const std::vector<std::byte> v1(v2.begin(), v2.end() - 1); // version 1: no trailing bool
    h.version = 1;
    auto read1 = decodeChunk<pnb::Environment>(v1, h);
    ASSERT_TRUE(read1.ok()) << read1.error().describe();
    EXPECT_FALSE(read1->generated);
    EXPECT_EQ(read1->radiance, 1u);
    EXPECT_FLOAT_EQ(read1->irradianceSh[0].z, 3.0f);
    EXPECT_FALSE(decodeChunk<pnb::Environment>(v2, h).ok()) << "version 1 with a byte left over";
}

} // namespace
