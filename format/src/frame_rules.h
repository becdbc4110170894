// The frame rules of FORMAT.md §3.4, shared by the memory-mapped reader and the stream reader so
// both accept exactly the same files. Internal to the format library.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "pnb/container.h"
#include "pnb/error.h"

namespace pnb::detail {

// Tracks where the next chunk must start and checks each chunk header against that.
class FrameRules {
public:
    // `limit` is the first byte that chunk data may not reach (the footer's offset), or
    // UINT64_MAX when the total size is not known yet (streaming). `limitIsEndOfData` says the
    // limit is merely where the available bytes end (a header scan of a file that may have been
    // cut short): a chunk of possible size reaching past it is then Truncated, as the stream
    // reader reports when read() runs dry, rather than BadChunkSize.
    explicit FrameRules(uint64_t limit, bool limitIsEndOfData = false)
        : mLimit(limit), mLimitIsEndOfData(limitIsEndOfData) {}

    // Checks a decoded chunk header found at `offset`: position, sequence number, size bounds,
    // and the TOC chunk's fixed properties. On success advances to the next chunk position.
    Status accept(const ChunkHeader& h, uint64_t offset);

    uint64_t nextOffset() const { return mNext; }
    uint32_t count() const { return mCount; }

private:
    uint64_t mLimit;
    bool mLimitIsEndOfData;
    uint64_t mNext = kFileHeaderSize;
    uint32_t mCount = 0;
};

// Checks that the TOC entries describe exactly `chunks` (same order, headers, offsets).
Status checkTocMatches(std::span<const TocEntry> toc, std::span<const ChunkInfo> chunks,
                       uint64_t tocOffset);

// Checks the footer against where the TOC was found and how long the file is.
Status checkFooter(const Footer& f, uint64_t tocOffset, uint64_t footerOffset);

TocEntry tocEntryFor(const ChunkInfo& c);

} // namespace pnb::detail
