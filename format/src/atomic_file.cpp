#include "pnb/atomic_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <string_view>

namespace pnb {

std::string directoryOf(const std::string& path) {
    size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

namespace {

std::string baseName(const std::string& path) {
    size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

// ".<name>.tmp.<digits>.<digits>": only names this code makes, never a user's file.
bool isTemporaryOf(std::string_view entry, const std::string& name) {
    const std::string prefix = "." + name + ".tmp.";
    if (entry.substr(0, prefix.size()) != prefix) return false;
    std::string_view rest = entry.substr(prefix.size());
    size_t dot = rest.find('.');
    auto digits = [](std::string_view d) {
        return !d.empty() && d.find_first_not_of("0123456789") == std::string_view::npos;
    };
    return dot != std::string_view::npos && digits(rest.substr(0, dot)) &&
           digits(rest.substr(dot + 1));
}

} // namespace

size_t removeStaleTemporaries(const std::string& path) {
    const std::string dirPath = directoryOf(path), name = baseName(path);
    DIR* dir = ::opendir(dirPath.c_str());
    if (!dir) return 0;
    size_t removed = 0;
    const time_t now = ::time(nullptr);
    while (const dirent* e = ::readdir(dir)) {
        if (!isTemporaryOf(e->d_name, name)) continue;
        const std::string temp = dirPath + "/" + e->d_name;
        int fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
        if (fd < 0) continue;
        struct stat st {};
        // A live writer holds LOCK_EX; one that has just created its file and not yet locked it
        // is younger than a second.
        if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
            st.st_nlink > 0 && now - st.st_ctime >= 1 && ::unlink(temp.c_str()) == 0)
            ++removed;
        ::close(fd);
    }
    ::closedir(dir);
    return removed;
}

Result<TemporaryFile> createTemporaryFor(const std::string& path) {
    static std::atomic<unsigned> counter{0};
    removeStaleTemporaries(path);
    TemporaryFile t;
    t.path = directoryOf(path) + "/." + baseName(path) + ".tmp." + std::to_string(::getpid()) +
             "." + std::to_string(counter++);
    t.fd = ::open(t.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (t.fd < 0 || ::flock(t.fd, LOCK_EX | LOCK_NB) != 0) {
        int e = errno;
        if (t.fd >= 0) {
            ::close(t.fd);
            ::unlink(t.path.c_str());
        }
        return makeError(FormatError::IoError, 0, "cannot create a temporary file next to '%s': %s",
                         path.c_str(), std::strerror(e));
    }
    return t;
}

Status writeFileAtomic(const std::string& path, std::span<const uint8_t> bytes) {
    if (path.empty() || path.back() == '/')
        return makeError(FormatError::IoError, 0, "cannot write '%s': not a file name",
                         path.c_str());
    auto temp = createTemporaryFor(path);
    if (!temp) return temp.error();
    const std::string tempPath = temp->path;
    int fd = temp->fd;
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
    // The file stays open (and flock-ed) until renamed, so no other writer takes it for stale.
    if (::fsync(fd) != 0) return fail("flush", tempPath, errno);
    if (::rename(tempPath.c_str(), path.c_str()) != 0)
        return fail("rename the temporary file to", path, errno);
    ::close(fd); // fsync succeeded: nothing is left to report
    int dir = ::open(directoryOf(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
    return {};
}

} // namespace pnb
