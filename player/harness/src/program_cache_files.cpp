// The program cache's entries as files (pnb_player/program_cache_files.h).
#include "pnb_player/program_cache_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "pnb/atomic_file.h"

namespace pnb::player {

namespace {

ProgramCacheEntryRead readEntry(const std::string& path, uint64_t maxBytes) {
    ProgramCacheEntryRead read;
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        read.error = errno;
        return read;
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        read.error = S_ISREG(st.st_mode) || st.st_mode == 0 ? errno : EISDIR;
        ::close(fd);
        return read;
    }
    if (uint64_t(st.st_size) > maxBytes) {
        ::close(fd);
        read.oversized = true;
        return read;
    }
    read.bytes.resize(size_t(st.st_size));
    size_t done = 0;
    while (done < read.bytes.size()) {
        ssize_t n = ::read(fd, read.bytes.data() + done, read.bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break; // shrank meanwhile: what was read is judged by the cache
        done += size_t(n);
    }
    read.bytes.resize(done);
    ::close(fd);
    return read;
}

std::string writeEntry(const std::string& directory, const std::string& path, std::span<const uint8_t> entry) {
    std::error_code ec;
    std::filesystem::create_directories(directory, ec);
    if (ec) return "cannot create " + directory + ": " + ec.message();
    auto temp = createTemporaryFor(path);
    if (!temp) return temp.error().describe();
    const uint8_t* p = entry.data();
    size_t left = entry.size();
    int failure = 0;
    while (left > 0) {
        ssize_t n = ::write(temp->fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            failure = n < 0 ? errno : ENOSPC;
            break;
        }
        p += n;
        left -= size_t(n);
    }
    if (::close(temp->fd) != 0 && !failure) failure = errno;
    if (!failure && ::rename(temp->path.c_str(), path.c_str()) != 0) failure = errno;
    if (failure) {
        ::unlink(temp->path.c_str());
        return "cannot write " + path + ": " + std::strerror(failure);
    }
    return "";
}

} // namespace

ProgramCacheStore programCacheFiles() { return {readEntry, writeEntry}; }

void configureProgramCacheOnDisk(ProgramCacheOptions options) {
    options.store = programCacheFiles();
    configureProgramCache(options);
}

} // namespace pnb::player
