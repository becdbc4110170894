// converter/src/import_paths.cpp — file references inside source files (import_paths.h).
#include "import_paths.h"

#include <algorithm>
#include <cctype>
#include <cstdarg>
#include <cstdio>

namespace pnb::converter::import_detail {

namespace fs = std::filesystem;

std::string format(const char* fmt, ...) {
    va_list args;
    va_start(args, fmt);
    va_list copy;
    va_copy(copy, args);
    int size = std::vsnprintf(nullptr, 0, fmt, copy);
    va_end(copy);
    std::string out(size > 0 ? size_t(size) : 0, '\0');
    if (size > 0) std::vsnprintf(out.data(), out.size() + 1, fmt, args);
    va_end(args);
    return out;
}

bool iequals(const std::string& a, const std::string& b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

bool isRegularFile(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec);
}

std::optional<fs::path> findIgnoringCase(const fs::path& base, const fs::path& rel) {
    fs::path current = base.empty() ? fs::path(".") : base;
    for (const fs::path& component : rel) {
        const std::string name = component.string();
        if (name.empty() || name == "." || name == "/") continue;
        if (name == "..") {
            current /= "..";
            continue;
        }
        std::error_code ec;
        if (fs::exists(current / component, ec)) {
            current /= component;
            continue;
        }
        std::optional<fs::path> match;
        fs::directory_iterator it(current, ec);
        for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
            fs::path candidate = it->path().filename();
            if (iequals(candidate.string(), name) && (!match || candidate < *match)) {
                match = candidate;
            }
        }
        if (!match) return std::nullopt;
        current /= *match;
    }
    if (!isRegularFile(current)) return std::nullopt;
    return current.lexically_normal();
}

std::optional<ResolvedPath> resolveReference(const fs::path& sourceDir, std::string ref) {
    std::replace(ref.begin(), ref.end(), '\\', '/');
    while (!ref.empty() && std::isspace(static_cast<unsigned char>(ref.back()))) ref.pop_back();
    size_t start = 0;
    while (start < ref.size() && std::isspace(static_cast<unsigned char>(ref[start]))) ++start;
    ref.erase(0, start);
    if (ref.rfind("file://", 0) == 0) ref.erase(0, 7);
    if (ref.empty()) return std::nullopt;

    // "C:/Users/..." is an absolute path from another machine: only its file name can help.
    const bool foreignAbsolute = ref.size() >= 3 && ref[1] == ':' && ref[2] == '/' &&
                                 std::isalpha(static_cast<unsigned char>(ref[0]));
    const fs::path refPath(ref);
    if (!foreignAbsolute) {
        if (refPath.is_absolute()) {
            if (isRegularFile(refPath)) return ResolvedPath{refPath.lexically_normal()};
            if (auto p = findIgnoringCase(refPath.root_path(), refPath.relative_path())) {
                return ResolvedPath{*p};
            }
        } else {
            fs::path exact = (sourceDir / refPath).lexically_normal();
            if (isRegularFile(exact)) return ResolvedPath{exact};
            if (auto p = findIgnoringCase(sourceDir, refPath)) return ResolvedPath{*p};
        }
    }
    if (refPath.has_filename() && refPath.filename() != refPath) {
        if (auto p = findIgnoringCase(sourceDir, refPath.filename())) {
            return ResolvedPath{*p, true};
        }
    }
    return std::nullopt;
}

} // namespace pnb::converter::import_detail
