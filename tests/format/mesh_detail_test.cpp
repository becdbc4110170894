// MDET: a mesh written as a coarse proxy (MESH) and its full detail (MDET) — the proxy's shape,
// the round trip, the chunk order writeScene gives (after every texture's smallest level, before
// any larger one) and the rules validateScene and SceneAssembler enforce.
#include <gtest/gtest.h>

#include <array>
#include <cstring>

#include "pnb/mesh_levels.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/writer.h"
#include "pnb_assets/box_room.h"

namespace {

using namespace pnb;

std::vector<std::byte> writeToMemory(const Scene& scene) {
    std::vector<std::byte> bytes;
    Writer w = Writer::toMemory(&bytes);
    EXPECT_TRUE(isOk(writeScene(w, scene)));
    EXPECT_TRUE(isOk(w.commit()));
    return bytes;
}

// Position of vertex v (the box room's meshes are F32).
std::array<float, 3> position(const Mesh& m, uint32_t v) {
    std::array<float, 3> p{};
    for (const VertexStream& s : m.streams)
        if (s.semantic == VertexSemantic::Position) std::memcpy(p.data(), s.data.data() + size_t(v) * 12, 12);
    return p;
}

// The box room with mesh 0 given one simplified level per level-0 submesh (its first triangle),
// written as proxy + detail.
struct Detailed {
    SceneBuilder b;
    Mesh detail;
    Detailed() {
        assets::buildBoxRoom(b);
        detail = b.scene.meshes[0];
        const size_t count = detail.submeshes.size();
        for (size_t k = 0; k < count; ++k) {
            Submesh level = detail.submeshes[k];
            level.lod = 1;
            level.indexCount = 3;
            level.lodError = 0.25f;
            detail.submeshes.push_back(level);
        }
        b.scene.meshes[0] = buildCoarseProxy(detail, b);
        b.scene.meshDetails.push_back({0, detail});
    }
};

TEST(MeshDetail, TheProxyHoldsEachChainsCoarsestLevelWithLevelZerosBounds) {
    Detailed d;
    const Mesh& proxy = d.b.scene.meshes[0];
    ASSERT_TRUE(hasLevelChains(d.detail));
    EXPECT_FALSE(hasLevelChains(proxy));
    const auto chains = buildLevelChains(d.detail.submeshes);
    ASSERT_EQ(proxy.submeshes.size(), chains.size());
    EXPECT_LT(proxy.vertexCount, d.detail.vertexCount);
    for (size_t c = 0; c < chains.size(); ++c) {
        const Submesh& p = proxy.submeshes[c];
        const Submesh& level0 = d.detail.submeshes[chains[c].levels.front()];
        const Submesh& coarse = d.detail.submeshes[chains[c].levels.back()];
        EXPECT_EQ(p.lod, 0);
        EXPECT_EQ(p.material, level0.material);
        EXPECT_EQ(std::memcmp(&p.bounds, &level0.bounds, sizeof p.bounds), 0);
        ASSERT_EQ(p.indexCount, coarse.indexCount);
        for (uint32_t k = 0; k < p.indexCount; ++k) // the same triangles, renumbered
            EXPECT_EQ(position(proxy, meshIndex(proxy, p.firstIndex + k)),
                      position(d.detail, meshIndex(d.detail, coarse.firstIndex + k)));
    }
    EXPECT_TRUE(isOk(validateScene(d.b.scene)));
}

TEST(MeshDetail, RoundTripsAndComesRightAfterTheSmallestTexelLevels) {
    Detailed d;
    auto bytes = writeToMemory(d.b.scene);
    auto container = Container::fromMemory(bytes);
    ASSERT_TRUE(container.ok());
    auto scene = readScene(*container);
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    ASSERT_EQ(scene->meshDetails.size(), 1u);
    EXPECT_EQ(encodeChunk(scene->meshDetails[0]), encodeChunk(d.b.scene.meshDetails[0]));
    EXPECT_EQ(encodeChunk(fullDetailMesh(*scene, 0)), encodeChunk(d.detail));
    EXPECT_EQ(encodeChunk(fullDetailMesh(*scene, 1)), encodeChunk(scene->meshes[1]));
    // Order: every texture's smallest level, then the MDET, then the larger levels.
    bool detailSeen = false, largerSeen = false;
    for (const ChunkInfo& info : container->chunks()) {
        if (info.header.tag == tags::kMeshDetail) {
            EXPECT_FALSE(largerSeen) << "MDET after a larger texel level";
            detailSeen = true;
        } else if (info.header.tag == tags::kTextureMip) {
            auto payload = container->load(info);
            ASSERT_TRUE(payload.ok());
            auto mip = decodeChunk<TextureMip>(payload->bytes(), info.header);
            ASSERT_TRUE(mip.ok());
            const bool smallest = mip->level + 1 == scene->textures[mip->texture].mipCount;
            if (!smallest) {
                EXPECT_TRUE(detailSeen) << "a larger level before the MDET";
                largerSeen = true;
            } else {
                EXPECT_FALSE(detailSeen) << "a smallest level after the MDET";
            }
        }
    }
    EXPECT_TRUE(detailSeen);
}

TEST(MeshDetail, ValidationNamesWhatIsWrong) {
    {
        Detailed d;
        d.b.scene.meshDetails[0].mesh = 99;
        Status s = validateScene(d.b.scene);
        EXPECT_NE(s.message.find("mesh detail 0: mesh = 99"), std::string::npos) << s.message;
    }
    {
        Detailed d;
        d.b.scene.meshDetails.push_back(d.b.scene.meshDetails[0]);
        Status s = validateScene(d.b.scene);
        EXPECT_NE(s.message.find("mesh 0 has one already"), std::string::npos) << s.message;
    }
    {
        Detailed d; // a level-0 submesh of another material: its draw item would change
        for (Submesh& sm : d.b.scene.meshDetails[0].detail.submeshes)
            if (sm.lod == 0) {
                sm.material = sm.material == 0 ? 1 : 0;
                break;
            }
        Status s = validateScene(d.b.scene);
        EXPECT_NE(s.message.find("are not those of mesh 0"), std::string::npos) << s.message;
    }
    {
        Detailed d; // the detail is checked as a mesh
        d.b.scene.meshDetails[0].detail.vertexCount += 1;
        Status s = validateScene(d.b.scene);
        EXPECT_NE(s.message.find("mesh detail 0: stream"), std::string::npos) << s.message;
    }
}

TEST(MeshDetail, AnMdetAfterALargerTexelLevelIsOutOfOrder) {
    Detailed d;
    SceneAssembler a;
    a.scene.textures = d.b.scene.textures;
    ChunkInfo info;
    info.header.tag = tags::kMeshDetail;
    info.header.sequence = 42;
    TextureMip smallest, larger;
    smallest.texture = larger.texture = 0;
    smallest.level = a.scene.textures[0].mipCount - 1;
    larger.level = 0;
    EXPECT_TRUE(isOk(a.checkProgressive(info, &smallest)));
    EXPECT_TRUE(isOk(a.checkProgressive(info, nullptr)));
    EXPECT_FALSE(a.largerTexelsSeen());
    EXPECT_TRUE(isOk(a.checkProgressive(info, &larger)));
    EXPECT_TRUE(a.largerTexelsSeen());
    Status s = a.checkProgressive(info, nullptr);
    EXPECT_NE(s.message.find("chunk 42 'MDET' comes after a texel level"), std::string::npos) << s.message;
}

} // namespace
