// pnb/container.h — the byte layout of the container's frame: file header, chunk headers, table
// of contents and footer (docs/FORMAT.md §2–3). Typed chunk payloads are in chunks.h.
//
// Does NOT do: file I/O (reader.h, writer.h), payload decoding (chunks.h).
//
// Everything is little-endian; the encode/decode functions here are the only code that knows the
// field offsets. They are public so tests and tools can build files by hand (e.g. a sparse
// 5 GiB file) without a second copy of the layout.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "pnb/error.h"
#include "pnb/tags.h"

namespace pnb {

// Format version written by this library. A reader accepts any minor of its own major.
inline constexpr uint16_t kVersionMajor = 1;
inline constexpr uint16_t kVersionMinor = 0;

// Every chunk header (and so every payload) starts at a multiple of this many bytes, so an
// uncompressed payload can be used in place from a memory mapping (SIMD loads, GPU uploads).
inline constexpr uint64_t kAlignment = 64;

inline constexpr size_t kFileHeaderSize = 64;
inline constexpr size_t kChunkHeaderSize = 64;
inline constexpr size_t kFooterSize = 32;

// PNG-style magic: the high-bit byte catches 7-bit transfers, CR LF catches CRLF->LF conversion,
// 0x1A stops DOS `type`, the final LF catches LF->CRLF conversion.
inline constexpr std::array<uint8_t, 8> kFileMagic = {0x89, 'P', 'N', 'B', '\r', '\n', 0x1A, '\n'};
inline constexpr std::array<uint8_t, 8> kFooterMagic = {'P', 'N', 'B', 'E', 'N', 'D', 0x1A, '\n'};
// Written as a little-endian u32: bytes 04 03 02 01. A big-endian writer would produce 01 02 03 04.
inline constexpr uint32_t kEndianMarker = 0x01020304;

enum class Compression : uint8_t {
    None = 0,
    Zstd = 1,
};

// Chunk header flag bits (u16). Bits not listed must be zero.
inline constexpr uint16_t kChunkCompressionMask = 0x000F; // a Compression value
inline constexpr uint16_t kChunkHasChecksum = 0x0010;     // payloadChecksum is valid
// A reader that does not know this chunk's tag or version must refuse it instead of skipping it
// or reading the fields it knows (FORMAT.md 3.5).
inline constexpr uint16_t kChunkCritical = 0x0020;

struct FileHeader {
    uint16_t versionMajor = kVersionMajor;
    uint16_t versionMinor = kVersionMinor;
    uint32_t flags = 0; // reserved in 1.0, must be zero
};

struct ChunkHeader {
    Tag tag{};
    uint16_t version = 1; // version of this chunk kind's payload layout
    uint16_t flags = 0;
    uint64_t storedSize = 0;      // payload bytes in the file (after compression)
    uint64_t rawSize = 0;         // payload bytes after decompression (= storedSize if none)
    uint64_t payloadChecksum = 0; // XXH3-64 of the stored bytes, if kChunkHasChecksum
    uint32_t sequence = 0;        // index of this chunk in file order, 0-based

    Compression compression() const {
        return static_cast<Compression>(flags & kChunkCompressionMask);
    }
    bool hasChecksum() const { return (flags & kChunkHasChecksum) != 0; }
};

struct Footer {
    uint64_t tocOffset = 0; // absolute offset of the TOCX chunk header
    uint64_t fileSize = 0;  // total file size including this footer
};

// One table-of-contents entry (FORMAT.md §3.3).
struct TocEntry {
    Tag tag{};
    uint16_t version = 0;
    uint16_t flags = 0;
    uint64_t offset = 0; // absolute offset of the chunk header
    uint64_t storedSize = 0;
    uint64_t rawSize = 0;
    uint64_t payloadChecksum = 0;
};

// A chunk as located in a file: its header plus where its payload lives.
struct ChunkInfo {
    ChunkHeader header;
    uint64_t headerOffset = 0;
    uint64_t payloadOffset = 0; // = headerOffset + kChunkHeaderSize
};

// XXH3-64 with seed 0, the only hash the format uses.
uint64_t checksum(std::span<const std::byte> bytes);

// Rounds up to the next multiple of kAlignment. Precondition: v <= UINT64_MAX - kAlignment.
constexpr uint64_t alignUp(uint64_t v) { return (v + kAlignment - 1) & ~(kAlignment - 1); }

// Encoders write exactly k*Size bytes, including the header's own checksum.
std::array<std::byte, kFileHeaderSize> encodeFileHeader(const FileHeader& h);
std::array<std::byte, kChunkHeaderSize> encodeChunkHeader(const ChunkHeader& h);
std::array<std::byte, kFooterSize> encodeFooter(const Footer& f);
std::vector<std::byte> encodeToc(std::span<const TocEntry> entries);

// Decoders validate everything that can be validated locally (magic, checksum, reserved bits,
// version). `offset` is the absolute position of `bytes` in the file, used in error messages.
// Precondition: bytes.size() >= the structure's size (callers check truncation first).
Result<FileHeader> decodeFileHeader(std::span<const std::byte> bytes);
Result<ChunkHeader> decodeChunkHeader(std::span<const std::byte> bytes, uint64_t offset);
Result<Footer> decodeFooter(std::span<const std::byte> bytes, uint64_t offset);
Result<std::vector<TocEntry>> decodeToc(std::span<const std::byte> payload, uint64_t offset);

} // namespace pnb
