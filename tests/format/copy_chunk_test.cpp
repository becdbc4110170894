// Writer::copyChunk: chunks copied from another container keep their stored bytes and header
// fields exactly (compression, checksum, sizes); only the sequence number is the writer's.

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "format_test_util.h"

namespace {

using namespace pnb;
using namespace pnb::test;

// The box room with every bulk chunk zstd-compressed, so copies must carry compressed payloads.
std::vector<std::byte> compressedSample(const WriteOptions& options = {}) {
    SceneBuilder b;
    assets::buildBoxRoom(b);
    std::vector<std::byte> bytes;
    Writer w = Writer::toMemory(&bytes, options);
    EXPECT_TRUE(isOk(writeScene(w, b.scene, Compression::Zstd)));
    EXPECT_TRUE(isOk(w.commit()));
    return bytes;
}

std::vector<std::byte> copyAll(const Container& source) {
    std::vector<std::byte> out;
    Writer w = Writer::toMemory(&out);
    for (const ChunkInfo& c : source.chunks()) {
        Status s = w.copyChunk(source, c);
        EXPECT_TRUE(isOk(s)) << s.describe();
    }
    EXPECT_TRUE(isOk(w.commit()));
    return out;
}

TEST(CopyChunk, RewritingEveryChunkGivesTheSameBytes) {
    WriteOptions noChecksums;
    noChecksums.checksums = false;
    for (const auto& original : {sampleBytes(), compressedSample(), sampleBytes(noChecksums)}) {
        auto source = Container::fromMemory(original);
        ASSERT_TRUE(source.ok()) << source.error().describe();
        EXPECT_EQ(copyAll(*source), original);
    }
    // The compressed sample really exercises compressed chunks.
    auto compressed = compressedSample();
    auto source = Container::fromMemory(compressed);
    ASSERT_TRUE(source.ok());
    size_t zstd = 0;
    for (const ChunkInfo& c : source->chunks()) zstd += c.header.compression() == Compression::Zstd;
    EXPECT_GT(zstd, 3u);
}

TEST(CopyChunk, OnlyTheSequenceNumberChangesWhenChunksMove) {
    auto original = compressedSample();
    auto source = Container::fromMemory(original);
    ASSERT_TRUE(source.ok());
    // Copy every chunk after an extra leading one: each moves by one place.
    std::vector<std::byte> out;
    Writer w = Writer::toMemory(&out);
    const std::byte extra[5] = {};
    ASSERT_TRUE(isOk(w.addChunk(Tag{{'X', 'T', 'R', 'A'}}, 1, extra)));
    for (const ChunkInfo& c : source->chunks()) ASSERT_TRUE(isOk(w.copyChunk(*source, c)));
    ASSERT_TRUE(isOk(w.commit()));
    auto copy = Container::fromMemory(out);
    ASSERT_TRUE(copy.ok()) << copy.error().describe();
    ASSERT_TRUE(isOk(copy->verifyAll()));
    ASSERT_EQ(copy->chunks().size(), source->chunks().size() + 1);
    for (size_t i = 0; i < source->chunks().size(); ++i) {
        const ChunkInfo& a = source->chunks()[i];
        const ChunkInfo& b = copy->chunks()[i + 1];
        EXPECT_EQ(b.header.sequence, a.header.sequence + 1);
        ChunkHeader expect = a.header;
        expect.sequence = b.header.sequence;
        EXPECT_EQ(encodeChunkHeader(b.header), encodeChunkHeader(expect)) << "chunk " << i;
        auto sa = source->stored(a), sb = copy->stored(b);
        ASSERT_TRUE(sa.ok() && sb.ok());
        EXPECT_TRUE(std::equal(sa->begin(), sa->end(), sb->begin(), sb->end())) << "chunk " << i;
    }
    // The copy is still a valid scene (unknown tags are skipped).
    auto scene = readScene(*copy);
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    EXPECT_EQ(scene->unknownChunks, 1u);
}

TEST(CopyChunk, ADamagedSourcePayloadIsNotSpread) {
    auto bytes = sampleBytes();
    auto probe = Container::fromMemory(bytes);
    ASSERT_TRUE(probe.ok());
    const ChunkInfo mesh = *probe->findFirst(tags::kMesh);
    bytes[mesh.payloadOffset + 3] ^= std::byte{0x40};

    auto verifying = Container::fromMemory(bytes); // verifyChecksums is on by default
    ASSERT_TRUE(verifying.ok());
    std::vector<std::byte> out;
    Writer w = Writer::toMemory(&out);
    Status s = w.copyChunk(*verifying, *verifying->findFirst(tags::kMesh));
    EXPECT_EQ(s.code, FormatError::ChecksumMismatch) << s.describe();

    // Without verification the bytes are copied as they are, and the copy fails to verify.
    ReadOptions trusting;
    trusting.verifyChecksums = false;
    auto unverified = Container::fromMemory(bytes, trusting);
    ASSERT_TRUE(unverified.ok());
    auto copied = copyAll(*unverified);
    EXPECT_EQ(copied, bytes);
    auto reopened = Container::fromMemory(copied);
    ASSERT_TRUE(reopened.ok());
    EXPECT_EQ(reopened->verifyAll().code, FormatError::ChecksumMismatch);
}

TEST(CopyChunk, FileToFileCopyIsIdentical) {
    // The box room plus a chunk of 3 MiB + 17 bytes (incompressible), larger than the writer's
    // copy buffer, so big payloads are copied in pieces.
    auto original = compressedSample();
    {
        auto box = Container::fromMemory(original);
        ASSERT_TRUE(box.ok());
        std::vector<std::byte> big((size_t(3) << 20) + 17);
        uint64_t x = 0x9E3779B97F4A7C15ull;
        for (std::byte& b : big) {
            x ^= x << 13, x ^= x >> 7, x ^= x << 17;
            b = std::byte(x >> 56);
        }
        std::vector<std::byte> bytes;
        Writer w = Writer::toMemory(&bytes);
        for (const ChunkInfo& c : box->chunks()) ASSERT_TRUE(isOk(w.copyChunk(*box, c)));
        ASSERT_TRUE(isOk(w.addChunk(Tag{{'B', 'U', 'L', 'K'}}, 1, big, Compression::Zstd)));
        ASSERT_TRUE(isOk(w.commit()));
        original = std::move(bytes);
    }
    std::string dir = ::testing::TempDir();
    std::string src = dir + "pnb-copy-src.pnb", dst = dir + "pnb-copy-dst.pnb";
    {
        std::ofstream f(src, std::ios::binary | std::ios::trunc);
        f.write(reinterpret_cast<const char*>(original.data()), std::streamsize(original.size()));
    }
    auto source = Container::open(src);
    ASSERT_TRUE(source.ok()) << source.error().describe();
    auto w = Writer::create(dst);
    ASSERT_TRUE(w.ok()) << w.error().describe();
    for (const ChunkInfo& c : source->chunks()) ASSERT_TRUE(isOk(w->copyChunk(*source, c)));
    ASSERT_TRUE(isOk(w->commit()));
    EXPECT_EQ(w->size(), original.size());
    std::ifstream in(dst, std::ios::binary);
    std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_EQ(chars.size(), original.size());
    EXPECT_EQ(std::memcmp(chars.data(), original.data(), chars.size()), 0);
    ::unlink(src.c_str());
    ::unlink(dst.c_str());
}

} // namespace
