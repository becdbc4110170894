// A container larger than 4 GiB, built by hand as a sparse file: offsets, sizes and TOC fields
// past 2^32 must survive every 64-bit path of the mapped reader. The 4.5 GiB chunk is a hole,
// so the test writes a few KB and runs in well under a second.

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/container.h"
#include "pnb/reader.h"
#include "pnb/scene.h"

namespace {

using namespace pnb;

constexpr uint64_t kBigSize = (uint64_t(9) << 29); // 4.5 GiB, a multiple of kAlignment
constexpr Tag kBigTag{{'B', 'I', 'G', '0'}};

class LargeFile : public ::testing::Test {
protected:
    void SetUp() override {
        std::string tmpl = ::testing::TempDir() + "pnb-large-XXXXXX";
        ASSERT_NE(::mkdtemp(tmpl.data()), nullptr) << std::strerror(errno);
        mDir = tmpl;
        mPath = mDir + "/big.pnb";
    }
    void TearDown() override {
        if (mFd >= 0) ::close(mFd);
        ::unlink(mPath.c_str());
        ::rmdir(mDir.c_str());
    }

    // Writes `b` at `offset`; false (after noting why) if the file system refuses, e.g. EFBIG.
    bool put(uint64_t offset, std::span<const std::byte> b) {
        size_t done = 0;
        while (done < b.size()) {
            ssize_t n = ::pwrite(mFd, b.data() + done, b.size() - done, off_t(offset + done));
            if (n <= 0) {
                mWriteError = std::strerror(errno);
                return false;
            }
            done += size_t(n);
        }
        return true;
    }

    std::string mDir, mPath, mWriteError;
    int mFd = -1;
};

ChunkHeader checkedHeader(Tag tag, std::span<const std::byte> payload, uint32_t sequence) {
    ChunkHeader h;
    h.tag = tag;
    h.flags = kChunkHasChecksum;
    h.storedSize = h.rawSize = payload.size();
    h.payloadChecksum = checksum(payload);
    h.sequence = sequence;
    return h;
}

TEST_F(LargeFile, SparseFileOver4GiBReads) {
    struct statvfs fs {};
    ASSERT_EQ(::statvfs(mDir.c_str(), &fs), 0);
    if (uint64_t(fs.f_bavail) * fs.f_frsize < (uint64_t(64) << 20))
        GTEST_SKIP() << "less than 64 MiB free in " << mDir;

    // Layout, by the frame rules: header | STRS | BIG0 (4.5 GiB hole) | INFO | TOCX | footer.
    StringTable strings;
    strings.strings = {"large-file", "tail chunk past 4 GiB"};
    const std::vector<std::byte> strs = encodeChunk(strings);
    SceneInfo info;
    info.name = 0;
    info.generator = 1;
    const std::vector<std::byte> tail = encodeChunk(info);

    const uint64_t off0 = kFileHeaderSize;
    const uint64_t off1 = alignUp(off0 + kChunkHeaderSize + strs.size());
    const uint64_t off2 = alignUp(off1 + kChunkHeaderSize + kBigSize);
    const uint64_t tocOff = alignUp(off2 + kChunkHeaderSize + tail.size());
    ASSERT_GT(off2, uint64_t(1) << 32);

    ChunkHeader h0 = checkedHeader(tags::kStrings, strs, 0);
    // The big chunk has no checksum: verifying it would mean reading 4.5 GiB of zeros.
    ChunkHeader h1;
    h1.tag = kBigTag;
    h1.storedSize = h1.rawSize = kBigSize;
    h1.sequence = 1;
    ChunkHeader h2 = checkedHeader(tags::kSceneInfo, tail, 2);
    auto entry = [](const ChunkHeader& h, uint64_t off) {
        return TocEntry{h.tag, h.version, h.flags, off, h.storedSize, h.rawSize,
                        h.payloadChecksum};
    };
    const std::vector<TocEntry> entries = {entry(h0, off0), entry(h1, off1), entry(h2, off2)};
    const std::vector<std::byte> toc = encodeToc(entries);
    ChunkHeader tocHeader = checkedHeader(tags::kToc, toc, 3);
    const uint64_t footerOff = tocOff + kChunkHeaderSize + toc.size();
    const uint64_t fileSize = footerOff + kFooterSize;

    mFd = ::open(mPath.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    ASSERT_GE(mFd, 0) << std::strerror(errno);
    // Everything not written below is a hole and reads as zeros: the BIG0 payload and all
    // padding, which the frame rules require to be zero anyway.
    bool written = put(0, encodeFileHeader(FileHeader{})) && put(off0, encodeChunkHeader(h0)) &&
                   put(off0 + kChunkHeaderSize, strs) && put(off1, encodeChunkHeader(h1)) &&
                   put(off2, encodeChunkHeader(h2)) && put(off2 + kChunkHeaderSize, tail) &&
                   put(tocOff, encodeChunkHeader(tocHeader)) &&
                   put(tocOff + kChunkHeaderSize, toc) &&
                   put(footerOff, encodeFooter(Footer{tocOff, fileSize}));
    if (!written) GTEST_SKIP() << "cannot write a file over 4 GiB here: " << mWriteError;
    struct stat st {};
    ASSERT_EQ(::fstat(mFd, &st), 0);
    ASSERT_EQ(uint64_t(st.st_size), fileSize);
    if (uint64_t(st.st_blocks) * 512 > (uint64_t(64) << 20))
        GTEST_SKIP() << "the file system does not keep holes (" << st.st_blocks * 512
                     << " bytes allocated)";

    for (bool useToc : {true, false}) {
        SCOPED_TRACE(useToc ? "TOC index" : "header scan");
        auto c = Container::open(mPath, ReadOptions{.useToc = useToc});
        ASSERT_TRUE(c.ok()) << c.error().describe();
        ASSERT_EQ(c->chunks().size(), 3u);
        EXPECT_EQ(c->bytes().size(), fileSize);
        const ChunkInfo& big = c->chunks()[1];
        const ChunkInfo& last = c->chunks()[2];
        EXPECT_TRUE(big.header.tag == kBigTag);
        EXPECT_EQ(big.header.storedSize, kBigSize);
        EXPECT_EQ(last.headerOffset, off2);
        EXPECT_GT(last.headerOffset, uint64_t(1) << 32);
        EXPECT_EQ(last.payloadOffset, off2 + kChunkHeaderSize);

        // The chunk past 4 GiB: exact bytes, zero-copy from the mapping, checksum verified.
        auto loaded = c->load(last);
        ASSERT_TRUE(loaded.ok()) << loaded.error().describe();
        EXPECT_TRUE(loaded->isZeroCopy());
        ASSERT_EQ(loaded->bytes().size(), tail.size());
        EXPECT_EQ(std::memcmp(loaded->bytes().data(), tail.data(), tail.size()), 0);
        EXPECT_EQ(loaded->bytes().data(), c->bytes().data() + off2 + kChunkHeaderSize);
        EXPECT_TRUE(c->stored(last).ok());
        EXPECT_TRUE(isOk(c->verifyAll()));

        // The big chunk is a 4.5 GiB view; its ends are readable (touches two pages only).
        auto bigPayload = c->load(big);
        ASSERT_TRUE(bigPayload.ok());
        ASSERT_EQ(bigPayload->bytes().size(), kBigSize);
        EXPECT_EQ(bigPayload->bytes().front(), std::byte{0});
        EXPECT_EQ(bigPayload->bytes().back(), std::byte{0});

        auto scene = readScene(*c);
        ASSERT_TRUE(scene.ok()) << scene.error().describe();
        EXPECT_EQ(scene->unknownChunks, 1u);
        EXPECT_EQ(scene->str(scene->info.name), "large-file");
        EXPECT_EQ(scene->str(scene->info.generator), "tail chunk past 4 GiB");
    }

    // Streaming is not tried: it reads every byte, 4.5 GiB of them.

    // The checksum past 4 GiB is really checked, and the error names a 64-bit offset.
    const std::byte flipped = tail[5] ^ std::byte{0xFF};
    ASSERT_TRUE(put(off2 + kChunkHeaderSize + 5, {&flipped, 1}));
    {
        auto c = Container::open(mPath);
        ASSERT_TRUE(c.ok()) << c.error().describe();
        auto loaded = c->load(c->chunks()[2]);
        ASSERT_FALSE(loaded.ok());
        EXPECT_EQ(loaded.error().code, FormatError::ChecksumMismatch);
        EXPECT_EQ(loaded.error().offset, off2 + kChunkHeaderSize);
        EXPECT_NE(loaded.error().describe().find(std::to_string(off2 + kChunkHeaderSize)),
                  std::string::npos)
            << loaded.error().describe();
    }

    // Cut inside the header past 4 GiB: both indexes report the truncation where it happens.
    ASSERT_EQ(::ftruncate(mFd, off_t(off2 + 10)), 0);
    for (bool useToc : {true, false}) {
        auto c = Container::open(mPath, ReadOptions{.useToc = useToc});
        ASSERT_FALSE(c.ok());
        EXPECT_EQ(c.error().code, FormatError::Truncated) << c.error().describe();
        // Either the cut or the start of the cut header; both are past 2^32.
        EXPECT_GE(c.error().offset, off2) << c.error().describe();
        EXPECT_LE(c.error().offset, off2 + 10) << c.error().describe();
    }
}

} // namespace
