#include "pnb/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

namespace pnb {

std::string directoryOf(const std::string& path) {
    size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

std::string temporaryPathFor(const std::string& path) {
    static std::atomic<unsigned> counter{0};
    size_t slash = path.find_last_of('/');
    std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    return directoryOf(path) + "/." + name + ".tmp." + std::to_string(::getpid()) + "." +
           std::to_string(counter++);
}

Status writeFileAtomic(const std::string& path, std::span<const uint8_t> bytes) {
    if (path.empty() || path.back() == '/')
        return makeError(FormatError::IoError, 0, "cannot write '%s': not a file name",
                         path.c_str());
    const std::string tempPath = temporaryPathFor(path);
    int fd = ::open(tempPath.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0)
        return makeError(FormatError::IoError, 0, "cannot create a temporary file next to '%s': %s",
                         path.c_str(), std::strerror(errno));
    auto fail = [&](const char* what, const std::string& subject, int error) {
        if (fd >= 0) ::close(fd);
        ::unlink(tempPath.c_str());
        return makeError(FormatError::IoError, 0, "cannot %s '%s': %s", what, subject.c_str(),
                         std::strerror(error));
    };
    // Replacing a file keeps its permissions (the temporary is created 0644).
    struct stat existing {};
    if (::stat(path.c_str(), &existing) == 0 && S_ISREG(existing.st_mode))
        ::fchmod(fd, existing.st_mode & 07777);

    const uint8_t* p = bytes.data();
    size_t left = bytes.size();
    while (left > 0) {
        ssize_t n = ::write(fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return fail("write", tempPath, n < 0 ? errno : ENOSPC);
        p += n;
        left -= size_t(n);
    }
    // Data must be durable before the rename makes it visible, and the rename itself must be
    // durable (directory fsync), or a power cut could leave an empty or missing file.
    if (::fsync(fd) != 0) return fail("flush", tempPath, errno);
    int closeResult = ::close(fd);
    fd = -1;
    if (closeResult != 0) return fail("flush", tempPath, errno);
    if (::rename(tempPath.c_str(), path.c_str()) != 0)
        return fail("rename the temporary file to", path, errno);
    int dir = ::open(directoryOf(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
    return {};
}

} // namespace pnb
