#include "frame_rules.h"

namespace pnb::detail {

namespace {
// No chunk of a real file ends beyond 2^62 bytes; keeps alignUp and offset sums far from overflow.
constexpr uint64_t kMaxChunkEnd = uint64_t(1) << 62;
} // namespace

Status FrameRules::accept(const ChunkHeader& h, uint64_t offset) {
    std::string tag = h.tag.str();
    if (offset != mNext)
        return makeError(FormatError::BadToc, offset, "chunk expected at byte %llu",
                         (unsigned long long)mNext);
    if (h.sequence != mCount)
        return makeError(FormatError::BadHeader, offset + 32,
                         "chunk '%s' has sequence number %u, expected %u", tag.c_str(), h.sequence,
                         mCount);
    uint64_t payloadOffset = offset + kChunkHeaderSize;
    if (payloadOffset > mLimit || h.storedSize > mLimit - payloadOffset) {
        // The header passed its checksum, so a size a real file can have means the file ends
        // early; sizes past kMaxChunkEnd cannot be real and stay BadChunkSize.
        if (mLimitIsEndOfData && payloadOffset <= kMaxChunkEnd &&
            h.storedSize <= kMaxChunkEnd - payloadOffset)
            return makeError(FormatError::Truncated, mLimit,
                             "file ends inside chunk %u '%s' (%llu payload bytes from byte %llu)",
                             h.sequence, tag.c_str(), (unsigned long long)h.storedSize,
                             (unsigned long long)payloadOffset);
        return makeError(FormatError::BadChunkSize, offset + 8,
                         "chunk %u '%s' of %llu bytes runs past the end of the file", h.sequence,
                         tag.c_str(), (unsigned long long)h.storedSize);
    }
    if (h.tag == tags::kToc) {
        if (h.version != 1 || h.compression() != Compression::None || !h.hasChecksum())
            return makeError(FormatError::BadToc, offset,
                             "table of contents must be version 1, uncompressed, checksummed");
        mNext = payloadOffset + h.storedSize; // the footer follows without padding
    } else {
        // alignUp cannot overflow: payloadOffset + storedSize <= mLimit, and a real limit is a
        // file size; with an unknown limit (streaming) ends beyond kMaxChunkEnd are refused here.
        uint64_t end = payloadOffset + h.storedSize;
        if (end > kMaxChunkEnd)
            return makeError(FormatError::BadChunkSize, offset + 8, "chunk '%s' is too large",
                             tag.c_str());
        mNext = alignUp(end);
    }
    ++mCount;
    return {};
}

TocEntry tocEntryFor(const ChunkInfo& c) {
    const ChunkHeader& h = c.header;
    return TocEntry{h.tag, h.version, h.flags, c.headerOffset, h.storedSize, h.rawSize,
                    h.payloadChecksum};
}

Status checkTocMatches(std::span<const TocEntry> toc, std::span<const ChunkInfo> chunks,
                       uint64_t tocOffset) {
    if (toc.size() != chunks.size())
        return makeError(FormatError::BadToc, tocOffset,
                         "table of contents lists %zu chunks, the file has %zu", toc.size(),
                         chunks.size());
    for (size_t i = 0; i < toc.size(); ++i) {
        TocEntry e = tocEntryFor(chunks[i]);
        const TocEntry& t = toc[i];
        if (!(t.tag == e.tag) || t.version != e.version || t.flags != e.flags ||
            t.offset != e.offset || t.storedSize != e.storedSize || t.rawSize != e.rawSize ||
            t.payloadChecksum != e.payloadChecksum)
            return makeError(FormatError::BadToc, chunks[i].headerOffset,
                             "table of contents entry %zu disagrees with chunk header '%s'", i,
                             e.tag.str().c_str());
    }
    return {};
}

Status checkFooter(const Footer& f, uint64_t tocOffset, uint64_t footerOffset) {
    if (f.tocOffset != tocOffset)
        return makeError(FormatError::BadToc, footerOffset + 8,
                         "footer points at byte %llu, the table of contents is at %llu",
                         (unsigned long long)f.tocOffset, (unsigned long long)tocOffset);
    if (f.fileSize != footerOffset + kFooterSize)
        return makeError(FormatError::BadToc, footerOffset + 16,
                         "footer records a file size of %llu bytes, it is %llu",
                         (unsigned long long)f.fileSize,
                         (unsigned long long)(footerOffset + kFooterSize));
    return {};
}

} // namespace pnb::detail
