#include "pnb/file_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <thread>

#include "pnb/container.h"

namespace pnb {

namespace {

bool readAt(int fd, void* out, size_t size, uint64_t offset) {
    auto* p = static_cast<char*>(out);
    while (size > 0) {
        ssize_t n = ::pread(fd, p, size, off_t(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n, size -= size_t(n), offset += uint64_t(n);
    }
    return true;
}

// The TOC chunk's payload checksum, through the footer: two small reads. 0 if the file is not a
// container this library can index (the stamp then rests on inode, size and time).
uint64_t tocChecksumOf(int fd, uint64_t fileSize) {
    if (fileSize < kFooterSize + kChunkHeaderSize) return 0;
    std::byte footerBytes[kFooterSize], headerBytes[kChunkHeaderSize];
    if (!readAt(fd, footerBytes, sizeof footerBytes, fileSize - kFooterSize)) return 0;
    auto footer = decodeFooter(footerBytes, fileSize - kFooterSize);
    if (!footer || footer->tocOffset > fileSize - kChunkHeaderSize) return 0;
    if (!readAt(fd, headerBytes, sizeof headerBytes, footer->tocOffset)) return 0;
    auto header = decodeChunkHeader(headerBytes, footer->tocOffset);
    return header ? header->payloadChecksum : 0;
}

FileStamp stampFromStat(const struct stat& st) {
    FileStamp s;
    s.exists = true;
    s.device = uint64_t(st.st_dev);
    s.inode = uint64_t(st.st_ino);
    s.size = uint64_t(st.st_size);
    s.modifiedNs = int64_t(st.st_mtim.tv_sec) * 1000000000 + int64_t(st.st_mtim.tv_nsec);
    return s;
}

} // namespace

std::string FileStamp::describe() const {
    if (!exists) return "no file";
    const time_t seconds = time_t(modifiedNs / 1000000000);
    struct tm utc {};
    char when[32] = "?";
    if (::gmtime_r(&seconds, &utc)) std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S", &utc);
    return std::to_string(size) + " bytes, modified " + when + " UTC";
}

Result<FileStamp> stampOf(const std::string& path) {
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        if (errno == ENOENT) return FileStamp{};
        return makeError(FormatError::IoError, 0, "cannot open '%s': %s", path.c_str(),
                         std::strerror(errno));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int e = errno;
        ::close(fd);
        return makeError(FormatError::IoError, 0, "cannot stat '%s': %s", path.c_str(),
                         std::strerror(e));
    }
    FileStamp s = stampFromStat(st);
    if (S_ISREG(st.st_mode)) s.tocChecksum = tocChecksumOf(fd, s.size);
    ::close(fd);
    return s;
}

Result<FileLock> FileLock::acquire(const std::string& path, const Options& options) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto pause = std::chrono::microseconds(500);
    bool announced = false;
    while (true) {
        int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
        if (fd < 0) {
            // No file: nothing to overtake. A file this process may not read: no tool of ours
            // read it either, so there is no read-to-rename to respect.
            if (errno == ENOENT || errno == EACCES) return FileLock{};
            return makeError(FormatError::IoError, 0, "cannot open '%s' to lock it: %s",
                             path.c_str(), std::strerror(errno));
        }
        // Polled rather than blocking, so the wait has a bound and a caller can say it waits.
        while (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            if (errno == ENOLCK || errno == EOPNOTSUPP || errno == EINVAL) {
                ::close(fd); // a file system without flock: the save goes ahead unguarded,
                return FileLock{}; // as it did before the lock existed
            }
            if (errno != EWOULDBLOCK && errno != EINTR) {
                const int e = errno;
                ::close(fd);
                return makeError(FormatError::IoError, 0, "cannot lock '%s': %s", path.c_str(),
                                 std::strerror(e));
            }
            const double waited = std::chrono::duration<double>(Clock::now() - start).count();
            if (waited >= options.timeoutSeconds) {
                ::close(fd);
                return makeError(FormatError::Locked, 0,
                                 "'%s' is being saved by another program (it holds the file's "
                                 "lock); gave up after waiting %.1f s",
                                 path.c_str(), waited);
            }
            if (!announced && options.onWait) options.onWait();
            announced = true;
            std::this_thread::sleep_for(pause);
            pause = std::min(pause * 2, std::chrono::microseconds(20000));
        }
        // The holder we waited for may have renamed a new file over the path: then this lock
        // guards a file nobody reads any more; take the new one's.
        struct stat locked {}, now {};
        if (::fstat(fd, &locked) == 0 && ::stat(path.c_str(), &now) == 0 &&
            locked.st_dev == now.st_dev && locked.st_ino == now.st_ino) {
            FileLock lock;
            lock.mFd = fd;
            lock.mPath = path;
            return lock;
        }
        ::close(fd);
    }
}

FileLock::FileLock(FileLock&& other) noexcept : mFd(other.mFd), mPath(std::move(other.mPath)) {
    other.mFd = -1;
}

FileLock& FileLock::operator=(FileLock&& other) noexcept {
    if (this != &other) {
        release();
        mFd = other.mFd;
        mPath = std::move(other.mPath);
        other.mFd = -1;
    }
    return *this;
}

FileLock::~FileLock() { release(); }

void FileLock::release() {
    if (mFd >= 0) ::close(mFd); // closing the last descriptor of the open file drops the flock
    mFd = -1;
}

} // namespace pnb
