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

int imageForReference(const std::filesystem::path& sourceDir, const std::string& ref,
                      const std::string& what, IrScene& scene,
                      std::map<std::string, int>& imageByPath) {
    const auto resolved = resolveReference(sourceDir, ref);
    if (!resolved) {
        scene.warnings.push_back(
            format("%s: texture '%s' not found; ignored", what.c_str(), ref.c_str()));
        return -1;
    }
    if (resolved->byNameOnly) {
        scene.warnings.push_back(format("%s: texture '%s' not found; using '%s' (same file name, "
                                        "next to the source file)",
                                        what.c_str(), ref.c_str(),
                                        resolved->path.string().c_str()));
    }
    const std::string key = resolved->path.string();
    if (auto it = imageByPath.find(key); it != imageByPath.end()) return it->second;
    IrImage image;
    image.name = resolved->path.filename().string();
    image.path = key;
    scene.images.push_back(std::move(image));
    const int index = int(scene.images.size() - 1);
    imageByPath.emplace(key, index);
    return index;
}

} // namespace pnb::converter::import_detail
