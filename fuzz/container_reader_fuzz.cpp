// container_reader_fuzz — libFuzzer target for the .pnb container reader (docs/STYLE.md §9.3).
//
// Feeds one input to every read path of pnb_format: the table-of-contents index and the
// front-to-back scan (Container::fromMemory with useToc on and off), verifyAll, load and loadInto
// of every chunk, readScene, and streamChunks over a memfd with checksums on and off. Then it
// does it all again on a copy whose checksums were recomputed (withValidChecksums): a mutation
// of a size, a flag or a TOC entry otherwise stops at the first XXH3 compare, never reaching the
// frame rules and decoders behind it. Crashes, leaks and sanitizer reports are the main findings.
// On top of those the harness abort()s (so libFuzzer keeps the input) when a property the library
// promises does not hold:
//   1. The access modes agree (reader.h: they "accept and reject exactly the same files"):
//      stream(checksums) ok => stream(no checksums) ok => scan ok => TOC index ok with the same
//      chunk list; and scan ok + verifyAll ok + every chunk within the limit => stream ok.
//   2. Round trip: a Scene that readScene accepts is written with writeScene, must read back and
//      verify, and must write again to identical bytes (the writer is deterministic).
//   3. A Scene that readScene accepts poses finitely (pnb/animation_pose.h): every clip at a few
//      times, every deformed node's vertices and bounds — the reader's rules promise that no
//      file it accepts can put a NaN into a frame.
//
// Does NOT do: fuzz the writer with arbitrary Scenes (only ones the reader produced), or
// Container::open (it is fromMemory over an mmap).
//
// Run it with scripts/fuzz; reproduce a finding with `build/asan/fuzz/container_reader_fuzz FILE`.

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string_view>
#include <vector>

#include "pnb/animation_pose.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/writer.h"

namespace {

using namespace pnb;

// Bounds what one input may make the reader allocate. load() allocates a compressed chunk's
// declared raw size before inflating it, and the default limit is 4 GiB: a 200-byte input that
// declares 4 GiB would be an out-of-memory report (-rss_limit_mb) against the harness, not a bug.
constexpr uint64_t kMaxRawChunkBytes = uint64_t(16) << 20;
// readScene keeps every decompressed payload alive at once; past this total (sum of the raw
// sizes of compressed chunks) the whole-scene paths are skipped, for the same reason.
constexpr uint64_t kSceneBudgetBytes = uint64_t(64) << 20;

// Reads land here so the optimiser cannot drop them; ASan checks every byte on the way.
volatile uint64_t gSink = 0;

void touch(std::span<const std::byte> bytes) {
    uint64_t sum = 0;
    for (std::byte b : bytes) sum += uint64_t(b);
    gSink = gSink + sum;
}

void touch(std::string_view s) {
    touch(std::span<const std::byte>(reinterpret_cast<const std::byte*>(s.data()), s.size()));
}

[[noreturn]] void fail(const char* property, const Status& status) {
    std::fprintf(stderr, "container_reader_fuzz: property violated: %s (%s)\n", property,
                 isOk(status) ? "no error" : status.describe().c_str());
    std::abort();
}

// The input as a file descriptor for streamChunks. memfd: no file system, no cleanup, and the
// same read(2) path as a real file. One descriptor serves every input of the process.
int inputFd(std::span<const std::byte> bytes) {
    static const int fd = memfd_create("pnb-fuzz-input", MFD_CLOEXEC);
    if (fd < 0 || ftruncate(fd, 0) != 0) {
        std::perror("container_reader_fuzz: memfd");
        std::abort();
    }
    size_t done = 0;
    while (done < bytes.size()) {
        ssize_t n = pwrite(fd, bytes.data() + done, bytes.size() - done, off_t(done));
        if (n <= 0) {
            std::perror("container_reader_fuzz: pwrite");
            std::abort();
        }
        done += size_t(n);
    }
    if (lseek(fd, 0, SEEK_SET) != 0) {
        std::perror("container_reader_fuzz: lseek");
        std::abort();
    }
    return fd;
}

Status stream(std::span<const std::byte> bytes, bool verifyChecksums) {
    ReadOptions options;
    options.verifyChecksums = verifyChecksums;
    options.maxRawChunkBytes = kMaxRawChunkBytes;
    return streamChunks(inputFd(bytes), options, [](const StreamedChunk& chunk) {
        touch(chunk.payload);
        return true;
    });
}

void touchScene(const Scene& s) {
    for (std::string_view str : s.strings.strings) touch(str);
    for (const ShaderSource& shader : s.shaders) touch(shader.source);
    for (const Mesh& mesh : s.meshes) {
        for (const VertexStream& vs : mesh.streams) touch(vs.data);
        touch(mesh.indices);
    }
    for (const TextureMip& mip : s.textureMips) touch(mip.data);
}

std::vector<std::byte> write(const Scene& scene) {
    std::vector<std::byte> out;
    Writer writer = Writer::toMemory(&out);
    Status s = writeScene(writer, scene);
    if (isOk(s)) s = writer.commit();
    if (!isOk(s)) fail("writeScene accepts every scene readScene returns", s);
    return out;
}

void checkRoundTrip(const Scene& scene) {
    const std::vector<std::byte> first = write(scene);
    ReadOptions options; // checksums on: the writer stored them, so they must match
    options.maxRawChunkBytes = kMaxRawChunkBytes;
    auto container = Container::fromMemory(first, options);
    if (!container) fail("a written scene opens", container.error());
    if (Status s = container->verifyAll(); !isOk(s)) fail("a written scene verifies", s);
    auto again = readScene(*container);
    if (!again) fail("a written scene reads back", again.error());
    touchScene(*again);
    if (write(*again) != first) fail("writing a read-back scene gives identical bytes", {});
}

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void checkPoses(const Scene& scene) {
    for (uint32_t clip = 0; clip < scene.animations.size() && clip < 4; ++clip)
        for (double t : {0.0, 0.37, 1e9}) {
            const Pose pose = poseAt(scene, clip, t);
            const std::vector<Matrix4d> world = nodeWorldMatrices(pose.graph);
            for (uint32_t n = 0; n < pose.graph.nodes.size(); ++n) {
                const Node& node = pose.graph.nodes[n];
                if (!finite(node.translation) || !finite(node.scale))
                    fail("a valid clip poses finite transforms", {});
                for (float w : pose.weights[n])
                    if (!std::isfinite(w)) fail("a valid clip poses finite morph weights", {});
                if (!isDeformed(scene, n)) continue;
                // A vertex carried beyond float stays where it is stored (whose finiteness the
                // rules do not check: a static draw of it would be as wrong): touch, for ASan.
                const DeformedVertices v = deformVertices(scene, n, pose, world);
                gSink = gSink + v.positions.size();
                std::vector<std::array<float, 16>> joints;
                if (const Skin* skin = skinOf(scene, n)) joints = jointMatrices(*skin, world, n);
                const Aabb box = deformedBounds(deformBounds(scene, n), joints, pose.weights[n]);
                gSink = gSink + (box.empty() ? 1 : 0);
            }
        }
}

struct Opened {
    bool indexed = false;
    bool verified = false;
    bool withinLimit = true; // every chunk's raw size <= kMaxRawChunkBytes
    std::vector<ChunkInfo> chunks;
};

// Every Container entry point over one index of the input. `roundTripDone` makes the (costly)
// round trip run once per input even when both index modes produce a scene.
Opened exercise(std::span<const std::byte> bytes, bool useToc, bool verifyChecksums,
                bool& roundTripDone) {
    ReadOptions options;
    options.useToc = useToc;
    options.verifyChecksums = verifyChecksums;
    options.maxRawChunkBytes = kMaxRawChunkBytes;
    Opened result;
    auto container = Container::fromMemory(bytes, options);
    if (!container) return result;
    result.indexed = true;
    result.chunks.assign(container->chunks().begin(), container->chunks().end());
    result.verified = isOk(container->verifyAll());

    uint64_t inflated = 0;
    std::vector<std::byte> dst;
    for (const ChunkInfo& chunk : container->chunks()) {
        const uint64_t rawSize = chunk.header.rawSize;
        if (rawSize > kMaxRawChunkBytes) result.withinLimit = false;
        if (chunk.header.compression() != Compression::None) inflated += rawSize;
        if (auto payload = container->load(chunk)) touch(payload->bytes());
        if (rawSize <= kMaxRawChunkBytes) {
            dst.resize(size_t(rawSize));
            if (isOk(container->loadInto(chunk, dst))) touch(dst);
        }
    }

    if (inflated <= kSceneBudgetBytes) {
        if (auto scene = readScene(*container)) {
            touchScene(*scene);
            checkPoses(*scene);
            if (!roundTripDone) {
                roundTripDone = true;
                checkRoundTrip(*scene);
            }
        }
    }
    return result;
}

bool sameChunks(const std::vector<ChunkInfo>& a, const std::vector<ChunkInfo>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        const ChunkHeader& x = a[i].header;
        const ChunkHeader& y = b[i].header;
        if (!(x.tag == y.tag) || x.version != y.version || x.flags != y.flags ||
            x.storedSize != y.storedSize || x.rawSize != y.rawSize ||
            x.payloadChecksum != y.payloadChecksum || x.sequence != y.sequence ||
            a[i].headerOffset != b[i].headerOffset || a[i].payloadOffset != b[i].payloadOffset)
            return false;
    }
    return true;
}

// The input with every stored checksum made to match its bytes: file header, chunk headers,
// payloads that have the checksum flag, their TOC entries, the TOC and the footer. Everything else
// (sizes, flags, offsets, the other TOC fields) stays as mutated. Assumes a little-endian host.
std::vector<std::byte> withValidChecksums(std::span<const std::byte> in) {
    std::vector<std::byte> b(in.begin(), in.end());
    const uint64_t size = b.size();
    auto load64 = [&](uint64_t at) {
        uint64_t v;
        std::memcpy(&v, &b[at], 8);
        return v;
    };
    auto store64 = [&](uint64_t at, uint64_t v) { std::memcpy(&b[at], &v, 8); };
    auto hash = [&](uint64_t at, uint64_t n) { return checksum({b.data() + at, size_t(n)}); };
    if (size < kFileHeaderSize) return b;
    store64(56, hash(0, 56));

    std::vector<uint64_t> payloadChecksums;
    uint64_t off = kFileHeaderSize;
    while (off <= size && size - off >= kChunkHeaderSize) {
        uint16_t flags;
        std::memcpy(&flags, &b[off + 6], 2);
        const uint64_t stored = load64(off + 8);
        const uint64_t payload = off + kChunkHeaderSize;
        if (stored > size - payload) { // runs past the end: only the header can be fixed
            store64(off + 56, hash(off, 56));
            break;
        }
        const bool isToc = std::memcmp(&b[off], tags::kToc.c, 4) == 0;
        if (isToc && stored >= 8) { // entries: 8-byte preamble, 40 bytes each, checksum at +32
            for (uint64_t i = 0; i < payloadChecksums.size() && 8 + 40 * i + 40 <= stored; ++i)
                store64(payload + 8 + 40 * i + 32, payloadChecksums[i]);
        }
        if (flags & kChunkHasChecksum) store64(off + 24, hash(payload, stored));
        payloadChecksums.push_back(load64(off + 24));
        store64(off + 56, hash(off, 56));
        const uint64_t end = payload + stored;
        if (isToc) {
            if (size - end >= kFooterSize) store64(end + 24, hash(end, 24));
            break;
        }
        off = alignUp(end);
    }
    return b;
}

void checkInput(std::span<const std::byte> bytes) {
    // TOC index with checksums on is how the player opens files. The scan runs with checksums
    // off: the fuzzer can rarely forge an XXH3 value, so this is the configuration in which
    // mutated payloads get past the hash into zstd, the chunk decoders and validateScene.
    bool roundTripDone = false;
    const Opened toc = exercise(bytes, /*useToc=*/true, /*verifyChecksums=*/true, roundTripDone);
    const Opened scan = exercise(bytes, /*useToc=*/false, /*verifyChecksums=*/false, roundTripDone);

    const Status streamed = stream(bytes, /*verifyChecksums=*/true);
    const Status streamedUnchecked = stream(bytes, /*verifyChecksums=*/false);

    if (scan.indexed && !(toc.indexed && sameChunks(toc.chunks, scan.chunks)))
        fail("a file the scan indexes, the TOC indexes to the same chunks", {});
    if (isOk(streamed) && !isOk(streamedUnchecked))
        fail("checksums off accepts whatever checksums on accepts", streamedUnchecked);
    if (isOk(streamedUnchecked) && !scan.indexed)
        fail("a file the stream accepts, the scan indexes", {});
    if (scan.indexed && scan.verified && scan.withinLimit && !isOk(streamed))
        fail("a file that indexes and verifies streams", streamed);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
    checkInput(bytes);
    const std::vector<std::byte> repaired = withValidChecksums(bytes);
    if (!std::equal(repaired.begin(), repaired.end(), bytes.begin()))
        checkInput(repaired);
    return 0;
}
