// The raw-bytes floor of pnb_load_probe: the same files a loader reads, mapped and copied into
// memory that has never been touched (so the copy pays the first-touch page faults a loader's
// own allocations pay). No loader can get its bytes into its own memory faster than this.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>

#include "peer_gl.h"
#include "probe.h"

namespace pnb::bench {

namespace {

struct FreeDeleter {
    void operator()(uint8_t* p) const { std::free(p); }
};

std::string errnoText(const std::string& what, const std::string& path) {
    return what + " " + path + ": " + std::strerror(errno);
}

} // namespace

ProbeResult loadFloor(const std::vector<std::string>& paths) {
    ProbeResult r;
    std::vector<std::unique_ptr<uint8_t, FreeDeleter>> copies;
    std::vector<size_t> sizes;
    double mapMs = 0, copyMs = 0;
    const auto start = Clock::now();
    for (const std::string& path : paths) {
        auto phase = Clock::now();
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) throw LoadFailure(errnoText("cannot open", path));
        struct stat st {};
        if (::fstat(fd, &st) != 0) {
            ::close(fd);
            throw LoadFailure(errnoText("cannot stat", path));
        }
        const size_t size = size_t(st.st_size);
        void* map = size ? ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0) : nullptr;
        ::close(fd);
        if (map == MAP_FAILED) throw LoadFailure(errnoText("cannot map", path));
        mapMs += msSince(phase);
        phase = Clock::now();
        // malloc, not new T[]() : value-initialising would fault the pages in before the copy.
        std::unique_ptr<uint8_t, FreeDeleter> copy(static_cast<uint8_t*>(std::malloc(size + 1)));
        if (!copy) throw LoadFailure("out of memory copying " + path);
        if (size) std::memcpy(copy.get(), map, size);
        copyMs += msSince(phase);
        if (size) ::munmap(map, size);
        copies.push_back(std::move(copy));
        sizes.push_back(size);
        r.files.insert(std::filesystem::absolute(path).lexically_normal().string());
        r.bufferBytes += size;
    }
    r.gpuReadyMs = msSince(start);
    r.phases = {{"map", mapMs}, {"copy", copyMs}};
    // One byte a page, outside the timing: the copies have an observable result.
    for (size_t f = 0; f < copies.size(); ++f)
        for (size_t i = 0; i < sizes[f]; i += 4096)
            r.checksum += copies[f].get()[i];
    const auto down = Clock::now();
    copies.clear();
    r.teardownMs = msSince(down);
    return r;
}

} // namespace pnb::bench
