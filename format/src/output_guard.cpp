#include "pnb/output_guard.h"

#include <sys/stat.h>

#include <filesystem>
#include <optional>
#include <vector>

namespace pnb {

namespace {

namespace fs = std::filesystem;

// Where a name leads: its inode when the file exists, and its resolved path.
struct Place {
    std::optional<std::pair<dev_t, ino_t>> inode;
    std::string resolved;
};

Place placeOf(const std::string& path) {
    Place p;
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) p.inode = std::make_pair(st.st_dev, st.st_ino);
    std::error_code ec;
    fs::path resolved = fs::weakly_canonical(fs::absolute(path, ec), ec);
    p.resolved = ec ? fs::absolute(path).lexically_normal().string() : resolved.string();
    return p;
}

bool samePlace(const Place& a, const Place& b) {
    if (a.inode && b.inode) return *a.inode == *b.inode;
    return a.resolved == b.resolved;
}

Status conflict(const RoleFile& output, const RoleFile& other, const Place& where,
                const char* what) {
    return Error{FormatError::OutputConflict, 0,
                 output.role + " '" + output.path + "' is " + what + " " + other.role + " '" +
                     other.path + "' (" + where.resolved +
                     "): writing it would replace it. Choose another output"};
}

} // namespace

Status checkOutputs(std::span<const RoleFile> inputs, std::span<const RoleFile> outputs) {
    std::vector<Place> in, out;
    for (const RoleFile& f : inputs) in.push_back(f.path.empty() ? Place{} : placeOf(f.path));
    for (size_t o = 0; o < outputs.size(); ++o) {
        out.push_back(outputs[o].path.empty() ? Place{} : placeOf(outputs[o].path));
        if (outputs[o].path.empty()) continue;
        for (size_t i = 0; i < inputs.size(); ++i)
            if (!inputs[i].path.empty() && samePlace(out[o], in[i]))
                return conflict(outputs[o], inputs[i], out[o], "the same file as");
        for (size_t k = 0; k < o; ++k)
            if (!outputs[k].path.empty() && samePlace(out[o], out[k]))
                return conflict(outputs[o], outputs[k], out[o], "the same file as");
    }
    return {};
}

Status checkInputs(std::span<const RoleFile> inputs) {
    for (const RoleFile& f : inputs) {
        struct stat st {};
        if (f.path.empty() || ::stat(f.path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) continue;
        const char* what = S_ISFIFO(st.st_mode)  ? "a FIFO (named pipe)"
                           : S_ISDIR(st.st_mode) ? "a directory"
                           : S_ISSOCK(st.st_mode) ? "a socket"
                                                  : "a device";
        return Error{FormatError::IoError, 0,
                     f.role + " '" + f.path + "' is " + what +
                         ", not a regular file (reading it could wait forever or never end)"};
    }
    return {};
}

} // namespace pnb
