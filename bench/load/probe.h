// bench/load/probe.h — one measured load of pnb_load_probe (see load_probe_main.cpp): what every
// loader returns, and the loaders themselves. Each loader does its whole job to GPU-ready (or,
// the floor, to bytes in fresh memory) and fills a ProbeResult; the main program adds the
// process-level times and prints it as one JSON line.
#pragma once

#include <chrono>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace pnb::bench {

using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

struct ProbeResult {
    // Named phases in the order they ran, ms; they add up to about gpuReadyMs.
    std::vector<std::pair<std::string, double>> phases;
    double gpuReadyMs = 0; // load start to glFinish returned (floor: to the last byte copied)
    double teardownMs = 0; // freeing what the load created (GL objects, CPU copies)
    // Every input file the load read (absolute paths), for eviction and the floor.
    std::set<std::string> files;
    uint64_t triangles = 0, textures = 0, programs = 0, mipLevels = 0;
    uint64_t bufferBytes = 0, textureBytes = 0;
    uint64_t checksum = 0; // floor: a sum over the copied bytes, so the copy cannot be elided
    std::string uploadPages; // pnb: the upload heap's pages and why (LoadStats::uploadPages)
};

// The player's loadScene() on a .pnb, then glFinish.
ProbeResult loadPnb(const std::string& path);
// Assimp::Importer::ReadFile (Triangulate | JoinIdenticalVertices | GenSmoothNormals), every
// texture decoded by stb_image, then the peer upload (peer_gl.h).
ProbeResult loadAssimp(const std::string& path);
// tinygltf LoadBinaryFromFile / LoadASCIIFromFile with its stb_image decoding, then the peer
// upload (peer_gl.h).
ProbeResult loadTinygltf(const std::string& path);
// mmap + memcpy of every file into freshly allocated memory.
ProbeResult loadFloor(const std::vector<std::string>& paths);

} // namespace pnb::bench
