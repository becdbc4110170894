// Round trips of every chunk kind through writer and reader, determinism, streaming vs mapped.

#include <gtest/gtest.h>

#include <cstring>

#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/writer.h"
#include "pnb_assets/box_room.h"

namespace {

using namespace pnb;

std::vector<std::byte> writeToMemory(const Scene& scene, const WriteOptions& options = {}) {
    std::vector<std::byte> bytes;
    Writer w = Writer::toMemory(&bytes, options);
    EXPECT_TRUE(isOk(writeScene(w, scene)));
    EXPECT_TRUE(isOk(w.commit()));
    return bytes;
}

// Two chunk values are equal when they encode to the same bytes: the encoder writes every field
// listed in fields(), so a field the decoder dropped or changed shows up as a byte difference.
template <class T> bool equalChunks(const T& a, const T& b) { return encodeChunk(a) == encodeChunk(b); }
template <class T> bool equalChunks(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!equalChunks(a[i], b[i])) return false;
    return true;
}

TEST(RoundTrip, EveryChunkKindSurvivesWriteAndRead) {
    SceneBuilder b;
    assets::buildBoxRoom(b);
    auto bytes = writeToMemory(b.scene);
    auto container = Container::fromMemory(bytes);
    ASSERT_TRUE(container.ok()) << container.error().describe();
    auto scene = readScene(*container);
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    const Scene& in = b.scene;
    const Scene& out = *scene;
    EXPECT_TRUE(equalChunks(in.strings, out.strings));
    EXPECT_TRUE(equalChunks(in.info, out.info));
    EXPECT_TRUE(equalChunks(in.settings, out.settings));
    EXPECT_TRUE(equalChunks(in.shaders, out.shaders));
    EXPECT_TRUE(equalChunks(in.programs, out.programs));
    EXPECT_TRUE(equalChunks(in.textures, out.textures));
    EXPECT_TRUE(equalChunks(in.materials, out.materials));
    EXPECT_TRUE(equalChunks(in.meshes, out.meshes));
    EXPECT_TRUE(equalChunks(in.lights, out.lights));
    EXPECT_TRUE(equalChunks(in.cameras, out.cameras));
    EXPECT_TRUE(equalChunks(in.nodes, out.nodes));
    EXPECT_TRUE(equalChunks(in.cameraPaths, out.cameraPaths));
    // Mips are stored smallest first; compare as sets keyed by level.
    ASSERT_EQ(in.textureMips.size(), out.textureMips.size());
    for (const TextureMip& m : in.textureMips) {
        bool found = false;
        for (const TextureMip& o : out.textureMips)
            if (o.texture == m.texture && o.level == m.level) found = equalChunks(m, o);
        EXPECT_TRUE(found) << "mip level " << m.level;
    }
    EXPECT_EQ(out.textureMips.front().level, in.textures[0].mipCount - 1) << "smallest mip first";
    EXPECT_EQ(out.unknownChunks, 0u);
}

TEST(RoundTrip, WritingTwiceGivesIdenticalBytes) {
    SceneBuilder a, b;
    assets::buildBoxRoom(a);
    assets::buildBoxRoom(b);
    EXPECT_EQ(writeToMemory(a.scene), writeToMemory(b.scene));
}

TEST(RoundTrip, EqualChunksDetectsADifference) {
    // Guards the comparison helper itself: a changed field must be noticed.
    SceneBuilder a;
    assets::buildBoxRoom(a);
    Material changed = a.scene.materials[0];
    changed.layerPriority = 7;
    EXPECT_FALSE(equalChunks(a.scene.materials[0], changed));
}

} // namespace
