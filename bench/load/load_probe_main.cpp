// pnb_load_probe — ONE load per process, printed as one JSON line, for scripts/bench-load.
//
//   pnb_load_probe --loader pnb|assimp|tinygltf FILE    load FILE to GPU-ready
//   pnb_load_probe --loader floor FILE...               mmap + copy FILE... into fresh memory
//   pnb_load_probe --evict FILE...                      drop FILE... from the page cache
//
// GPU-ready means the same thing for every GL loader (probe.h has what each does): geometry in
// GL buffers with vertex arrays, textures in GL textures with full mip chains, the programs
// linked, glFinish returned. The EGL context (headless, Mesa llvmpipe here) is created first and
// timed apart ("context_ms"), as a viewer creates its window before it opens a file.
//
// Times (std::chrono::steady_clock = CLOCK_MONOTONIC, ms): exec_to_main_ms when the runner put
// its CLOCK_MONOTONIC spawn time in PNB_PROBE_SPAWN_NS (dynamic linking + static initialisers),
// context_ms, gpu_ready_ms with its phases, teardown_ms (freeing what the load made), inner_ms
// (main entry to the JSON line). The runner times the whole process from outside as well.
// "files" lists every input file the load read (what --evict and the floor are given).
//
// --evict: fdatasync, posix_fadvise(POSIX_FADV_DONTNEED), then mincore() over a fresh mapping
// to report how many bytes are still resident (pages another process maps stay; the line says
// so rather than pretending).
//
// Exit codes: 0 ok, 1 usage, 2 the load failed (the JSON line has "ok": false and "error").
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "peer_gl.h"
#include "pnb_player/gl_context.h"
#include "probe.h"

namespace {

using nlohmann::json;
using pnb::bench::Clock;
using pnb::bench::msSince;

void printLine(const json& j) {
    std::fputs((j.dump() + "\n").c_str(), stdout);
    std::fflush(stdout);
}

[[noreturn]] void usage(const std::string& what) {
    std::fprintf(stderr,
                 "pnb_load_probe: %s\n"
                 "usage: pnb_load_probe --loader pnb|assimp|tinygltf FILE\n"
                 "       pnb_load_probe --loader floor FILE...\n"
                 "       pnb_load_probe --evict FILE...\n",
                 what.c_str());
    std::exit(1);
}

json evict(const std::vector<std::string>& paths) {
    uint64_t bytes = 0, resident = 0;
    json errors = json::array();
    const long page = sysconf(_SC_PAGESIZE);
    for (const std::string& path : paths) {
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) {
            errors.push_back(path + ": " + std::strerror(errno));
            continue;
        }
        struct stat st {};
        ::fstat(fd, &st);
        const size_t size = size_t(st.st_size);
        bytes += size;
        ::fdatasync(fd); // dirty pages cannot be dropped
        if (int e = ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED); e != 0)
            errors.push_back(path + ": posix_fadvise: " + std::strerror(e));
        if (size > 0) {
            void* map = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
            if (map != MAP_FAILED) {
                std::vector<unsigned char> vec((size + size_t(page) - 1) / size_t(page));
                if (::mincore(map, size, vec.data()) == 0)
                    for (unsigned char v : vec)
                        resident += (v & 1) ? uint64_t(page) : 0;
                ::munmap(map, size);
            }
        }
        ::close(fd);
    }
    return {{"evicted_files", paths.size()},
            {"bytes", bytes},
            {"resident_bytes_after", resident},
            {"method", "fdatasync + posix_fadvise(POSIX_FADV_DONTNEED)"},
            {"errors", errors}};
}

json fileList(const std::set<std::string>& files) {
    json out = json::array();
    std::error_code ec;
    for (const std::string& f : files) {
        const auto size = std::filesystem::file_size(f, ec);
        out.push_back({{"path", f}, {"bytes", ec ? 0 : uint64_t(size)}});
    }
    return out;
}

} // namespace

int main(int argc, char** argv) {
    const auto mainEntry = Clock::now();
    json line;
    if (const char* spawn = std::getenv("PNB_PROBE_SPAWN_NS")) {
        const auto now =
            std::chrono::duration_cast<std::chrono::nanoseconds>(mainEntry.time_since_epoch())
                .count();
        line["exec_to_main_ms"] = double(now - std::strtoll(spawn, nullptr, 10)) / 1e6;
    }
    if (argc < 3) usage("missing arguments");
    const std::string mode = argv[1];
    if (mode == "--evict") {
        printLine(evict({argv + 2, argv + argc}));
        return 0;
    }
    if (mode != "--loader") usage("unknown option " + mode);
    const std::string loader = argv[2];
    const std::vector<std::string> inputs(argv + 3, argv + argc);
    if (inputs.empty()) usage("no input file");
    if (loader != "floor" && inputs.size() != 1) usage("--loader " + loader + " takes one FILE");
    line["loader"] = loader;
    line["inputs"] = inputs;

    pnb::bench::ProbeResult r;
    try {
        if (loader == "floor") {
            r = pnb::bench::loadFloor(inputs);
        } else {
            if (loader != "pnb" && loader != "assimp" && loader != "tinygltf")
                usage("unknown loader " + loader);
            const auto start = Clock::now();
            auto context = pnb::player::createHeadlessContext();
            if (!context) throw pnb::bench::LoadFailure(context.error().message);
            line["context_ms"] = msSince(start);
            const pnb::player::GlInfo info = (*context)->info();
            line["gl"] = {{"renderer", info.renderer}, {"version", info.version}};
            if (loader == "pnb")
                r = pnb::bench::loadPnb(inputs[0]);
            else if (loader == "assimp")
                r = pnb::bench::loadAssimp(inputs[0]);
            else
                r = pnb::bench::loadTinygltf(inputs[0]);
        }
    } catch (const std::exception& e) {
        line["ok"] = false;
        line["error"] = e.what();
        printLine(line);
        return 2;
    }
    line["ok"] = true;
    line["gpu_ready_ms"] = r.gpuReadyMs;
    json phases = json::object();
    for (const auto& [name, ms] : r.phases)
        phases[name] = ms;
    line["phases"] = phases;
    line["teardown_ms"] = r.teardownMs;
    line["files"] = fileList(r.files);
    line["triangles"] = r.triangles;
    line["textures"] = r.textures;
    line["mip_levels"] = r.mipLevels;
    line["programs"] = r.programs;
    line["buffer_bytes"] = r.bufferBytes;
    line["texture_bytes"] = r.textureBytes;
    line["checksum"] = r.checksum;
    if (!r.uploadPages.empty()) line["upload_pages"] = r.uploadPages;
    line["inner_ms"] = msSince(mainEntry);
    printLine(line);
    return 0;
}
