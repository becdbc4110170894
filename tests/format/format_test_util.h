// Helpers shared by the adversarial format tests: sample bytes, hand-built files, and real
// non-seekable streams (pipes) and in-memory descriptors (memfd) for streamChunks.
#pragma once

#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "pnb/container.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/writer.h"
#include "pnb_assets/box_room.h"

namespace pnb::test {

inline std::vector<std::byte> writeToMemory(const Scene& scene, const WriteOptions& options = {}) {
    std::vector<std::byte> bytes;
    Writer w = Writer::toMemory(&bytes, options);
    EXPECT_TRUE(isOk(writeScene(w, scene)));
    EXPECT_TRUE(isOk(w.commit()));
    return bytes;
}

// The box room with default options: every v1 chunk kind, ~32 KB.
inline std::vector<std::byte> sampleBytes(const WriteOptions& options = {}) {
    SceneBuilder b;
    assets::buildBoxRoom(b);
    return writeToMemory(b.scene, options);
}

// Builds a container by hand from the public encoders, for shapes the Writer never produces
// (crafted sizes, flags, versions). Chunks are laid out by the frame rules: each header at the
// next 64-byte boundary, the TOC last, the footer right after it.
class FileBuilder {
public:
    std::vector<std::byte> bytes;
    std::vector<TocEntry> toc;

    explicit FileBuilder(const FileHeader& header = {}) { append(encodeFileHeader(header)); }

    uint32_t nextSequence() const { return uint32_t(toc.size()); }

    // Appends `h` as given (only the sequence number is filled in) followed by `stored` and zero
    // padding. Returns the header's offset.
    uint64_t addRaw(ChunkHeader h, std::span<const std::byte> stored) {
        h.sequence = nextSequence();
        uint64_t offset = bytes.size();
        append(encodeChunkHeader(h));
        append(stored);
        bytes.resize(alignUp(bytes.size()));
        toc.push_back(TocEntry{h.tag, h.version, h.flags, offset, h.storedSize, h.rawSize,
                               h.payloadChecksum});
        return offset;
    }

    // An ordinary uncompressed, checksummed chunk.
    uint64_t add(Tag tag, uint16_t version, std::span<const std::byte> payload) {
        ChunkHeader h;
        h.tag = tag;
        h.version = version;
        h.flags = kChunkHasChecksum;
        h.storedSize = h.rawSize = payload.size();
        h.payloadChecksum = checksum(payload);
        return addRaw(h, payload);
    }

    // Appends the table of contents and the footer. Returns the finished file.
    std::vector<std::byte> finish() {
        std::vector<std::byte> payload = encodeToc(toc);
        ChunkHeader h;
        h.tag = tags::kToc;
        h.version = 1;
        h.flags = kChunkHasChecksum;
        h.storedSize = h.rawSize = payload.size();
        h.payloadChecksum = checksum(payload);
        h.sequence = nextSequence();
        uint64_t tocOffset = bytes.size();
        append(encodeChunkHeader(h));
        append(payload);
        append(encodeFooter(Footer{tocOffset, bytes.size() + kFooterSize}));
        return bytes;
    }

private:
    void append(std::span<const std::byte> b) { bytes.insert(bytes.end(), b.begin(), b.end()); }
};

// An anonymous in-memory file: a real descriptor for streamChunks without touching the disk.
class MemFd {
public:
    explicit MemFd(std::span<const std::byte> contents) {
        mFd = memfd_create("pnb-test", MFD_CLOEXEC);
        EXPECT_GE(mFd, 0) << std::strerror(errno);
        writeAll(0, contents);
    }
    ~MemFd() {
        if (mFd >= 0) ::close(mFd);
    }
    MemFd(const MemFd&) = delete;
    MemFd& operator=(const MemFd&) = delete;

    int fd() const { return mFd; }

    // Overwrites bytes in place (the file keeps its size unless the write extends it).
    void writeAll(uint64_t offset, std::span<const std::byte> b) {
        size_t done = 0;
        while (done < b.size()) {
            ssize_t n = ::pwrite(mFd, b.data() + done, b.size() - done, off_t(offset + done));
            ASSERT_GT(n, 0) << std::strerror(errno);
            done += size_t(n);
        }
    }
    void truncate(uint64_t size) { ASSERT_EQ(::ftruncate(mFd, off_t(size)), 0); }

    // Streams the current contents from the start.
    Status stream(const ReadOptions& options, const ChunkCallback& onChunk) {
        EXPECT_EQ(::lseek(mFd, 0, SEEK_SET), 0);
        return streamChunks(mFd, options, onChunk);
    }

private:
    int mFd = -1;
};

// Streams `bytes` through a pipe fed by a writer thread, so the reader sees a real
// non-seekable stream whose data arrives in pieces (pipe capacity is 64 KiB).
inline Status streamThroughPipe(std::span<const std::byte> bytes, const ReadOptions& options,
                                const ChunkCallback& onChunk) {
    int fds[2];
    if (::pipe(fds) != 0) {
        ADD_FAILURE() << "pipe: " << std::strerror(errno);
        return makeError(FormatError::IoError, 0, "pipe failed");
    }
    std::thread feeder([&bytes, out = fds[1]] {
        size_t done = 0;
        while (done < bytes.size()) {
            ssize_t n = ::write(out, bytes.data() + done, bytes.size() - done);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) break;
            done += size_t(n);
        }
        ::close(out);
    });
    Status s = streamChunks(fds[0], options, onChunk);
    // Drain whatever the reader left (it may stop early on an error) so the feeder can finish
    // without blocking on a full pipe or dying of SIGPIPE.
    char sink[4096];
    while (::read(fds[0], sink, sizeof(sink)) > 0) {
    }
    feeder.join();
    ::close(fds[0]);
    return s;
}

// A chunk as a reader delivered it: header fields plus the raw (decompressed) payload.
struct SeenChunk {
    ChunkHeader header;
    uint64_t headerOffset = 0;
    std::vector<std::byte> raw;
};

inline ChunkCallback collectInto(std::vector<SeenChunk>& out) {
    return [&out](const StreamedChunk& c) {
        out.push_back(SeenChunk{c.info.header, c.info.headerOffset,
                                std::vector<std::byte>(c.payload.begin(), c.payload.end())});
        return true;
    };
}

} // namespace pnb::test
