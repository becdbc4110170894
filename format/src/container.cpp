// Frame encoding and decoding: file header, chunk header, footer, table of contents.
// Field offsets are defined here and in docs/FORMAT.md §3 only; keep the two in step.

#include "pnb/container.h"

#include <cstring>

#include <xxhash.h>

#include "bytes.h"

namespace pnb {

using detail::loadLE;
using detail::storeLE;

namespace {

constexpr size_t kTocEntrySize = 40;
constexpr size_t kTocPreambleSize = 8;

bool allZero(std::span<const std::byte> bytes) {
    for (std::byte b : bytes)
        if (b != std::byte{0}) return false;
    return true;
}

Tag loadTag(const std::byte* p) {
    Tag t;
    std::memcpy(t.c, p, 4);
    return t;
}

} // namespace

uint64_t checksum(std::span<const std::byte> bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

// [SECTION] file header: magic[8] major:u16 minor:u16 endian:u32 headerSize:u32 flags:u32
//           reserved[32] checksum:u64 (of bytes 0..55)

std::array<std::byte, kFileHeaderSize> encodeFileHeader(const FileHeader& h) {
    std::array<std::byte, kFileHeaderSize> b{};
    std::memcpy(b.data(), kFileMagic.data(), 8);
    storeLE<uint16_t>(&b[8], h.versionMajor);
    storeLE<uint16_t>(&b[10], h.versionMinor);
    storeLE<uint32_t>(&b[12], kEndianMarker);
    storeLE<uint32_t>(&b[16], uint32_t(kFileHeaderSize));
    storeLE<uint32_t>(&b[20], h.flags);
    storeLE<uint64_t>(&b[56], checksum({b.data(), 56}));
    return b;
}

Result<FileHeader> decodeFileHeader(std::span<const std::byte> b) {
    if (std::memcmp(b.data(), kFileMagic.data(), 8) != 0) {
        // A file that starts right but with CR/LF bytes changed went through a text-mode copy.
        bool textMode = b[0] == std::byte{0x89} && b[1] == std::byte{'P'} &&
                        b[2] == std::byte{'N'} && b[3] == std::byte{'B'};
        return makeError(FormatError::BadMagic, 0, "%s",
                         textMode ? "magic damaged: the file was transferred in text mode "
                                    "(line endings or 8-bit bytes changed)"
                                  : "not a Penumbra container (magic \\x89PNB\\r\\n\\x1a\\n expected)");
    }
    uint32_t endian = loadLE<uint32_t>(&b[12]);
    if (endian != kEndianMarker)
        return makeError(FormatError::BadEndianness, 12,
                         "endianness marker 0x%08x is not the little-endian 0x%08x", endian,
                         kEndianMarker);
    FileHeader h;
    h.versionMajor = loadLE<uint16_t>(&b[8]);
    h.versionMinor = loadLE<uint16_t>(&b[10]);
    // The version is checked before the checksum: a future major may change the header.
    if (h.versionMajor != kVersionMajor)
        return makeError(FormatError::UnsupportedVersion, 8,
                         "file format version %u.%u, this reader supports %u.x; %s",
                         h.versionMajor, h.versionMinor, kVersionMajor,
                         h.versionMajor > kVersionMajor ? "update Penumbra to read it"
                                                        : "reconvert the scene");
    if (loadLE<uint64_t>(&b[56]) != checksum(b.first(56)))
        return makeError(FormatError::HeaderChecksumMismatch, 56, "file header checksum mismatch");
    if (loadLE<uint32_t>(&b[16]) != kFileHeaderSize)
        return makeError(FormatError::BadHeader, 16, "file header size %u, expected %zu",
                         loadLE<uint32_t>(&b[16]), kFileHeaderSize);
    h.flags = loadLE<uint32_t>(&b[20]);
    if (h.flags != 0)
        return makeError(FormatError::BadHeader, 20, "unknown file flags 0x%08x", h.flags);
    if (!allZero(b.subspan(24, 32)))
        return makeError(FormatError::BadHeader, 24, "reserved file header bytes are not zero");
    return h;
}

// [SECTION] chunk header: tag[4] version:u16 flags:u16 storedSize:u64 rawSize:u64
//           payloadChecksum:u64 sequence:u32 reserved[20] checksum:u64 (of bytes 0..55)

std::array<std::byte, kChunkHeaderSize> encodeChunkHeader(const ChunkHeader& h) {
    std::array<std::byte, kChunkHeaderSize> b{};
    std::memcpy(b.data(), h.tag.c, 4);
    storeLE<uint16_t>(&b[4], h.version);
    storeLE<uint16_t>(&b[6], h.flags);
    storeLE<uint64_t>(&b[8], h.storedSize);
    storeLE<uint64_t>(&b[16], h.rawSize);
    storeLE<uint64_t>(&b[24], h.payloadChecksum);
    storeLE<uint32_t>(&b[32], h.sequence);
    storeLE<uint64_t>(&b[56], checksum({b.data(), 56}));
    return b;
}

Result<ChunkHeader> decodeChunkHeader(std::span<const std::byte> b, uint64_t offset) {
    if (loadLE<uint64_t>(&b[56]) != checksum(b.first(56)))
        return makeError(FormatError::HeaderChecksumMismatch, offset,
                         "chunk header checksum mismatch");
    ChunkHeader h;
    h.tag = loadTag(b.data());
    h.version = loadLE<uint16_t>(&b[4]);
    h.flags = loadLE<uint16_t>(&b[6]);
    h.storedSize = loadLE<uint64_t>(&b[8]);
    h.rawSize = loadLE<uint64_t>(&b[16]);
    h.payloadChecksum = loadLE<uint64_t>(&b[24]);
    h.sequence = loadLE<uint32_t>(&b[32]);
    std::string tag = h.tag.str();
    if (h.flags & ~(kChunkCompressionMask | kChunkHasChecksum | kChunkCritical))
        return makeError(FormatError::BadHeader, offset + 6, "chunk '%s': unknown flags 0x%04x",
                         tag.c_str(), h.flags);
    if (uint8_t(h.compression()) > uint8_t(Compression::Zstd))
        return makeError(FormatError::BadHeader, offset + 6, "chunk '%s': unknown compression %u",
                         tag.c_str(), unsigned(h.compression()));
    if (h.compression() == Compression::None && h.rawSize != h.storedSize)
        return makeError(FormatError::BadChunkSize, offset + 16,
                         "chunk '%s': uncompressed but raw size %llu != stored size %llu",
                         tag.c_str(), (unsigned long long)h.rawSize,
                         (unsigned long long)h.storedSize);
    if (!h.hasChecksum() && h.payloadChecksum != 0)
        return makeError(FormatError::BadHeader, offset + 24,
                         "chunk '%s': checksum present but flag not set", tag.c_str());
    if (!allZero(b.subspan(36, 20)))
        return makeError(FormatError::BadHeader, offset + 36,
                         "chunk '%s': reserved header bytes are not zero", tag.c_str());
    return h;
}

// [SECTION] footer: magic[8] tocOffset:u64 fileSize:u64 checksum:u64 (of bytes 0..23)

std::array<std::byte, kFooterSize> encodeFooter(const Footer& f) {
    std::array<std::byte, kFooterSize> b{};
    std::memcpy(b.data(), kFooterMagic.data(), 8);
    storeLE<uint64_t>(&b[8], f.tocOffset);
    storeLE<uint64_t>(&b[16], f.fileSize);
    storeLE<uint64_t>(&b[24], checksum({b.data(), 24}));
    return b;
}

Result<Footer> decodeFooter(std::span<const std::byte> b, uint64_t offset) {
    if (std::memcmp(b.data(), kFooterMagic.data(), 8) != 0)
        return makeError(FormatError::Truncated, offset,
                         "no footer at the end of the file (truncated or not finished)");
    if (loadLE<uint64_t>(&b[24]) != checksum(b.first(24)))
        return makeError(FormatError::HeaderChecksumMismatch, offset, "footer checksum mismatch");
    Footer f;
    f.tocOffset = loadLE<uint64_t>(&b[8]);
    f.fileSize = loadLE<uint64_t>(&b[16]);
    return f;
}

// [SECTION] table of contents payload: count:u32 reserved:u32, then count entries of
//           tag[4] version:u16 flags:u16 offset:u64 storedSize:u64 rawSize:u64 checksum:u64

std::vector<std::byte> encodeToc(std::span<const TocEntry> entries) {
    std::vector<std::byte> b(kTocPreambleSize + entries.size() * kTocEntrySize);
    storeLE<uint32_t>(&b[0], uint32_t(entries.size()));
    std::byte* p = b.data() + kTocPreambleSize;
    for (const TocEntry& e : entries) {
        std::memcpy(p, e.tag.c, 4);
        storeLE<uint16_t>(p + 4, e.version);
        storeLE<uint16_t>(p + 6, e.flags);
        storeLE<uint64_t>(p + 8, e.offset);
        storeLE<uint64_t>(p + 16, e.storedSize);
        storeLE<uint64_t>(p + 24, e.rawSize);
        storeLE<uint64_t>(p + 32, e.payloadChecksum);
        p += kTocEntrySize;
    }
    return b;
}

Result<std::vector<TocEntry>> decodeToc(std::span<const std::byte> b, uint64_t offset) {
    if (b.size() < kTocPreambleSize)
        return makeError(FormatError::BadToc, offset, "table of contents shorter than 8 bytes");
    uint32_t count = loadLE<uint32_t>(&b[0]);
    if (loadLE<uint32_t>(&b[4]) != 0)
        return makeError(FormatError::BadToc, offset + 4, "reserved TOC field is not zero");
    if ((b.size() - kTocPreambleSize) / kTocEntrySize != count ||
        (b.size() - kTocPreambleSize) % kTocEntrySize != 0)
        return makeError(FormatError::BadToc, offset,
                         "table of contents of %zu bytes cannot hold %u entries", b.size(), count);
    std::vector<TocEntry> entries(count);
    const std::byte* p = b.data() + kTocPreambleSize;
    for (TocEntry& e : entries) {
        e.tag = loadTag(p);
        e.version = loadLE<uint16_t>(p + 4);
        e.flags = loadLE<uint16_t>(p + 6);
        e.offset = loadLE<uint64_t>(p + 8);
        e.storedSize = loadLE<uint64_t>(p + 16);
        e.rawSize = loadLE<uint64_t>(p + 24);
        e.payloadChecksum = loadLE<uint64_t>(p + 32);
        p += kTocEntrySize;
    }
    return entries;
}

} // namespace pnb
