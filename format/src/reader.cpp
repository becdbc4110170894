// Container reader: memory-mapped random access and forward-only streaming.
// Both paths apply the same frame rules (frame_rules.h); see docs/FORMAT.md §3.4 and §5.

#include "pnb/reader.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <zstd.h>

#include "frame_rules.h"
#include "mapping_guard.h"

namespace pnb {

using detail::FrameRules;

namespace {

bool allZero(std::span<const std::byte> bytes) {
    return std::all_of(bytes.begin(), bytes.end(), [](std::byte b) { return b == std::byte{0}; });
}

bool sameHeader(const ChunkHeader& a, const ChunkHeader& b) {
    return a.tag == b.tag && a.version == b.version && a.flags == b.flags &&
           a.storedSize == b.storedSize && a.rawSize == b.rawSize &&
           a.payloadChecksum == b.payloadChecksum && a.sequence == b.sequence;
}

Status verifyChecksum(const ChunkInfo& c, std::span<const std::byte> stored) {
    if (!c.header.hasChecksum() || checksum(stored) == c.header.payloadChecksum) return {};
    return makeError(FormatError::ChecksumMismatch, c.payloadOffset,
                     "chunk %u '%s': payload checksum mismatch (%llu bytes)", c.header.sequence,
                     c.header.tag.str().c_str(), (unsigned long long)stored.size());
}

// One decompression context per thread, reused: creating one per chunk costs more than
// inflating a small chunk.
ZSTD_DCtx* threadDctx() {
    struct Holder {
        ZSTD_DCtx* ctx = ZSTD_createDCtx();
        ~Holder() { ZSTD_freeDCtx(ctx); }
    };
    thread_local Holder holder;
    ZSTD_DCtx_reset(holder.ctx, ZSTD_reset_session_and_parameters);
    return holder.ctx;
}

Error decompressionError(const ChunkInfo& c, const char* why) {
    return makeError(FormatError::DecompressionFailed, c.payloadOffset,
                     "chunk %u '%s': zstd %s (raw size %llu)", c.header.sequence,
                     c.header.tag.str().c_str(), why, (unsigned long long)c.header.rawSize);
}

// A frame that declares its content size must declare rawSize: checked before allocating, so a
// small damaged chunk cannot make the reader reserve gigabytes first.
Status checkFrameContentSize(const ChunkInfo& c, std::span<const std::byte> stored) {
    unsigned long long declared = ZSTD_getFrameContentSize(stored.data(), stored.size());
    if (declared == ZSTD_CONTENTSIZE_ERROR) return decompressionError(c, "frame header is invalid");
    if (declared != ZSTD_CONTENTSIZE_UNKNOWN && declared != c.header.rawSize)
        return decompressionError(c, "frame declares a different size");
    return {};
}

Status decompressInto(const ChunkInfo& c, std::span<const std::byte> stored,
                      std::span<std::byte> dst) {
    size_t n = ZSTD_decompressDCtx(threadDctx(), dst.data(), dst.size(), stored.data(),
                                   stored.size());
    if (ZSTD_isError(n)) return decompressionError(c, ZSTD_getErrorName(n));
    if (n != c.header.rawSize) return decompressionError(c, "produced the wrong size");
    return {};
}

// Inflates through a small window, checking the output size without allocating it.
Status checkDecompressedSize(const ChunkInfo& c, std::span<const std::byte> stored) {
    if (Status s = checkFrameContentSize(c, stored); !isOk(s)) return s;
    ZSTD_DCtx* ctx = threadDctx();
    thread_local std::vector<std::byte> window(ZSTD_DStreamOutSize());
    ZSTD_inBuffer in{stored.data(), stored.size(), 0};
    uint64_t produced = 0;
    size_t ret = 1;
    while (true) {
        ZSTD_outBuffer out{window.data(), window.size(), 0};
        ret = ZSTD_decompressStream(ctx, &out, &in);
        produced += out.pos;
        if (ZSTD_isError(ret) || produced > c.header.rawSize) break;
        if (ret == 0 && in.pos == in.size) break;           // frame complete, input used
        if (in.pos == in.size && out.pos < out.size) break; // input exhausted mid-frame
    }
    if (ZSTD_isError(ret) || ret != 0 || produced != c.header.rawSize || in.pos != in.size)
        return decompressionError(c, "payload does not inflate to its raw size");
    return {};
}

Status checkRawLimit(const ChunkInfo& c, const ReadOptions& o) {
    if (c.header.rawSize <= o.maxRawChunkBytes) return {};
    return makeError(FormatError::LimitExceeded, c.headerOffset + 16,
                     "chunk %u '%s' inflates to %llu bytes, over the reader's limit of %llu",
                     c.header.sequence, c.header.tag.str().c_str(),
                     (unsigned long long)c.header.rawSize,
                     (unsigned long long)o.maxRawChunkBytes);
}

// A buffer too short for a file header: wrong magic, or a truncated container.
Status checkHeaderPrefix(std::span<const std::byte> bytes) {
    size_t n = std::min<size_t>(bytes.size(), kFileMagic.size());
    // An empty file maps nothing: data() is null, and memcmp(null, p, 0) is undefined behaviour.
    if (n > 0 && std::memcmp(bytes.data(), kFileMagic.data(), n) != 0)
        return makeError(FormatError::BadMagic, 0, "not a Penumbra container");
    return makeError(FormatError::Truncated, bytes.size(),
                     "file of %zu bytes is shorter than the %zu-byte header", bytes.size(),
                     kFileHeaderSize);
}

} // namespace

// [SECTION] Payload

Payload Payload::view(std::span<const std::byte> bytes) {
    Payload p;
    p.mView = bytes;
    return p;
}

Payload Payload::own(std::vector<std::byte> bytes) {
    Payload p;
    p.mOwned = std::move(bytes);
    p.mView = p.mOwned;
    return p;
}

Payload::Payload(Payload&& o) noexcept { *this = std::move(o); }

Payload& Payload::operator=(Payload&& o) noexcept {
    bool owned = !o.mOwned.empty();
    mOwned = std::move(o.mOwned);
    mView = owned ? std::span<const std::byte>(mOwned) : o.mView;
    o.mOwned.clear();
    o.mView = {};
    return *this;
}

// [SECTION] Container: open and index

Result<Container> Container::open(const std::string& path, const ReadOptions& options) {
    // O_NONBLOCK: opening a FIFO must not wait for a writer (it is refused just below).
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0)
        return makeError(FormatError::IoError, 0, "cannot open '%s': %s", path.c_str(),
                         std::strerror(errno));
    struct stat st {};
    if (fstat(fd, &st) != 0) {
        int e = errno;
        ::close(fd);
        return makeError(FormatError::IoError, 0, "cannot stat '%s': %s", path.c_str(),
                         std::strerror(e));
    }
    if (!S_ISREG(st.st_mode)) { // a FIFO or device cannot be mapped; a directory is no file
        ::close(fd);
        return makeError(FormatError::IoError, 0,
                         "'%s' is not a regular file but a FIFO, device or directory, which "
                         "cannot be mapped",
                         path.c_str());
    }
    Container c;
    c.mOptions = options;
    size_t size = size_t(st.st_size);
    if (size > 0) {
        void* m = mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (m == MAP_FAILED) {
            int e = errno;
            ::close(fd);
            return makeError(FormatError::IoError, 0, "cannot map '%s': %s", path.c_str(),
                             std::strerror(e));
        }
        c.mMapping = m;
        c.mMappingSize = size;
        c.mGuardSlot = detail::guardMapping(m, size);
        c.mBytes = {static_cast<const std::byte*>(m), size};
    }
    ::close(fd);
    c.mPath = path;
    Status s = c.guarded(c.index());
    if (!isOk(s)) {
        s.message = path + ": " + s.message;
        return s;
    }
    return c;
}

Result<Container> Container::fromMemory(std::span<const std::byte> bytes,
                                        const ReadOptions& options) {
    Container c;
    c.mOptions = options;
    c.mBytes = bytes;
    Status s = c.index();
    if (!isOk(s)) return s;
    return c;
}

Container::Container(Container&& o) noexcept { *this = std::move(o); }

Container& Container::operator=(Container&& o) noexcept {
    if (this == &o) return *this;
    if (mMapping) {
        detail::unguardMapping(mGuardSlot);
        munmap(mMapping, mMappingSize);
    }
    mOptions = o.mOptions;
    mHeader = o.mHeader;
    mChunks = std::move(o.mChunks);
    mBytes = o.mBytes;
    mMapping = o.mMapping;
    mMappingSize = o.mMappingSize;
    mGuardSlot = o.mGuardSlot;
    mPath = std::move(o.mPath);
    o.mMapping = nullptr;
    o.mMappingSize = 0;
    o.mGuardSlot = detail::kNoGuard;
    o.mBytes = {};
    return *this;
}

Container::~Container() {
    if (mMapping) {
        detail::unguardMapping(mGuardSlot);
        munmap(mMapping, mMappingSize);
    }
}

Status Container::intact() const {
    const uint64_t missing = detail::truncatedAt(mGuardSlot);
    if (missing == UINT64_MAX) return {};
    return makeError(FormatError::IoError, missing,
                     "'%s' shrank while it was being read (truncated or rewritten by another "
                     "program): its bytes from offset %llu on are gone",
                     mPath.c_str(), (unsigned long long)missing);
}

Status Container::guarded(Status s) const {
    if (Status t = intact(); !isOk(t)) return t;
    return s;
}

namespace {

// Index by walking chunk headers from the start; the TOC must then agree with what was walked.
Status indexByScan(std::span<const std::byte> b, std::vector<ChunkInfo>& chunks) {
    const uint64_t size = b.size();
    FrameRules rules(size, /*limitIsEndOfData=*/true);
    chunks.clear();
    while (true) {
        uint64_t off = rules.nextOffset();
        if (off > size || size - off < kChunkHeaderSize)
            return makeError(FormatError::Truncated, std::min(off, size),
                             "file ends inside the chunk header expected at byte %llu "
                             "(no table of contents found)",
                             (unsigned long long)off);
        auto h = decodeChunkHeader(b.subspan(off, kChunkHeaderSize), off);
        if (!h) return h.error();
        if (Status s = rules.accept(*h, off); !isOk(s)) return s;
        ChunkInfo info{*h, off, off + kChunkHeaderSize};
        if (h->tag == tags::kToc) {
            auto payload = b.subspan(info.payloadOffset, h->storedSize);
            if (Status s = verifyChecksum(info, payload); !isOk(s)) return s;
            auto toc = decodeToc(payload, info.payloadOffset);
            if (!toc) return toc.error();
            if (Status s = detail::checkTocMatches(*toc, chunks, off); !isOk(s)) return s;
            uint64_t footerOff = rules.nextOffset();
            if (size - footerOff < kFooterSize)
                return makeError(FormatError::Truncated, size, "file ends inside the footer");
            auto footer = decodeFooter(b.subspan(footerOff, kFooterSize), footerOff);
            if (!footer) return footer.error();
            if (Status s = detail::checkFooter(*footer, off, footerOff); !isOk(s)) return s;
            if (size != footerOff + kFooterSize)
                return makeError(FormatError::TrailingBytes, footerOff + kFooterSize,
                                 "%llu bytes after the footer",
                                 (unsigned long long)(size - footerOff - kFooterSize));
            return {};
        }
        uint64_t end = info.payloadOffset + h->storedSize;
        uint64_t next = rules.nextOffset();
        if (next > size)
            return makeError(FormatError::Truncated, size,
                             "file ends inside the padding after chunk %u", h->sequence);
        if (!allZero(b.subspan(end, next - end)))
            return makeError(FormatError::BadPadding, end, "non-zero padding after chunk %u '%s'",
                             h->sequence, h->tag.str().c_str());
        chunks.push_back(info);
    }
}

// Index from the footer and table of contents without touching the chunks themselves.
Status indexFromToc(std::span<const std::byte> b, std::vector<ChunkInfo>& chunks) {
    const uint64_t size = b.size();
    if (size < kFileHeaderSize + kChunkHeaderSize + 8 + kFooterSize)
        return makeError(FormatError::Truncated, size, "file of %llu bytes is too short",
                         (unsigned long long)size);
    const uint64_t footerOff = size - kFooterSize;
    auto footer = decodeFooter(b.subspan(footerOff, kFooterSize), footerOff);
    if (!footer) return footer.error();
    const uint64_t tocOff = footer->tocOffset;
    if (tocOff < kFileHeaderSize || tocOff % kAlignment != 0 ||
        tocOff > footerOff - kChunkHeaderSize)
        return makeError(FormatError::BadToc, footerOff + 8,
                         "footer points at byte %llu, not a possible chunk position",
                         (unsigned long long)tocOff);
    auto tocHeader = decodeChunkHeader(b.subspan(tocOff, kChunkHeaderSize), tocOff);
    if (!tocHeader) return tocHeader.error();
    if (!(tocHeader->tag == tags::kToc))
        return makeError(FormatError::BadToc, tocOff, "footer points at chunk '%s', not TOCX",
                         tocHeader->tag.str().c_str());
    ChunkInfo tocInfo{*tocHeader, tocOff, tocOff + kChunkHeaderSize};
    if (tocHeader->storedSize != footerOff - tocInfo.payloadOffset)
        return makeError(FormatError::BadChunkSize, tocOff + 8,
                         "table of contents size does not reach the footer");
    auto payload = b.subspan(tocInfo.payloadOffset, tocHeader->storedSize);
    if (Status s = verifyChecksum(tocInfo, payload); !isOk(s)) return s;
    auto toc = decodeToc(payload, tocInfo.payloadOffset);
    if (!toc) return toc.error();

    FrameRules rules(footerOff);
    chunks.clear();
    chunks.reserve(toc->size());
    for (size_t i = 0; i < toc->size(); ++i) {
        const TocEntry& e = (*toc)[i];
        ChunkHeader h{e.tag, e.version, e.flags, e.storedSize, e.rawSize, e.payloadChecksum,
                      uint32_t(i)};
        if (e.tag == tags::kToc)
            return makeError(FormatError::BadToc, e.offset, "TOCX listed inside the TOC");
        // Round-trip through the header codec to apply its field checks to the TOC entry.
        auto checked = decodeChunkHeader(encodeChunkHeader(h), e.offset);
        if (!checked) return checked.error();
        if (Status s = rules.accept(h, e.offset); !isOk(s)) return s;
        chunks.push_back(ChunkInfo{h, e.offset, e.offset + kChunkHeaderSize});
    }
    return rules.accept(*tocHeader, tocOff);
}

} // namespace

Status Container::index() {
    if (mBytes.size() < kFileHeaderSize) return checkHeaderPrefix(mBytes);
    auto h = decodeFileHeader(mBytes.first(kFileHeaderSize));
    if (!h) return h.error();
    mHeader = *h;
    if (!mOptions.useToc) return indexByScan(mBytes, mChunks);
    Status s = indexFromToc(mBytes, mChunks);
    if (isOk(s)) return s;
    // The scan explains a damaged end of file better (truncation point, trailing bytes).
    Status scan = indexByScan(mBytes, mChunks);
    mChunks.clear();
    return isOk(scan) ? s : scan;
}

// [SECTION] Container: lookups and payload access

std::vector<const ChunkInfo*> Container::find(Tag tag) const {
    std::vector<const ChunkInfo*> out;
    for (const ChunkInfo& c : mChunks)
        if (c.header.tag == tag) out.push_back(&c);
    return out;
}

const ChunkInfo* Container::findFirst(Tag tag) const {
    for (const ChunkInfo& c : mChunks)
        if (c.header.tag == tag) return &c;
    return nullptr;
}

// The chunk header in the file must be intact and equal to the index entry (which, on the TOC
// path, came from the table of contents without reading the chunk).
Status Container::checkHeader(const ChunkInfo& c) const {
    // Indexing proved the header and payload lie inside the file.
    auto actual = decodeChunkHeader(mBytes.subspan(c.headerOffset, kChunkHeaderSize),
                                    c.headerOffset);
    if (!actual) return actual.error();
    if (!sameHeader(*actual, c.header))
        return makeError(FormatError::BadToc, c.headerOffset,
                         "chunk %u header disagrees with the table of contents",
                         c.header.sequence);
    return {};
}

Result<std::span<const std::byte>> Container::stored(const ChunkInfo& c) const {
    if (Status s = guarded(checkHeader(c)); !isOk(s)) return s;
    auto bytes = mBytes.subspan(c.payloadOffset, c.header.storedSize);
    if (mOptions.verifyChecksums)
        if (Status s = guarded(verifyChecksum(c, bytes)); !isOk(s)) return s;
    return bytes;
}

Result<Payload> Container::load(const ChunkInfo& c) const {
    auto bytes = stored(c);
    if (!bytes) return bytes.error();
    if (c.header.compression() == Compression::None) return Payload::view(*bytes);
    if (Status s = checkRawLimit(c, mOptions); !isOk(s)) return s;
    if (Status s = checkFrameContentSize(c, *bytes); !isOk(s)) return s;
    std::vector<std::byte> raw(c.header.rawSize);
    if (Status s = guarded(decompressInto(c, *bytes, raw)); !isOk(s)) return s;
    return Payload::own(std::move(raw));
}

Status Container::loadInto(const ChunkInfo& c, std::span<std::byte> dst) const {
    if (dst.size() != c.header.rawSize)
        return makeError(FormatError::BadChunkSize, c.headerOffset,
                         "destination of %zu bytes for chunk %u of raw size %llu", dst.size(),
                         c.header.sequence, (unsigned long long)c.header.rawSize);
    auto bytes = stored(c);
    if (!bytes) return bytes.error();
    if (c.header.compression() == Compression::None) {
        if (!dst.empty()) std::memcpy(dst.data(), bytes->data(), dst.size());
        return intact();
    }
    return guarded(decompressInto(c, *bytes, dst));
}

Status Container::verifyAll() const { return guarded(verifyAllUnguarded()); }

Status Container::verifyAllUnguarded() const {
    for (const ChunkInfo& c : mChunks) {
        if (Status s = checkHeader(c); !isOk(s)) return s;
        auto bytes = mBytes.subspan(c.payloadOffset, c.header.storedSize);
        if (Status s = verifyChecksum(c, bytes); !isOk(s)) return s;
        uint64_t end = c.payloadOffset + c.header.storedSize;
        if (!allZero(mBytes.subspan(end, alignUp(end) - end)))
            return makeError(FormatError::BadPadding, end, "non-zero padding after chunk %u",
                             c.header.sequence);
        if (c.header.compression() == Compression::Zstd)
            if (Status s = checkDecompressedSize(c, bytes); !isOk(s)) return s;
    }
    return {};
}

// [SECTION] Streaming

namespace {

// Reads exactly what is asked from a descriptor, growing buffers only as bytes arrive.
class FdSource {
public:
    explicit FdSource(int fd) : mFd(fd) {}

    // Appends up to n bytes to `out`; returns how many arrived before end of file, or -1 on error.
    int64_t read(std::vector<std::byte>& out, uint64_t n) {
        uint64_t got = 0;
        while (got < n) {
            // Grow by at most 1 MiB beyond what has arrived: memory follows real data.
            size_t step = size_t(std::min<uint64_t>(n - got, 1 << 20));
            size_t old = out.size();
            out.resize(old + step);
            ssize_t r = ::read(mFd, out.data() + old, step);
            if (r < 0 && errno == EINTR) {
                out.resize(old);
                continue;
            }
            if (r <= 0) {
                out.resize(old);
                return r < 0 ? -1 : int64_t(got);
            }
            out.resize(old + size_t(r));
            got += uint64_t(r);
            mPos += uint64_t(r);
        }
        return int64_t(got);
    }

    uint64_t pos() const { return mPos; }

private:
    int mFd;
    uint64_t mPos = 0;
};

Status readExactly(FdSource& src, std::vector<std::byte>& buf, uint64_t n, const char* what) {
    buf.clear();
    uint64_t start = src.pos();
    int64_t got = src.read(buf, n);
    if (got < 0)
        return makeError(FormatError::IoError, start, "read error in %s: %s", what,
                         std::strerror(errno));
    if (uint64_t(got) < n)
        return makeError(FormatError::Truncated, start + uint64_t(got),
                         "stream ends inside %s (%llu of %llu bytes)", what,
                         (unsigned long long)got, (unsigned long long)n);
    return {};
}

} // namespace

Status streamChunks(int fd, const ReadOptions& options, const ChunkCallback& onChunk) {
    FdSource src(fd);
    std::vector<std::byte> buf, raw;
    if (Status s = readExactly(src, buf, kFileHeaderSize, "the file header"); !isOk(s))
        return buf.size() < kFileHeaderSize ? checkHeaderPrefix(buf) : s;
    if (auto h = decodeFileHeader(buf); !h) return h.error();

    FrameRules rules(UINT64_MAX);
    std::vector<ChunkInfo> seen;
    while (true) {
        uint64_t off = src.pos();
        if (Status s = readExactly(src, buf, kChunkHeaderSize, "a chunk header"); !isOk(s))
            return s;
        auto h = decodeChunkHeader(buf, off);
        if (!h) return h.error();
        if (Status s = rules.accept(*h, off); !isOk(s)) return s;
        ChunkInfo info{*h, off, off + kChunkHeaderSize};
        if (h->compression() == Compression::None || h->tag == tags::kToc)
            if (Status s = checkRawLimit(info, options); !isOk(s)) return s;
        if (Status s = readExactly(src, buf, h->storedSize, "a chunk payload"); !isOk(s)) return s;
        if (options.verifyChecksums || h->tag == tags::kToc)
            if (Status s = verifyChecksum(info, buf); !isOk(s)) return s;

        if (h->tag == tags::kToc) {
            auto toc = decodeToc(buf, info.payloadOffset);
            if (!toc) return toc.error();
            if (Status s = detail::checkTocMatches(*toc, seen, off); !isOk(s)) return s;
            uint64_t footerOff = src.pos();
            if (Status s = readExactly(src, buf, kFooterSize, "the footer"); !isOk(s)) return s;
            auto footer = decodeFooter(buf, footerOff);
            if (!footer) return footer.error();
            if (Status s = detail::checkFooter(*footer, off, footerOff); !isOk(s)) return s;
            std::vector<std::byte> extra;
            int64_t more = src.read(extra, 1);
            if (more != 0)
                return makeError(FormatError::TrailingBytes, src.pos() - (more > 0 ? 1 : 0),
                                 "bytes after the footer");
            return {};
        }

        std::span<const std::byte> payload = buf;
        if (h->compression() == Compression::Zstd) {
            if (Status s = checkRawLimit(info, options); !isOk(s)) return s;
            if (Status s = checkFrameContentSize(info, buf); !isOk(s)) return s;
            raw.resize(h->rawSize);
            if (Status s = decompressInto(info, buf, raw); !isOk(s)) return s;
            payload = raw;
        }
        seen.push_back(info);
        if (!onChunk(StreamedChunk{info, payload})) return {};

        uint64_t pad = rules.nextOffset() - src.pos();
        if (Status s = readExactly(src, buf, pad, "chunk padding"); !isOk(s)) return s;
        if (!allZero(buf))
            return makeError(FormatError::BadPadding, src.pos() - pad,
                             "non-zero padding after chunk %u", h->sequence);
    }
}

Status streamChunks(const std::string& path, const ReadOptions& options,
                    const ChunkCallback& onChunk) {
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return makeError(FormatError::IoError, 0, "cannot open '%s': %s", path.c_str(),
                         std::strerror(errno));
    Status s = streamChunks(fd, options, onChunk);
    ::close(fd);
    return s;
}

Result<Payload> readChunkAt(int fd, const ChunkInfo& info, const ReadOptions& options) {
    auto preadAll = [&](std::vector<std::byte>& dst, uint64_t n, uint64_t offset) -> Status {
        dst.resize(n);
        for (uint64_t got = 0; got < n;) {
            ssize_t r = ::pread(fd, dst.data() + got, n - got, off_t(offset + got));
            if (r < 0 && errno == EINTR) continue;
            if (r < 0)
                return makeError(FormatError::IoError, offset + got, "read error in chunk %u: %s",
                                 info.header.sequence, std::strerror(errno));
            if (r == 0)
                return makeError(FormatError::Truncated, offset + got,
                                 "the file ends inside chunk %u (it changed since it was read)",
                                 info.header.sequence);
            got += uint64_t(r);
        }
        return {};
    };
    std::vector<std::byte> bytes;
    if (Status s = preadAll(bytes, kChunkHeaderSize, info.headerOffset); !isOk(s)) return s;
    auto header = decodeChunkHeader(bytes, info.headerOffset);
    if (!header) return header.error();
    if (!sameHeader(*header, info.header))
        return makeError(FormatError::BadToc, info.headerOffset,
                         "chunk %u: the header there is not the one read before (the file changed)",
                         info.header.sequence);
    if (Status s = preadAll(bytes, info.header.storedSize, info.payloadOffset); !isOk(s)) return s;
    if (options.verifyChecksums)
        if (Status s = verifyChecksum(info, bytes); !isOk(s)) return s;
    if (info.header.compression() == Compression::None) return Payload::own(std::move(bytes));
    if (Status s = checkRawLimit(info, options); !isOk(s)) return s;
    if (Status s = checkFrameContentSize(info, bytes); !isOk(s)) return s;
    std::vector<std::byte> raw(info.header.rawSize);
    if (Status s = decompressInto(info, bytes, raw); !isOk(s)) return s;
    return Payload::own(std::move(raw));
}

} // namespace pnb
