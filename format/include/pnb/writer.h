// pnb/writer.h — writing a container: deterministic bytes, atomic replacement of the target.
//
// Does NOT do: typed payload encoding (chunks.h); ordering policy (the caller adds chunks in the
// streamable order of FORMAT.md §4.1; scene.h readScene checks it). Copied chunks (copyChunk)
// are taken as they are: the writer does not check that their references still hold.
//
// Chunks are written as they are added, so memory stays bounded by one chunk. The file is built
// under a temporary name in the target's directory, then fsync'ed and renamed over the target by
// commit(): an interrupted save (crash, kill, full disk) leaves any previous file intact.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pnb/container.h"
#include "pnb/error.h"
#include "pnb/file_lock.h"

namespace pnb {

class CompressionMemo; // compression_memo.h
class Container;       // reader.h

struct WriteOptions {
    // Store an XXH3 checksum of every payload. Default: true. The TOC always has one.
    bool checksums = true;
    // zstd level for chunks added with Compression::Zstd. Default: 9 (ratio/speed balance).
    int zstdLevel = 9;
    // When set, zstd results are looked up in and added to this memo (compression_memo.h):
    // the same bytes, computed once per process for payloads several containers share.
    std::shared_ptr<CompressionMemo> compressionMemo;
    // commit() renames under an exclusive lock on the file it replaces (pnb/file_lock.h), so it
    // never lands inside another tool's read-to-rename; this bounds the wait for that lock.
    FileLock::Options lock;
    // The caller already holds the target's lock (pnb-edit, from read to rename): commit() uses
    // it instead of taking it a second time (which would wait on itself). Its path must be the
    // target's.
    const FileLock* heldLock = nullptr;
    // Called under the lock just before the rename (the compare-before-rename of a tool that
    // read the target): an error aborts the commit and leaves the target untouched.
    std::function<Status()> beforeReplace;
};

class Writer {
public:
    // Starts a file that commit() will atomically place at `path`. The temporary is
    // "<dir>/.<name>.tmp.<pid>.<n>"; it is removed if the Writer is destroyed uncommitted, and by
    // the next create() for the same path if the process died first (createTemporaryFor).
    static Result<Writer> create(const std::string& path, const WriteOptions& options = {});
    // Writes into `out` (cleared first) instead of a file; commit() only finalises. For tests.
    static Writer toMemory(std::vector<std::byte>* out, const WriteOptions& options = {});

    Writer(Writer&&) noexcept;
    Writer& operator=(Writer&&) noexcept;
    ~Writer();

    // Appends a chunk. With Compression::Zstd the payload is compressed, but stored raw when
    // compression would not make it smaller (the flag then says None). Deterministic: the same
    // arguments always produce the same bytes. Errors: IoError (disk), after which only
    // destruction is valid.
    // `critical` sets kChunkCritical: readers that do not know this tag or version must refuse
    // the chunk (FORMAT.md 3.5); no chunk of format 1.0 needs it.
    Status addChunk(Tag tag, uint16_t version, std::span<const std::byte> raw,
                    Compression compression = Compression::None, bool critical = false);
    // Appends `chunk` of `source` as it is stored there: the same tag, version, flags
    // (compression and checksum bit), stored and raw sizes, payload checksum and payload bytes.
    // Only the sequence number and the header checksum are this writer's. The payload is neither
    // decompressed nor re-compressed nor re-hashed by the writer: `source.stored()` supplies it,
    // and verifies its checksum if `source.options().verifyChecksums` (so a copy of a damaged
    // chunk fails with ChecksumMismatch instead of spreading the damage). WriteOptions do not
    // apply: a chunk without a checksum stays without one. Rewriting a file chunk by chunk with
    // copyChunk gives a byte-identical file.
    // Preconditions: `chunk` is one of `source.chunks()` (so never the TOCX). Errors: the
    // source's (BadToc, ChecksumMismatch), IoError (disk, after which only destruction is valid).
    Status copyChunk(const Container& source, const ChunkInfo& chunk);
    // Writes the TOC and footer, flushes, fsyncs and renames into place, under the target's
    // lock (WriteOptions::lock, heldLock, beforeReplace). Call once. Errors: IoError, Locked
    // (another tool kept the target locked past the timeout), beforeReplace's; on any error the
    // target is untouched.
    Status commit();

    // Bytes written so far (next chunk's offset is alignUp of this).
    uint64_t size() const;

private:
    struct Impl;
    explicit Writer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> mImpl;
};

} // namespace pnb
