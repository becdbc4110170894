// pnb_format_bench — read throughput of the container library, like with like.
//
// The questions it answers (format issue; issue 13 item 4): what does the reader cost over the
// bare operation it performs, and does reading and verifying an uncompressed container from a
// warm page cache run at >= 50% of memcpy bandwidth? Each benchmark moves the same payload bytes
// and reports them with SetBytesProcessed, so rates compare directly. Two like-with-like pairs,
// over the same mapping of the same file, opened once outside the timing and pre-faulted:
//   MemcpyFromMapping   memcpy of every payload from the mapping into warm caller memory
//   LoadIntoOpenOnce    Container::loadInto() of every chunk into the same memory (hash + copy)
// and
//   HashFromMapping     XXH3 (pnb::checksum) of every payload in the mapping, nothing else
//   MmapVerifyOpenOnce  Container::load() of every chunk: zero-copy views, checksums verified
// The ratio inside each pair is the reader's overhead. The other paths, for the whole picture:
//   Memcpy         memcpy of all payload bytes between two warm heap buffers (the old baseline)
//   MmapVerify     Container::open + load() of every chunk each iteration (mapping set-up and
//                  page-table faults included)
//   MmapLoadInto   Container::open + loadInto() of every chunk each iteration (hash + copy)
//   ZstdLoadInto   the same over the zstd-compressed file: decompress into caller memory
//   Stream         streamChunks(): read(2) into the reader's buffer, hash, hand over
// All of them verify checksums (the ReadOptions default) and time wall clock, since the reader's
// costs include page faults and system calls. Rates count raw (decompressed) payload bytes.
//
// Test data: 64 MESH chunks of about 4 MiB each (a procedural terrain grid: float positions with
// noise, UVs, u32 triangle indices), written once uncompressed and once with zstd (WriteOptions
// default level), both with checksums, in PNB_BENCH_DATA_DIR (default: next to this binary).
// They are REGENERATED at every start (a few seconds), then read once in full: how long a file
// has sat in the page cache changed the mapped-read rates between 50 % and 100 % of memcpy from
// one run to the next, so every run starts from the same state (PNB_BENCH_REUSE_DATA=1 reuses
// intact files instead, for quick iterations). PNB_BENCH_CHUNKS=N overrides the chunk count.
//
// Does NOT do: cold-cache measurements (they would measure the disk; drop caches by hand for
// that), or decode the MESH payloads (chunks.h decoding is not part of the read path measured).

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/reader.h"
#include "pnb/writer.h"

namespace {

using namespace pnb;

// Bump when the generated data changes, so cached files from an older generator are not reused.
constexpr int kGeneratorVersion = 2;
constexpr uint32_t kDefaultChunkCount = 64;
// Grid of one chunk: kGridColumns x kGridRows vertices. 44 bytes per vertex (12 position, 8 UV,
// ~24 of indices) puts a chunk just over 4 MiB, the whole file over 256 MiB.
constexpr uint32_t kGridColumns = 256;
constexpr uint32_t kGridRows = 374;

[[noreturn]] void fatal(const std::string& what) {
    std::fprintf(stderr, "pnb_format_bench: %s\n", what.c_str());
    std::exit(1);
}

uint32_t hash32(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// Storage for one generated mesh; the Mesh's Blobs point into it.
struct MeshData {
    std::vector<float> positions, uvs;
    std::vector<uint32_t> indices;
    Mesh mesh;
};

template <class T> Blob blobOf(const std::vector<T>& v) {
    return {reinterpret_cast<const std::byte*>(v.data()), v.size() * sizeof(T)};
}

// Patch `chunk` of a large heightfield: smooth hills plus per-vertex noise, so zstd finds the
// structure of the indices and the float exponents but not the noisy mantissas (a ratio of
// about 2-3, as for real scanned or sculpted geometry).
void makeTerrainPatch(uint32_t chunk, MeshData& d) {
    const uint32_t cols = kGridColumns, rows = kGridRows;
    const float spacing = 0.25f;
    d.positions.clear();
    d.uvs.clear();
    d.indices.clear();
    Aabb bounds;
    bounds.min = {INFINITY, INFINITY, INFINITY};
    bounds.max = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t r = 0; r < rows; ++r)
        for (uint32_t c = 0; c < cols; ++c) {
            // Three 10-bit noise values per vertex: a scanned surface is never an exact grid.
            uint32_t h = hash32(chunk * cols * rows + r * cols + c);
            float nx = float(h & 1023) / 1024.0f - 0.5f;
            float ny = float((h >> 10) & 1023) / 1024.0f;
            float nz = float((h >> 20) & 1023) / 1024.0f - 0.5f;
            float x = (float(chunk * (cols - 1) + c) + 0.2f * nx) * spacing;
            float z = (float(r) + 0.2f * nz) * spacing;
            float y = 4.0f * std::sin(x * 0.05f) * std::cos(z * 0.07f) + 0.3f * ny;
            d.positions.insert(d.positions.end(), {x, y, z});
            d.uvs.insert(d.uvs.end(), {float(c) / float(cols - 1), float(r) / float(rows - 1)});
            bounds.min = {std::fmin(bounds.min.x, x), std::fmin(bounds.min.y, y),
                          std::fmin(bounds.min.z, z)};
            bounds.max = {std::fmax(bounds.max.x, x), std::fmax(bounds.max.y, y),
                          std::fmax(bounds.max.z, z)};
        }
    for (uint32_t r = 0; r + 1 < rows; ++r)
        for (uint32_t c = 0; c + 1 < cols; ++c) {
            uint32_t a = r * cols + c, b = a + 1, e = a + cols, f = e + 1;
            d.indices.insert(d.indices.end(), {a, e, f, a, f, b});
        }

    Mesh& m = d.mesh;
    m = Mesh{};
    m.indexType = IndexType::U32;
    m.vertexCount = cols * rows;
    VertexStream position;
    position.semantic = VertexSemantic::Position;
    position.componentCount = 3;
    position.data = blobOf(d.positions);
    VertexStream uv;
    uv.semantic = VertexSemantic::TexCoord0;
    uv.componentCount = 2;
    uv.data = blobOf(d.uvs);
    m.streams = {position, uv};
    m.indices = blobOf(d.indices);
    Submesh all;
    all.indexCount = uint32_t(d.indices.size());
    all.bounds = bounds;
    m.submeshes = {all};
    m.bounds = bounds;
}

uint32_t chunkCount() {
    const char* env = std::getenv("PNB_BENCH_CHUNKS");
    if (!env) return kDefaultChunkCount;
    long n = std::strtol(env, nullptr, 10);
    if (n < 1 || n > 4096) fatal("PNB_BENCH_CHUNKS must be a number from 1 to 4096");
    return uint32_t(n);
}

// A cached file is reused only if it is complete and every checksum holds.
bool usable(const std::string& path, uint32_t chunks) {
    if (!std::filesystem::exists(path)) return false;
    auto c = Container::open(path);
    return c && c->chunks().size() == chunks && isOk(c->verifyAll());
}

void generate(const std::string& path, uint32_t chunks, Compression compression) {
    std::fprintf(stderr, "pnb_format_bench: generating %s\n", path.c_str());
    auto writer = Writer::create(path);
    if (!writer) fatal(writer.error().describe());
    MeshData d;
    for (uint32_t i = 0; i < chunks; ++i) {
        makeTerrainPatch(i, d);
        if (Status s = writeChunk(*writer, d.mesh, compression); !isOk(s)) fatal(s.describe());
    }
    if (Status s = writer->commit(); !isOk(s)) fatal(s.describe());
}

struct Dataset {
    std::string plainPath, zstdPath;
    uint64_t rawBytes = 0;    // sum of the chunks' raw sizes, the same in both files
    uint64_t zstdBytes = 0;   // sum of the compressed file's stored sizes
    std::vector<std::byte> source; // every raw payload back to back: the memcpy baseline's input
};

Dataset makeDataset() {
    const uint32_t chunks = chunkCount();
    const char* env = std::getenv("PNB_BENCH_DATA_DIR");
    const std::filesystem::path dir = env ? env : PNB_BENCH_DEFAULT_DATA_DIR;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) fatal("cannot create " + dir.string() + ": " + ec.message());
    const std::string stem = "terrain_v" + std::to_string(kGeneratorVersion) + "_" +
                             std::to_string(chunks) + "x4MiB";
    Dataset d;
    d.plainPath = (dir / (stem + ".pnb")).string();
    d.zstdPath = (dir / (stem + "_zstd.pnb")).string();
    const bool reuse = std::getenv("PNB_BENCH_REUSE_DATA") != nullptr;
    if (!reuse || !usable(d.plainPath, chunks)) generate(d.plainPath, chunks, Compression::None);
    if (!reuse || !usable(d.zstdPath, chunks)) generate(d.zstdPath, chunks, Compression::Zstd);
    // Read both in full once (verifyAll hashes every payload): every benchmark below starts
    // from page-cache-resident files.
    if (!usable(d.plainPath, chunks) || !usable(d.zstdPath, chunks))
        fatal("the generated files do not verify");

    auto plain = Container::open(d.plainPath);
    auto packed = Container::open(d.zstdPath);
    if (!plain || !packed) fatal("cannot reopen the generated files");
    for (const ChunkInfo& c : plain->chunks()) d.rawBytes += c.header.rawSize;
    for (const ChunkInfo& c : packed->chunks()) d.zstdBytes += c.header.storedSize;
    d.source.resize(d.rawBytes);
    uint64_t at = 0;
    for (const ChunkInfo& c : plain->chunks()) {
        std::span<std::byte> dst(d.source.data() + at, c.header.rawSize);
        if (Status s = plain->loadInto(c, dst); !isOk(s)) fatal(s.describe());
        at += c.header.rawSize;
    }
    std::fprintf(stderr, "pnb_format_bench: %u chunks, %.1f MiB raw, zstd file %.1f MiB (%.2fx)\n",
                 chunks, double(d.rawBytes) / (1 << 20), double(d.zstdBytes) / (1 << 20),
                 double(d.rawBytes) / double(d.zstdBytes));
    return d;
}

const Dataset& dataset() {
    static const Dataset d = makeDataset();
    return d;
}

// The uncompressed file opened once, outside the timing, and pre-faulted: one full verified
// pass maps every page, so the like-with-like pairs below time the work, not first-touch faults.
const Container& openOnce() {
    static Container c = [] {
        auto opened = Container::open(dataset().plainPath);
        if (!opened) fatal(opened.error().describe());
        if (Status s = opened->verifyAll(); !isOk(s)) fatal(s.describe());
        return std::move(*opened);
    }();
    return c;
}

std::span<const std::byte> payloadOf(const Container& c, const ChunkInfo& chunk) {
    return c.bytes().subspan(chunk.payloadOffset, chunk.header.rawSize);
}

// Destination for the copying benchmarks. Value-initialised, so every page is faulted in before
// timing starts and the copies measure bandwidth, not first-touch page faults.
std::vector<std::byte> warmDestination(uint64_t size) { return std::vector<std::byte>(size); }

void finish(benchmark::State& state, const Dataset& d) {
    state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(d.rawBytes));
}

void Memcpy(benchmark::State& state) {
    const Dataset& d = dataset();
    std::vector<std::byte> dst = warmDestination(d.rawBytes);
    for (auto _ : state) {
        std::memcpy(dst.data(), d.source.data(), d.rawBytes);
        benchmark::ClobberMemory();
    }
    finish(state, d);
}

// Runs `body` (one pass over the data, returning a Status) per iteration; a failure aborts the
// benchmark with the error instead of reporting a rate for work that was not done.
template <class Body> void run(benchmark::State& state, const Dataset& d, Body body) {
    for (auto _ : state) {
        if (Status s = body(); !isOk(s)) {
            state.SkipWithError(s.describe().c_str());
            break;
        }
        benchmark::ClobberMemory();
    }
    finish(state, d);
}

// load() of every chunk: for uncompressed chunks a zero-copy view, after hashing the mapped bytes.
Status loadEach(const Container& c) {
    for (const ChunkInfo& chunk : c.chunks()) {
        auto payload = c.load(chunk);
        if (!payload) return payload.error();
        benchmark::DoNotOptimize(payload->bytes().data());
    }
    return {};
}

void MmapVerify(benchmark::State& state) {
    const Dataset& d = dataset();
    run(state, d, [&]() -> Status {
        auto c = Container::open(d.plainPath);
        return c ? loadEach(*c) : c.error();
    });
}

// MmapVerify with the container opened once and pre-faulted, outside the timing (a player keeps
// it open): the hashing plus the reader's checks; its pair is HashFromMapping. The gap to
// MmapVerify is the cost of mapping and unmapping the file, i.e. of page-table setup and
// teardown, which on a VM depends on how the page cache holds the file.
void MmapVerifyOpenOnce(benchmark::State& state) {
    const Dataset& d = dataset();
    const Container& c = openOnce();
    run(state, d, [&]() -> Status { return loadEach(c); });
}

void MemcpyFromMapping(benchmark::State& state) {
    const Dataset& d = dataset();
    const Container& c = openOnce();
    std::vector<std::byte> dst = warmDestination(d.rawBytes);
    for (auto _ : state) {
        uint64_t at = 0;
        for (const ChunkInfo& chunk : c.chunks()) {
            const auto src = payloadOf(c, chunk);
            std::memcpy(dst.data() + at, src.data(), src.size());
            at += src.size();
        }
        benchmark::ClobberMemory();
    }
    finish(state, d);
}

void LoadIntoOpenOnce(benchmark::State& state) {
    const Dataset& d = dataset();
    const Container& c = openOnce();
    std::vector<std::byte> dst = warmDestination(d.rawBytes);
    run(state, d, [&]() -> Status {
        uint64_t at = 0;
        for (const ChunkInfo& chunk : c.chunks()) {
            std::span<std::byte> out(dst.data() + at, chunk.header.rawSize);
            if (Status s = c.loadInto(chunk, out); !isOk(s)) return s;
            at += chunk.header.rawSize;
        }
        return {};
    });
}

void HashFromMapping(benchmark::State& state) {
    const Dataset& d = dataset();
    const Container& c = openOnce();
    for (auto _ : state) {
        uint64_t h = 0;
        for (const ChunkInfo& chunk : c.chunks())
            h ^= checksum(payloadOf(c, chunk));
        benchmark::DoNotOptimize(h);
    }
    finish(state, d);
}

void loadIntoAll(benchmark::State& state, const std::string& path, const Dataset& d) {
    std::vector<std::byte> dst = warmDestination(d.rawBytes);
    run(state, d, [&]() -> Status {
        auto c = Container::open(path);
        if (!c) return c.error();
        uint64_t at = 0;
        for (const ChunkInfo& chunk : c->chunks()) {
            std::span<std::byte> out(dst.data() + at, chunk.header.rawSize);
            if (Status s = c->loadInto(chunk, out); !isOk(s)) return s;
            at += chunk.header.rawSize;
        }
        return {};
    });
}

void MmapLoadInto(benchmark::State& state) { loadIntoAll(state, dataset().plainPath, dataset()); }

void ZstdLoadInto(benchmark::State& state) {
    const Dataset& d = dataset();
    loadIntoAll(state, d.zstdPath, d);
    state.counters["ratio"] = double(d.rawBytes) / double(d.zstdBytes);
}

void Stream(benchmark::State& state) {
    const Dataset& d = dataset();
    run(state, d, [&]() -> Status {
        return streamChunks(d.plainPath, ReadOptions{}, [](const StreamedChunk& chunk) {
            benchmark::DoNotOptimize(chunk.payload.data());
            return true;
        });
    });
}

} // namespace

BENCHMARK(MemcpyFromMapping)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(LoadIntoOpenOnce)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(HashFromMapping)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(Memcpy)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(MmapVerify)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(MmapVerifyOpenOnce)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(MmapLoadInto)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(ZstdLoadInto)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(Stream)->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
