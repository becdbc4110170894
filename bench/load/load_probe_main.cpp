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
// Exit codes: 0 ok, 1 usage, 2 the load failed (the JSON line has "ok": false and "error"). The
// command line is one pnb_cli option table, which also prints --help.
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
#include "pnb_cli/options.h"
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

constexpr const char* kUsage = "usage: pnb_load_probe --loader pnb|assimp|tinygltf FILE\n"
                               "       pnb_load_probe --loader floor FILE...\n"
                               "       pnb_load_probe --evict FILE...\n";

[[noreturn]] void usage(const std::string& what) {
    std::fprintf(stderr, "pnb_load_probe: %s\n%s", what.c_str(), kUsage);
    std::exit(1);
}

// [SECTION] command line

enum class Mode { None, Loader, Evict };

struct Request {
    Mode mode = Mode::None;
    std::string loader;
    std::vector<std::string> files; // the mode's FILE arguments, in order
    bool help = false;
};

// The mode comes first, once, its files after it, as this tool has always read its command line.
bool choose(Request& r, Mode mode) {
    if (r.mode != Mode::None || !r.files.empty()) return false;
    r.mode = mode;
    return true;
}

std::vector<pnb::cli::Option> options(Request& r) {
    return {
        pnb::cli::valued("", "--loader", "NAME",
                         "load FILE to GPU-ready with pnb, assimp or tinygltf (and stb_image); or "
                         "\"floor\": mmap + copy FILE... into fresh memory",
                         [&r](const char* name) {
                             r.loader = name;
                             return choose(r, Mode::Loader);
                         }),
        pnb::cli::flag("", "--evict",
                       "drop FILE... from the page cache (fdatasync + posix_fadvise), then report "
                       "the bytes still resident",
                       [&r](const char*) { return choose(r, Mode::Evict); }),
        pnb::cli::flag("", "-h, --help", "print this help and exit",
                       [&r](const char*) {
                           r.help = true;
                           return pnb::cli::Verdict::stopHere();
                       }),
    };
}

// This tool's wording of a parse error (argc: a lone FILE is "missing arguments", as it was).
std::string wording(const pnb::cli::ParseError& e, int argc) {
    using Kind = pnb::cli::ParseError::Kind;
    switch (e.kind) {
    case Kind::MissingValue:
        return "missing arguments";
    case Kind::BadValue:
        return "give one of --loader and --evict, once, before FILE";
    case Kind::FlagWithValue:
        return "unknown option " + e.option + "=" + e.value;
    case Kind::Positional: // FILE before the mode
        return argc < 3 ? "missing arguments" : "unknown option " + e.value;
    case Kind::UnknownOption:
        break;
    }
    return "unknown option " + e.option;
}

// Parses the command line, or exits: with the help (0) or a usage error (1).
Request parseOrExit(int argc, char** argv) {
    Request r;
    const std::vector<pnb::cli::Option> table = options(r);
    auto file = [&r](const char* arg) {
        if (r.mode == Mode::None) return false;
        r.files.emplace_back(arg);
        return true;
    };
    if (auto e = pnb::cli::parse(table, file, argc, argv)) usage(wording(*e, argc));
    if (r.help) {
        std::printf("%s\n%s", kUsage,
                    pnb::cli::helpText(table, {.column = 18, .wrapAt = 100}).c_str());
        std::exit(0);
    }
    if (r.mode == Mode::None || (r.mode == Mode::Evict && r.files.empty()))
        usage("missing arguments");
    if (r.mode == Mode::Loader) {
        if (r.files.empty()) usage("no input file");
        if (r.loader != "floor" && r.files.size() != 1)
            usage("--loader " + r.loader + " takes one FILE");
        if (r.loader != "floor" && r.loader != "pnb" && r.loader != "assimp" &&
            r.loader != "tinygltf")
            usage("unknown loader " + r.loader);
    }
    return r;
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
    const Request request = parseOrExit(argc, argv);
    if (request.mode == Mode::Evict) {
        printLine(evict(request.files));
        return 0;
    }
    const std::string& loader = request.loader;
    const std::vector<std::string>& inputs = request.files;
    line["loader"] = loader;
    line["inputs"] = inputs;

    pnb::bench::ProbeResult r;
    try {
        if (loader == "floor") {
            r = pnb::bench::loadFloor(inputs);
        } else {
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
