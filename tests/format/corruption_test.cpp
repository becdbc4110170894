// Adversarial tests of the container (docs/STYLE.md §9.3): every single-byte change, every
// truncation, trailing bytes, text-mode and endianness damage, versions, unknown tags, sizes
// that overflow, raw-size limits, and streaming vs mapped parity.
//
// The per-byte loops run the real read paths on a ~32 KB sample. Failures are collected and the
// first few reported, so one broken rule does not print 60,000 lines. Under ASan/UBSan (CI) the
// loops double as a memory-safety sweep: every decoded blob and string is read back.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

#include "format_test_util.h"
#include "pnb/chunks.h"

namespace {

using namespace pnb;
using namespace pnb::test;

// [SECTION] helpers

// Which structure of a valid file a byte belongs to, so a failure can say what was missed.
enum class Region : uint8_t {
    FileHeader,
    ChunkHeader,
    Payload,
    Padding,
    TocHeader,
    TocPayload,
    Footer,
    Unassigned
};

const char* regionName(Region r) {
    switch (r) {
    case Region::FileHeader: return "file header";
    case Region::ChunkHeader: return "chunk header";
    case Region::Payload: return "payload";
    case Region::Padding: return "padding";
    case Region::TocHeader: return "TOC header";
    case Region::TocPayload: return "TOC payload";
    case Region::Footer: return "footer";
    case Region::Unassigned: break;
    }
    return "unassigned";
}

// What the per-byte loops need to know about one byte of the valid file.
struct ByteInfo {
    Region region = Region::Unassigned;
    int32_t chunk = -1;      // index in Container::chunks() for chunk headers/payloads/padding
    bool compressed = false; // in a zstd chunk
    bool edge = false;       // first or last byte of its region (where off-by-one bugs live)
};

// Maps every byte of a valid file to its structure. Fails the test (via EXPECT) if the regions
// do not tile the file: a byte in two regions, or in none. The tiling is what lets the per-byte
// tests claim that *every* byte is covered.
std::vector<ByteInfo> mapBytes(std::span<const std::byte> bytes) {
    std::vector<ByteInfo> map(bytes.size());
    auto mark = [&](uint64_t begin, uint64_t end, Region r, int32_t chunk, bool compressed) {
        for (uint64_t i = begin; i < end; ++i) {
            EXPECT_EQ(map[i].region, Region::Unassigned) << "byte " << i << " is in two regions";
            map[i] = ByteInfo{r, chunk, compressed, i == begin || i + 1 == end};
        }
    };
    auto c = Container::fromMemory(bytes);
    EXPECT_TRUE(c.ok());
    if (!c.ok()) return map;
    mark(0, kFileHeaderSize, Region::FileHeader, -1, false);
    for (const ChunkInfo& ci : c->chunks()) {
        uint64_t end = ci.payloadOffset + ci.header.storedSize;
        int32_t index = int32_t(ci.header.sequence);
        bool zstd = ci.header.compression() == Compression::Zstd;
        mark(ci.headerOffset, ci.payloadOffset, Region::ChunkHeader, index, zstd);
        mark(ci.payloadOffset, end, Region::Payload, index, zstd);
        mark(end, alignUp(end), Region::Padding, index, zstd);
    }
    uint64_t footerOff = bytes.size() - kFooterSize;
    auto footer = decodeFooter(bytes.subspan(footerOff), footerOff);
    EXPECT_TRUE(footer.ok());
    if (!footer.ok()) return map;
    mark(footer->tocOffset, footer->tocOffset + kChunkHeaderSize, Region::TocHeader, -1, false);
    mark(footer->tocOffset + kChunkHeaderSize, footerOff, Region::TocPayload, -1, false);
    mark(footerOff, bytes.size(), Region::Footer, -1, false);
    return map;
}

// Reads every decoded byte the scene points at, so ASan sees any view that escapes its payload.
uint64_t touchScene(const Scene& s) {
    uint64_t sum = 0;
    auto touch = [&sum](std::span<const std::byte> b) {
        for (std::byte x : b) sum += uint8_t(x);
    };
    for (std::string_view str : s.strings.strings)
        touch(std::as_bytes(std::span<const char>(str.data(), str.size())));
    for (const ShaderSource& sh : s.shaders) touch(sh.source);
    for (const Mesh& m : s.meshes) {
        for (const VertexStream& vs : m.streams) touch(vs.data);
        touch(m.indices);
        sum += m.submeshes.size();
    }
    for (const TextureMip& mip : s.textureMips) touch(mip.data);
    for (const Payload& p : s.payloads) touch(p.bytes());
    // StringRefs were range-checked by validateScene; resolving them must stay in bounds.
    sum += s.str(s.info.name).size() + s.str(s.info.generator).size();
    for (const Node& n : s.nodes.nodes) sum += s.str(n.name).size();
    return sum;
}

// The outcome of the whole read path on one buffer: open, verifyAll, readScene.
struct ReadOutcome {
    Error open, verify, scene;
    bool opened() const { return open.code == FormatError::None; }
    bool detected() const {
        return !opened() || verify.code != FormatError::None || scene.code != FormatError::None;
    }
};

// Keeps the touched sums alive (so the reads are not optimised away); atomic because the
// per-byte loops run on several threads.
std::atomic<uint64_t> gSink{0};

ReadOutcome fullRead(std::span<const std::byte> bytes, const ReadOptions& options = {},
                     bool withScene = true) {
    ReadOutcome r;
    auto c = Container::fromMemory(bytes, options);
    if (!c) {
        r.open = c.error();
        return r;
    }
    r.verify = c->verifyAll();
    if (!withScene) return r;
    auto scene = readScene(*c);
    if (!scene)
        r.scene = scene.error();
    else
        gSink.fetch_add(touchScene(*scene), std::memory_order_relaxed);
    return r;
}

// Streams and touches every delivered payload.
ChunkCallback touchingCallback() {
    return [](const StreamedChunk& c) {
        uint64_t sum = 0;
        for (std::byte b : c.payload) sum += uint8_t(b);
        gSink.fetch_add(sum, std::memory_order_relaxed);
        return true;
    };
}

// Collects per-case failure descriptions from any thread; reports a count and the first few.
class Failures {
public:
    void add(const std::string& what) {
        std::lock_guard<std::mutex> lock(mMutex);
        if (mList.size() < 20) mList.push_back(what);
        ++mCount;
    }
    void report(const char* test) const {
        if (mCount == 0) return;
        std::ostringstream os;
        os << test << ": " << mCount << " failures; first ones:\n";
        for (const std::string& s : mList) os << "  " << s << "\n";
        ADD_FAILURE() << os.str();
    }

private:
    std::mutex mMutex;
    std::vector<std::string> mList;
    size_t mCount = 0;
};

// Calls fn(copy, offset) for every offset of `bytes`, spread over a few threads (Container and
// readScene are safe to run concurrently); each thread mutates and restores its own copy.
// Offsets are interleaved because the costly ones (chunk headers) cluster at the start.
template <class Fn> void forEachOffset(const std::vector<std::byte>& bytes, Fn fn) {
    const unsigned n = std::clamp(std::thread::hardware_concurrency(), 1u, 4u);
    std::vector<std::thread> threads;
    for (unsigned t = 0; t < n; ++t)
        threads.emplace_back([&bytes, &fn, t, n] {
            std::vector<std::byte> copy = bytes;
            for (size_t off = t; off < copy.size(); off += n) fn(copy, off);
        });
    for (std::thread& th : threads) th.join();
}

struct Mutation {
    const char* name;
    std::byte (*apply)(std::byte);
};
// XOR 0xFF changes every bit; +1 changes as few as one bit (the low one), which catches checks
// that only look at high bits or compare against a few magic values.
constexpr Mutation kMutations[] = {
    {"xor-ff", [](std::byte b) { return b ^ std::byte{0xFF}; }},
    {"plus-1", [](std::byte b) { return std::byte(uint8_t(uint8_t(b) + 1)); }},
};

std::string at(uint64_t offset, const ByteInfo& b, const char* mutation) {
    std::string where = regionName(b.region);
    if (b.chunk >= 0) where += " of chunk " + std::to_string(b.chunk);
    return "byte " + std::to_string(offset) + " (" + where + ", " + mutation + ")";
}

class Corruption : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        sSample = new std::vector<std::byte>(sampleBytes());
        sUnchecked = new std::vector<std::byte>(sampleBytes(WriteOptions{.checksums = false}));
    }
    static void TearDownTestSuite() {
        delete sSample;
        delete sUnchecked;
        sSample = sUnchecked = nullptr;
    }
    static std::vector<std::byte>* sSample;
    static std::vector<std::byte>* sUnchecked;
};
std::vector<std::byte>* Corruption::sSample = nullptr;
std::vector<std::byte>* Corruption::sUnchecked = nullptr;

std::vector<std::byte> withFileHeader(std::vector<std::byte> bytes,
                                      const std::array<std::byte, kFileHeaderSize>& header) {
    std::copy(header.begin(), header.end(), bytes.begin());
    return bytes;
}

// Checks one expected error code through all three read modes (TOC index, header scan, pipe).
void expectRejectedEverywhere(std::span<const std::byte> bytes, FormatError expected,
                              const std::string& what) {
    for (bool useToc : {true, false}) {
        auto c = Container::fromMemory(bytes, ReadOptions{.useToc = useToc});
        ASSERT_FALSE(c.ok()) << what << " (useToc " << useToc << ") was accepted";
        EXPECT_EQ(c.error().code, expected)
            << what << " (useToc " << useToc << "): " << c.error().describe();
    }
    Status s = streamThroughPipe(bytes, {}, touchingCallback());
    EXPECT_EQ(s.code, expected) << what << " (stream): " << s.describe();
}

// [SECTION] 1a. every single-byte change is detected with checksums on

TEST_F(Corruption, SampleRegionsTileTheFile) {
    const auto& bytes = *sSample;
    ASSERT_GT(bytes.size(), 16384u) << "the sample should exercise many chunks";
    std::vector<ByteInfo> map = mapBytes(bytes);
    std::map<Region, size_t> counts;
    size_t compressedPayload = 0;
    for (const ByteInfo& b : map) {
        ++counts[b.region];
        compressedPayload += b.region == Region::Payload && b.compressed;
    }
    EXPECT_EQ(counts[Region::Unassigned], 0u) << "some bytes belong to no structure";
    for (Region r : {Region::FileHeader, Region::ChunkHeader, Region::Payload, Region::Padding,
                     Region::TocHeader, Region::TocPayload, Region::Footer})
        EXPECT_GT(counts[r], 0u) << regionName(r) << " not exercised by the sample";
    // Without a compressed chunk the zstd paths would go untested by the byte loops.
    EXPECT_GT(compressedPayload, 0u);
}

// Cost note: verifyAll and readScene each inflate every zstd chunk with a fresh zstd context
// (~1 ms per verifyAll under ASan), too slow for 63,000 cases. So every byte outside payloads,
// the first and last byte of every payload, and every 13th payload byte get the whole read path
// (open, verifyAll, readScene, and the header-scan open + verifyAll); the remaining payload
// bytes get exactly the step of that path that reads them: load() of their chunk (what
// readScene does per chunk), through both indexes. Every offset is covered by something.
bool wholePath(const ByteInfo& b, size_t off) {
    return b.region != Region::Payload || b.edge || off % 13 == 0;
}

TEST_F(Corruption, EverySingleByteChangeIsDetected) {
    ASSERT_FALSE(fullRead(*sSample).detected()) << "the unmodified sample must read cleanly";
    const std::vector<ByteInfo> map = mapBytes(*sSample);
    Failures fail;
    std::atomic<size_t> whole{0}, loadOnly{0};
    forEachOffset(*sSample, [&](std::vector<std::byte>& bytes, size_t off) {
        const ByteInfo& b = map[off];
        const std::byte original = bytes[off];
        for (const Mutation& m : kMutations) {
            bytes[off] = m.apply(original);
            if (wholePath(b, off)) {
                ++whole;
                // Default options: TOC index, checksums verified on load.
                ReadOutcome r = fullRead(bytes);
                if (!r.detected()) fail.add(at(off, b, m.name) + ": undetected");
                if (r.opened() && r.verify.code == FormatError::None)
                    fail.add(at(off, b, m.name) + ": verifyAll passed");
                // readScene alone (no verifyAll) must notice any change to a byte it consumes;
                // only padding is left to verifyAll, which is what checks it.
                if (r.opened() && b.region != Region::Padding &&
                    r.scene.code == FormatError::None)
                    fail.add(at(off, b, m.name) + ": readScene passed");
                // The header-scan index must reject it too, at open or in verifyAll.
                ReadOutcome scan = fullRead(bytes, ReadOptions{.useToc = false}, false);
                if (!scan.detected()) fail.add(at(off, b, m.name) + ": scan undetected");
            } else {
                ++loadOnly;
                for (bool useToc : {true, false}) {
                    auto c = Container::fromMemory(bytes, ReadOptions{.useToc = useToc});
                    if (c.ok() && c->load(c->chunks()[size_t(b.chunk)]).ok())
                        fail.add(at(off, b, m.name) + ": load passed, useToc " +
                                 std::to_string(useToc));
                }
            }
        }
        bytes[off] = original;
    });
    fail.report("single-byte changes, checksums on");
    EXPECT_EQ(whole + loadOnly, sSample->size() * std::size(kMutations));
    std::cout << "[ checksums on ] " << whole << " cases through the whole read path, "
              << loadOnly << " through load() of their chunk\n";
}

TEST_F(Corruption, EverySeventhByteChangeIsDetectedWhenStreaming) {
    const auto& bytes = *sSample;
    const std::vector<ByteInfo> map = mapBytes(bytes);
    MemFd file(bytes);
    ASSERT_TRUE(isOk(file.stream({}, touchingCallback()))) << "the sample must stream cleanly";
    Failures fail;
    size_t tried = 0;
    // Every 7th offset: 7 is coprime with the 64-byte alignment, so the subset walks through
    // every position within headers, payload starts and padding across the file.
    for (size_t off = 0; off < bytes.size(); off += 7) {
        for (const Mutation& m : kMutations) {
            std::byte changed = m.apply(bytes[off]);
            file.writeAll(off, {&changed, 1});
            Status s = file.stream({}, touchingCallback());
            if (isOk(s)) fail.add(at(off, map[off], m.name) + ": stream undetected");
            ++tried;
        }
        file.writeAll(off, {&bytes[off], 1});
    }
    EXPECT_GE(tried, 2 * bytes.size() / 7); // every 7th offset, each mutation
    fail.report("single-byte changes, streaming");
}

// [SECTION] 1b. without payload checksums: an error or a clean read, never undefined behaviour

TEST_F(Corruption, UncheckedFileSingleByteChangesAreMemorySafe) {
    ASSERT_FALSE(fullRead(*sUnchecked).detected()) << "the unmodified sample must read cleanly";
    {
        auto c = Container::fromMemory(*sUnchecked);
        ASSERT_TRUE(c.ok());
        for (const ChunkInfo& ci : c->chunks())
            ASSERT_FALSE(ci.header.hasChecksum()) << "sample should have no payload checksums";
    }
    const std::vector<ByteInfo> map = mapBytes(*sUnchecked);
    size_t payloadBytes = 0;
    for (const ByteInfo& b : map) payloadBytes += b.region == Region::Payload;
    std::mutex countMutex;
    std::map<Region, size_t> undetected;
    Failures fail;
    forEachOffset(*sUnchecked, [&](std::vector<std::byte>& bytes, size_t off) {
        const ByteInfo& b = map[off];
        const std::byte original = bytes[off];
        for (const Mutation& m : kMutations) {
            bytes[off] = m.apply(original);
            // Every case decodes the whole scene and reads every view it produced: that is
            // where ASan/UBSan look. verifyAll has nothing to check in an uncompressed payload
            // without a checksum (it checks headers, padding and zstd streams), so for those
            // bytes it runs only on the same sample as above, to keep the loop affordable.
            bool verifySees = b.region != Region::Payload || b.compressed || wholePath(b, off);
            ReadOutcome r;
            auto c = Container::fromMemory(bytes);
            if (!c) {
                r.open = c.error();
            } else {
                if (verifySees) r.verify = c->verifyAll();
                auto scene = readScene(*c);
                if (!scene)
                    r.scene = scene.error();
                else
                    gSink.fetch_add(touchScene(*scene), std::memory_order_relaxed);
            }
            if (!r.detected()) {
                std::lock_guard<std::mutex> lock(countMutex);
                ++undetected[b.region];
                // Headers, TOC and footer keep their own checksums and padding is checked, so
                // only payload bytes may change unnoticed.
                if (b.region != Region::Payload) fail.add(at(off, b, m.name));
            }
        }
        bytes[off] = original;
    });
    fail.report("undetected changes outside payloads, checksums off");
    const size_t tried = payloadBytes * std::size(kMutations);
    std::cout << "[ checksums off ] " << undetected[Region::Payload] << " of " << tried
              << " payload byte changes read without error (expected: no payload checksums)\n";
    RecordProperty("undetected_payload_changes", int(undetected[Region::Payload]));
    RecordProperty("payload_changes_tried", int(tried));
}

TEST_F(Corruption, UncheckedFileStreamingIsMemorySafe) {
    const auto& bytes = *sUnchecked;
    const std::vector<ByteInfo> map = mapBytes(bytes);
    MemFd file(bytes);
    ASSERT_TRUE(isOk(file.stream({}, touchingCallback())));
    Failures fail;
    for (size_t off = 0; off < bytes.size(); off += 7) {
        for (const Mutation& m : kMutations) {
            std::byte changed = m.apply(bytes[off]);
            file.writeAll(off, {&changed, 1});
            Status s = file.stream({}, touchingCallback());
            if (isOk(s) && map[off].region != Region::Payload)
                fail.add(at(off, map[off], m.name));
        }
        file.writeAll(off, {&bytes[off], 1});
    }
    fail.report("undetected streamed changes outside payloads, checksums off");
}

// [SECTION] 1c. every truncation is rejected as Truncated

TEST_F(Corruption, EveryTruncationIsRejectedAsTruncated) {
    const auto& bytes = *sSample;
    const std::span<const std::byte> all(bytes);
    Failures fail;
    for (size_t len = 0; len < bytes.size(); ++len) {
        for (bool useToc : {true, false}) {
            auto c = Container::fromMemory(all.first(len), ReadOptions{.useToc = useToc});
            if (c.ok()) {
                fail.add("length " + std::to_string(len) + " accepted (useToc " +
                         std::to_string(useToc) + ")");
            } else if (c.error().code != FormatError::Truncated || c.error().offset > len) {
                fail.add("length " + std::to_string(len) + " (useToc " + std::to_string(useToc) +
                         "): " + c.error().describe());
            }
        }
    }
    fail.report("truncations, mapped");
}

TEST_F(Corruption, EveryTruncationIsRejectedAsTruncatedWhenStreaming) {
    const auto& bytes = *sSample;
    MemFd file(bytes);
    Failures fail;
    // Shrinking the same memfd keeps each shorter prefix without copying the file again.
    for (size_t len = bytes.size(); len-- > 0;) {
        file.truncate(len);
        Status s = file.stream({}, touchingCallback());
        if (s.code != FormatError::Truncated || s.offset > len)
            fail.add("length " + std::to_string(len) + ": " + s.describe());
    }
    fail.report("truncations, streaming");
}

TEST_F(Corruption, EmptyInputIsTruncated) {
    // A default span has a null data pointer: the reader must not hand it to memcmp.
    auto c = Container::fromMemory(std::span<const std::byte>{});
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().code, FormatError::Truncated) << c.error().describe();
    EXPECT_EQ(streamThroughPipe({}, {}, touchingCallback()).code, FormatError::Truncated);
}

// [SECTION] 1d. trailing bytes, bad magic, text-mode damage, versions, endianness

TEST_F(Corruption, TrailingBytesAreRejected) {
    const auto& bytes = *sSample;
    const std::vector<std::byte> footer(bytes.end() - kFooterSize, bytes.end());
    struct Case {
        const char* name;
        std::vector<std::byte> extra;
    };
    // A copy of the footer and a whole second file are the nasty ones: the last 32 bytes are
    // then a valid footer, which a footer-first reader could trust.
    const Case cases[] = {
        {"one zero byte", std::vector<std::byte>(1)},
        {"63 bytes", std::vector<std::byte>(63, std::byte{0x5A})},
        {"a copy of the footer", footer},
        {"a second copy of the file", bytes},
    };
    for (const Case& c : cases) {
        std::vector<std::byte> longer = bytes;
        longer.insert(longer.end(), c.extra.begin(), c.extra.end());
        expectRejectedEverywhere(longer, FormatError::TrailingBytes, c.name);
        auto err = Container::fromMemory(longer);
        if (!err.ok()) {
            EXPECT_EQ(err.error().offset, bytes.size())
                << c.name << ": the error should point at the first extra byte";
        }
    }
}

TEST_F(Corruption, BadMagicIsRejected) {
    const auto& bytes = *sSample;
    std::vector<std::byte> elf = bytes;
    const uint8_t elfMagic[8] = {0x7F, 'E', 'L', 'F', 2, 1, 1, 0};
    std::memcpy(elf.data(), elfMagic, 8);
    expectRejectedEverywhere(elf, FormatError::BadMagic, "ELF magic");

    // Shorter than a file header, and not a container: BadMagic rather than Truncated, because
    // the bytes that are there already rule it out.
    const std::string text = "hello, world\n";
    expectRejectedEverywhere(std::as_bytes(std::span(text)), FormatError::BadMagic,
                             "short text file");

    // A 7-bit transfer clears the high bit of every byte.
    std::vector<std::byte> sevenBit = bytes;
    for (std::byte& b : sevenBit) b &= std::byte{0x7F};
    expectRejectedEverywhere(sevenBit, FormatError::BadMagic, "7-bit transfer");
}

TEST_F(Corruption, TextModeConversionsAreRejectedAsBadMagic) {
    const auto& bytes = *sSample;
    std::vector<std::byte> crlf; // LF -> CRLF, as a Windows text-mode copy does
    for (std::byte b : bytes) {
        if (b == std::byte{'\n'}) crlf.push_back(std::byte{'\r'});
        crlf.push_back(b);
    }
    ASSERT_GT(crlf.size(), bytes.size());
    expectRejectedEverywhere(crlf, FormatError::BadMagic, "LF->CRLF");
    auto c = Container::fromMemory(crlf);
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("text mode"), std::string::npos)
        << "the message should name the cause: " << c.error().message;

    std::vector<std::byte> lf; // CRLF -> LF, the reverse conversion
    for (size_t i = 0; i < bytes.size(); ++i) {
        bool crBeforeLf = bytes[i] == std::byte{'\r'} && i + 1 < bytes.size() &&
                          bytes[i + 1] == std::byte{'\n'};
        if (!crBeforeLf) lf.push_back(bytes[i]);
    }
    ASSERT_LT(lf.size(), bytes.size());
    expectRejectedEverywhere(lf, FormatError::BadMagic, "CRLF->LF");
}

TEST_F(Corruption, NewerMajorVersionIsRejectedWithAnUpdateHint) {
    auto bytes = withFileHeader(*sSample, encodeFileHeader(FileHeader{.versionMajor = 2}));
    expectRejectedEverywhere(bytes, FormatError::UnsupportedVersion, "version 2.0");
    auto c = Container::fromMemory(bytes);
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("update"), std::string::npos) << c.error().message;

    auto older = withFileHeader(*sSample, encodeFileHeader(FileHeader{.versionMajor = 0}));
    expectRejectedEverywhere(older, FormatError::UnsupportedVersion, "version 0.0");
}

TEST_F(Corruption, NewerMinorVersionIsAccepted) {
    // Minor versions only add things a 1.0 reader can skip (unknown chunk tags).
    auto bytes = withFileHeader(*sSample,
                                encodeFileHeader(FileHeader{.versionMajor = 1, .versionMinor = 9}));
    auto c = Container::fromMemory(bytes);
    ASSERT_TRUE(c.ok()) << c.error().describe();
    EXPECT_EQ(c->header().versionMinor, 9);
    EXPECT_TRUE(isOk(c->verifyAll()));
    EXPECT_TRUE(readScene(*c).ok());
    EXPECT_TRUE(isOk(streamThroughPipe(bytes, {}, touchingCallback())));
}

TEST_F(Corruption, BigEndianMarkerIsRejected) {
    std::vector<std::byte> bytes = *sSample;
    // What a big-endian writer storing 0x01020304 natively would produce; re-checksummed so
    // only the marker is wrong.
    const uint8_t bigEndian[4] = {0x01, 0x02, 0x03, 0x04};
    std::memcpy(&bytes[12], bigEndian, 4);
    uint64_t sum = checksum(std::span(bytes).first(56));
    for (int i = 0; i < 8; ++i) bytes[56 + i] = std::byte(uint8_t(sum >> (8 * i)));
    expectRejectedEverywhere(bytes, FormatError::BadEndianness, "big-endian marker");
}

// [SECTION] 1e. unknown tags are skipped; newer chunk versions are refused

// Writes the box room in the order of FORMAT.md 4.1 with `extra` called right after INFO, and
// (if set) the first material written with `materialVersion`.
template <class Extra>
std::vector<std::byte> writeBoxRoomWith(const Scene& s, Extra extra, uint16_t materialVersion = 1) {
    std::vector<std::byte> bytes;
    Writer w = Writer::toMemory(&bytes);
    auto ok = [](const Status& st) { EXPECT_TRUE(isOk(st)) << st.describe(); };
    ok(writeChunk(w, s.strings));
    ok(writeChunk(w, s.info));
    extra(w);
    ok(writeChunk(w, s.settings));
    for (const auto& x : s.shaders) ok(writeChunk(w, x));
    for (const auto& x : s.programs) ok(writeChunk(w, x));
    for (const auto& x : s.textures) ok(writeChunk(w, x));
    for (size_t i = 0; i < s.materials.size(); ++i) {
        if (i == 0 && materialVersion != 1)
            ok(w.addChunk(tags::kMaterial, materialVersion, encodeChunk(s.materials[0])));
        else
            ok(writeChunk(w, s.materials[i]));
    }
    for (const auto& x : s.meshes) ok(writeChunk(w, x));
    ok(writeChunk(w, s.lights));
    ok(writeChunk(w, s.cameras));
    ok(writeChunk(w, s.nodes));
    for (const auto& x : s.cameraPaths) ok(writeChunk(w, x));
    for (const auto& x : s.textureMips) ok(writeChunk(w, x));
    ok(w.commit());
    return bytes;
}

TEST_F(Corruption, UnknownChunkTagIsSkipped) {
    SceneBuilder b;
    assets::buildBoxRoom(b);
    const Tag unknown{{'Z', 'Z', 'Z', 'Z'}};
    std::vector<std::byte> extraPayload(300);
    for (size_t i = 0; i < extraPayload.size(); ++i) extraPayload[i] = std::byte(i * 7 + 1);
    auto bytes = writeBoxRoomWith(b.scene, [&](Writer& w) {
        EXPECT_TRUE(isOk(w.addChunk(unknown, 1, extraPayload)));
    });

    auto c = Container::fromMemory(bytes);
    ASSERT_TRUE(c.ok()) << c.error().describe();
    ASSERT_EQ(c->find(unknown).size(), 1u);
    EXPECT_EQ(c->find(unknown)[0]->header.sequence, 2u) << "between INFO and RSET";
    EXPECT_TRUE(isOk(c->verifyAll()));
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    EXPECT_EQ(scene->unknownChunks, 1u);
    // Skipping must not disturb what follows: the chunks after it decode as written.
    EXPECT_EQ(encodeChunk(scene->settings), encodeChunk(b.scene.settings));
    ASSERT_EQ(scene->meshes.size(), b.scene.meshes.size());
    for (size_t i = 0; i < scene->meshes.size(); ++i)
        EXPECT_EQ(encodeChunk(scene->meshes[i]), encodeChunk(b.scene.meshes[i]));
    EXPECT_EQ(encodeChunk(scene->nodes), encodeChunk(b.scene.nodes));

    // The stream hands the unknown chunk to the caller, intact, in its place.
    std::vector<SeenChunk> seen;
    ASSERT_TRUE(isOk(streamThroughPipe(bytes, {}, collectInto(seen))));
    ASSERT_GT(seen.size(), 3u);
    EXPECT_TRUE(seen[2].header.tag == unknown);
    EXPECT_EQ(seen[2].raw, extraPayload);
}

// FORMAT.md 3.5: a newer chunk version is read by the fields this reader knows (the
// synthetic next-version files of format_evolution_test.cpp cover appended fields and the
// critical bit).
TEST_F(Corruption, NewerChunkVersionIsReadByItsKnownFields) {
    SceneBuilder b;
    assets::buildBoxRoom(b);
    auto bytes = writeBoxRoomWith(b.scene, [](Writer&) {}, /*materialVersion=*/ChunkTraits<Material>::version + 1);
    auto c = Container::fromMemory(bytes);
    ASSERT_TRUE(c.ok()) << c.error().describe();
    EXPECT_TRUE(isOk(c->verifyAll()));
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    EXPECT_EQ(scene->newerChunks, 1u); // the first material
    EXPECT_TRUE(isOk(streamThroughPipe(bytes, {}, touchingCallback())));

    // Version 0 was never written by anyone: refused the same way.
    auto zero = writeBoxRoomWith(b.scene, [](Writer&) {}, /*materialVersion=*/0);
    auto c0 = Container::fromMemory(zero);
    ASSERT_TRUE(c0.ok());
    auto scene0 = readScene(*c0);
    ASSERT_FALSE(scene0.ok());
    EXPECT_EQ(scene0.error().code, FormatError::UnsupportedChunkVersion);
}

// [SECTION] 1f. overflowing chunk sizes, raw-size limits

std::vector<std::byte> smallStringTable() {
    StringTable t;
    t.strings = {"a", "bc"};
    return encodeChunk(t);
}

TEST_F(Corruption, OverflowingChunkSizesAreRejected) {
    const uint64_t sizes[] = {
        UINT64_MAX - 10,
        UINT64_MAX,
        uint64_t(1) << 63,
        (uint64_t(1) << 62) + 1, // no wrap-around, but beyond any real file
    };
    for (uint64_t storedSize : sizes) {
        for (bool compressed : {false, true}) {
            FileBuilder fb;
            fb.add(tags::kStrings, 1, smallStringTable());
            ChunkHeader h;
            h.tag = tags::kMesh;
            h.version = 1;
            h.flags = uint16_t(compressed ? Compression::Zstd : Compression::None);
            h.storedSize = storedSize;
            h.rawSize = compressed ? 100 : storedSize;
            // A properly checksummed header: only the size is absurd.
            uint64_t off = fb.addRaw(h, {});
            auto bytes = fb.finish();
            std::string what = "storedSize " + std::to_string(storedSize) +
                               (compressed ? " zstd" : "") + " at byte " + std::to_string(off);
            expectRejectedEverywhere(bytes, FormatError::BadChunkSize, what);
        }
    }
    // The sum payloadOffset + storedSize wraps to exactly zero: the classic overflow.
    FileBuilder fb;
    fb.add(tags::kStrings, 1, smallStringTable());
    const uint64_t headerOff = fb.bytes.size();
    ChunkHeader h;
    h.tag = tags::kMesh;
    h.storedSize = h.rawSize = uint64_t(0) - (headerOff + kChunkHeaderSize);
    fb.addRaw(h, {});
    expectRejectedEverywhere(fb.finish(), FormatError::BadChunkSize, "wrapping size");
}

TEST_F(Corruption, RawSizeOverTheLimitIsRefusedOnLoad) {
    const auto& bytes = *sSample;
    auto c = Container::fromMemory(bytes);
    ASSERT_TRUE(c.ok());
    const ChunkInfo* zstd = nullptr;
    for (const ChunkInfo& ci : c->chunks())
        if (ci.header.compression() == Compression::Zstd) zstd = &ci;
    ASSERT_NE(zstd, nullptr);
    const uint64_t raw = zstd->header.rawSize;

    // Exactly at the limit loads; one byte over is refused before anything is allocated.
    auto atLimit = Container::fromMemory(bytes, ReadOptions{.maxRawChunkBytes = raw});
    ASSERT_TRUE(atLimit.ok());
    EXPECT_TRUE(atLimit->load(atLimit->chunks()[zstd->header.sequence]).ok());
    auto over = Container::fromMemory(bytes, ReadOptions{.maxRawChunkBytes = raw - 1});
    ASSERT_TRUE(over.ok()) << "the limit applies on load, not on open";
    auto loaded = over->load(over->chunks()[zstd->header.sequence]);
    ASSERT_FALSE(loaded.ok());
    EXPECT_EQ(loaded.error().code, FormatError::LimitExceeded) << loaded.error().describe();
    EXPECT_EQ(readScene(*over).error().code, FormatError::LimitExceeded);
    EXPECT_EQ(streamThroughPipe(bytes, ReadOptions{.maxRawChunkBytes = raw - 1},
                                touchingCallback())
                  .code,
              FormatError::LimitExceeded);
}

TEST_F(Corruption, HugeDeclaredRawSizeIsRefusedWithoutAllocating) {
    // A real zstd payload whose header claims it inflates to 1 TiB (a decompression bomb as far
    // as the header is concerned). Default limit: LimitExceeded; verifyAll inflates through a
    // window and reports the mismatch without allocating the declared size.
    auto sample = Container::fromMemory(*sSample);
    ASSERT_TRUE(sample.ok());
    const ChunkInfo& strs = sample->chunks()[0];
    ASSERT_TRUE(strs.header.tag == tags::kStrings);
    ASSERT_EQ(strs.header.compression(), Compression::Zstd);
    auto stored = sample->stored(strs);
    ASSERT_TRUE(stored.ok());

    for (uint64_t rawSize : {uint64_t(1) << 40, strs.header.rawSize + 1, strs.header.rawSize - 1}) {
        FileBuilder fb;
        ChunkHeader h = strs.header;
        h.rawSize = rawSize;
        fb.addRaw(h, *stored);
        auto bytes = fb.finish();
        auto c = Container::fromMemory(bytes);
        ASSERT_TRUE(c.ok()) << c.error().describe();
        auto loaded = c->load(c->chunks()[0]);
        ASSERT_FALSE(loaded.ok()) << "raw size " << rawSize;
        const FormatError expected = rawSize > ReadOptions{}.maxRawChunkBytes
                                         ? FormatError::LimitExceeded
                                         : FormatError::DecompressionFailed;
        EXPECT_EQ(loaded.error().code, expected) << loaded.error().describe();
        EXPECT_EQ(c->verifyAll().code, FormatError::DecompressionFailed);
        EXPECT_EQ(streamThroughPipe(bytes, {}, touchingCallback()).code, expected);
    }
}

// [SECTION] 1g. streaming and mapped reads deliver the same chunks

TEST_F(Corruption, StreamingMatchesMappedChunkForChunk) {
    const auto& bytes = *sSample;
    std::vector<SeenChunk> streamed;
    Status s = streamThroughPipe(bytes, {}, collectInto(streamed));
    ASSERT_TRUE(isOk(s)) << s.describe();

    for (bool useToc : {true, false}) {
        auto c = Container::fromMemory(bytes, ReadOptions{.useToc = useToc});
        ASSERT_TRUE(c.ok()) << c.error().describe();
        ASSERT_EQ(c->chunks().size(), streamed.size()) << "useToc " << useToc;
        for (size_t i = 0; i < streamed.size(); ++i) {
            const ChunkInfo& ci = c->chunks()[i];
            const SeenChunk& sc = streamed[i];
            SCOPED_TRACE("chunk " + std::to_string(i) + " '" + ci.header.tag.str() + "'");
            EXPECT_TRUE(ci.header.tag == sc.header.tag);
            EXPECT_EQ(ci.header.version, sc.header.version);
            EXPECT_EQ(ci.header.flags, sc.header.flags);
            EXPECT_EQ(ci.header.storedSize, sc.header.storedSize);
            EXPECT_EQ(ci.header.rawSize, sc.header.rawSize);
            EXPECT_EQ(ci.header.payloadChecksum, sc.header.payloadChecksum);
            EXPECT_EQ(ci.header.sequence, sc.header.sequence);
            EXPECT_EQ(ci.headerOffset, sc.headerOffset);
            auto loaded = c->load(ci);
            ASSERT_TRUE(loaded.ok()) << loaded.error().describe();
            ASSERT_EQ(loaded->bytes().size(), sc.raw.size());
            EXPECT_TRUE(std::equal(sc.raw.begin(), sc.raw.end(), loaded->bytes().begin()));
        }
    }
}

} // namespace
