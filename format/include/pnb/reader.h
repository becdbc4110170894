// pnb/reader.h — reading a container: random access from a memory mapping, or a forward-only
// stream that hands over each chunk as soon as its bytes have arrived (docs/FORMAT.md §5).
//
// Does NOT do: decoding typed payloads (chunks.h), cross-reference checks (scene.h validateScene).
//
// Both modes share one bounds-checked frame parser (container.h decoders + the rules of
// FORMAT.md §3), so they accept and reject exactly the same files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "pnb/container.h"
#include "pnb/error.h"

namespace pnb {

struct ReadOptions {
    // Verify each payload's XXH3 checksum when it is loaded (Container::load) or streamed.
    // Default: true. Turning it off skips hashing, not structural checks.
    bool verifyChecksums = true;
    // Container::open: locate chunks through the footer + table of contents (true, default) or by
    // scanning chunk headers from the start (false; also what streaming does). Both validate.
    bool useToc = true;
    // Upper bound on one chunk's raw (decompressed) size that load()/streaming will allocate.
    // Default: 4 GiB. Zero-copy views of uncompressed chunks are not limited.
    uint64_t maxRawChunkBytes = uint64_t(4) << 30;
};

// A loaded payload: a view into the mapping (uncompressed chunk), or an owned buffer
// (decompressed). Move-only so the view cannot outlive an owned buffer by copy.
class Payload {
public:
    Payload() = default;
    static Payload view(std::span<const std::byte> bytes);
    static Payload own(std::vector<std::byte> bytes);
    Payload(Payload&&) noexcept;
    Payload& operator=(Payload&&) noexcept;
    Payload(const Payload&) = delete;
    Payload& operator=(const Payload&) = delete;

    std::span<const std::byte> bytes() const { return mView; }
    bool isZeroCopy() const { return mOwned.empty() && !mView.empty(); }

private:
    std::vector<std::byte> mOwned;
    std::span<const std::byte> mView;
};

// An opened container. Thread safety: const member functions may be called concurrently.
class Container {
public:
    // Maps `path` read-only and indexes its chunks. Validates the file header, the footer and
    // table of contents (or every chunk header, with useToc = false); payloads are not hashed
    // until load(). Errors: IoError, Truncated, BadMagic, UnsupportedVersion, ...
    static Result<Container> open(const std::string& path, const ReadOptions& options = {});
    // Same over caller memory, which must outlive the Container (tests, fuzzing).
    static Result<Container> fromMemory(std::span<const std::byte> bytes,
                                        const ReadOptions& options = {});

    Container(Container&& other) noexcept;
    Container& operator=(Container&& other) noexcept;
    Container(const Container&) = delete;
    Container& operator=(const Container&) = delete;
    ~Container();

    const FileHeader& header() const { return mHeader; }
    const ReadOptions& options() const { return mOptions; }
    // Chunks in file order, excluding the table of contents itself.
    std::span<const ChunkInfo> chunks() const { return mChunks; }
    // The whole file.
    std::span<const std::byte> bytes() const { return mBytes; }

    // Chunks with `tag`, in file order (pointers into chunks()).
    std::vector<const ChunkInfo*> find(Tag tag) const;
    const ChunkInfo* findFirst(Tag tag) const;

    // The chunk's stored (possibly compressed) bytes, zero-copy. Re-validates the chunk header
    // against the index, and verifies the checksum if options().verifyChecksums.
    Result<std::span<const std::byte>> stored(const ChunkInfo& chunk) const;
    // The raw payload: zero-copy for uncompressed chunks, decompressed otherwise.
    Result<Payload> load(const ChunkInfo& chunk) const;
    // Decompresses (or copies) the raw payload into caller memory of exactly rawSize bytes.
    Status loadInto(const ChunkInfo& chunk, std::span<std::byte> dst) const;
    // Checks every chunk: header vs index, zero padding, checksum (always, whatever the
    // options), and that compressed payloads inflate to their raw size. First error wins.
    Status verifyAll() const;
    // IoError if the mapped file shrank under this Container (another program truncated it):
    // the pages past its new end read as zeros instead of raising SIGBUS, and every read above
    // reports this error instead of its own. A caller that reads bytes()/payload views itself
    // (an upload straight from the mapping) calls it after reading. Always ok for fromMemory.
    Status intact() const;

private:
    Container() = default;
    Status index();
    Status checkHeader(const ChunkInfo& chunk) const;

    ReadOptions mOptions;
    FileHeader mHeader;
    std::vector<ChunkInfo> mChunks;
    std::span<const std::byte> mBytes;
    void* mMapping = nullptr; // owned mmap, or null for fromMemory
    size_t mMappingSize = 0;
    int mGuardSlot = -1;      // detail::guardMapping slot of the mapping
    std::string mPath;        // for intact()'s message
    // `s`, unless the mapping shrank meanwhile: then intact()'s error, the true cause.
    Status guarded(Status s) const;
    Status verifyAllUnguarded() const;
};

// A chunk handed to a streaming callback. `payload` is the raw (decompressed, verified) payload;
// it is valid only during the callback.
struct StreamedChunk {
    ChunkInfo info;
    std::span<const std::byte> payload;
};
// Return false to stop reading early (streamChunks then returns success).
using ChunkCallback = std::function<bool(const StreamedChunk&)>;

// Reads a container front to back from a file descriptor (a file, pipe or socket) with read(2),
// calling `onChunk` for each chunk as soon as it is complete and verified. Memory is bounded by
// the largest chunk actually received. Validates the TOC, footer and end of file after the last
// chunk. Does not close `fd`.
Status streamChunks(int fd, const ReadOptions& options, const ChunkCallback& onChunk);
Status streamChunks(const std::string& path, const ReadOptions& options,
                    const ChunkCallback& onChunk);

// Reads chunk `info` again with pread(2) from a seekable `fd` of the same file (a streaming
// player fetching a texel level it dropped): the header at info.headerOffset must equal
// info.header, the checksum is verified (per `options`) and a compressed payload is inflated.
// Returns the raw payload, owned. Errors: IoError, Truncated (the file shrank), BadToc (the
// header there is another one: the file changed), ChecksumMismatch, decompression errors.
Result<Payload> readChunkAt(int fd, const ChunkInfo& info, const ReadOptions& options);

} // namespace pnb
