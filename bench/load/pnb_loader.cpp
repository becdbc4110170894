// The pnb side of pnb_load_probe: the player's own loader, unchanged (see probe.h).
#include <epoxy/gl.h>

#include <filesystem>

#include "peer_gl.h"
#include "pnb_player/gpu_scene.h"
#include "pnb_player/program_cache_files.h"
#include "probe.h"

namespace pnb::bench {

ProbeResult loadPnb(const std::string& path) {
    ProbeResult r;
    player::LoadStats stats;
    // As pnb-play loads: programs through the program binary cache ($PNB_PROGRAM_CACHE_DIR, which
    // bench_load.py points at its own directory, filled by its untimed warm-up run).
    player::ProgramCacheOptions cache;
    cache.enabled = true;
    player::configureProgramCacheOnDisk(cache);
    const auto start = Clock::now();
    auto scene = player::loadScene(path, {}, &stats);
    if (!scene) throw LoadFailure(scene.error().message);
    glFinish(); // loadScene ends its upload with glFinish; this covers the programs too
    r.gpuReadyMs = msSince(start);
    r.phases = {{"open", stats.openMs},
                {"read", stats.readMs},
                {"decode", stats.decodeMs},
                {"upload", stats.uploadMs},
                {"compile", stats.compileMs}};
    r.files.insert(std::filesystem::absolute(path).lexically_normal().string());
    const player::GpuScene& s = **scene;
    r.triangles = s.triangles;
    r.textures = s.textures.size();
    for (const player::GpuTexture& t : s.textures)
        r.mipLevels += t.mipCount;
    for (const auto& p : s.programs)
        r.programs += p ? 1 : 0;
    r.bufferBytes = s.memory.meshBytes;
    r.uploadPages = stats.uploadPages;
    r.textureBytes = s.memory.textureBytes;
    const auto down = Clock::now();
    scene->reset();
    glFinish();
    r.teardownMs = msSince(down);
    return r;
}

} // namespace pnb::bench
