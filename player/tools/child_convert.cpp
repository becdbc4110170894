#include "child_convert.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

extern char** environ;

namespace pnb::player {

namespace fs = std::filesystem;

bool isConvertibleSource(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".gltf" || ext == ".glb" || ext == ".obj";
}

std::string findConverter() {
    if (const char* env = std::getenv("PNB_CONVERT"); env && *env) return env;
    std::error_code ec;
    fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        fs::path beside = self.parent_path() / "pnb-convert";
        if (access(beside.c_str(), X_OK) == 0) return beside.string();
    }
    const char* path = std::getenv("PATH");
    for (std::string dirs = path ? path : ""; !dirs.empty();) {
        size_t colon = dirs.find(':');
        std::string dir = dirs.substr(0, colon);
        dirs = colon == std::string::npos ? "" : dirs.substr(colon + 1);
        if (dir.empty()) dir = ".";
        std::string candidate = dir + "/pnb-convert";
        if (access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return "";
}

TempContainer& TempContainer::operator=(TempContainer&& o) noexcept {
    if (this != &o) {
        TempContainer dying(std::move(*this));
        mDir = std::move(o.mDir);
        mFile = std::move(o.mFile);
        o.mDir.clear();
    }
    return *this;
}

TempContainer::~TempContainer() {
    if (mDir.empty()) return;
    std::error_code ec;
    fs::remove_all(mDir, ec);
}

PlayResult<TempContainer> convertInChild(const std::string& source, const std::string& converter) {
    if (converter.empty())
        return PlayError{PlayErrorKind::Input,
                         "cannot open " + source + ": pnb-convert was not found (beside pnb-play, on PATH, "
                         "or $PNB_CONVERT); convert it with 'pnb-convert " + source +
                             " -o OUT.pnb' and open the .pnb"};
    std::error_code ec;
    fs::path tmpRoot = fs::temp_directory_path(ec);
    if (ec) tmpRoot = "/tmp";
    std::string pattern = (tmpRoot / "pnb-play-XXXXXX").string();
    std::vector<char> dirBuf(pattern.begin(), pattern.end());
    dirBuf.push_back('\0');
    if (!mkdtemp(dirBuf.data()))
        return PlayError{PlayErrorKind::Io, "cannot create a temporary directory in " + tmpRoot.string() + ": " +
                                                std::strerror(errno)};
    std::string dir = dirBuf.data();
    TempContainer out(dir, dir + "/" + fs::path(source).stem().string() + ".pnb");

    std::vector<std::string> args = {converter, source, "-o", out.file(), "-q"};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    int rc = posix_spawn(&pid, converter.c_str(), nullptr, nullptr, argv.data(), environ);
    if (rc != 0)
        return PlayError{PlayErrorKind::Input, "cannot open " + source + ": cannot run " + converter + ": " +
                                                   std::strerror(rc)};
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            return PlayError{PlayErrorKind::Input, "cannot open " + source + ": waiting for " + converter + ": " +
                                                       std::strerror(errno)};
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return out;
    std::string how = WIFEXITED(status) ? "exit code " + std::to_string(WEXITSTATUS(status))
                                        : "signal " + std::to_string(WTERMSIG(status));
    return PlayError{PlayErrorKind::Input, "cannot open " + source + ": pnb-convert failed (" + how +
                                               "; its message is above)"};
}

} // namespace pnb::player
