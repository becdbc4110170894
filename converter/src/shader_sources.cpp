// #include resolution over the embedded shader library.

#include <algorithm>
#include <set>

#include "pnb_converter/shader_permutations.h"
#include "render_shaders.h" // generated: kRenderShaders

namespace pnb::converter {

namespace {

std::string_view findFile(std::span<const ShaderFile> library, std::string_view name) {
    for (const ShaderFile& f : library)
        if (f.name == name) return f.text;
    return {};
}

std::string directoryOf(std::string_view name) {
    size_t slash = name.rfind('/');
    return slash == std::string_view::npos ? std::string() : std::string(name.substr(0, slash + 1));
}

// Resolves "a/../b" and "./" so the same file reached two ways is recognised as one.
std::string normalisePath(const std::string& path) {
    std::vector<std::string> parts;
    size_t start = 0;
    while (start <= path.size()) {
        size_t end = path.find('/', start);
        if (end == std::string::npos) end = path.size();
        std::string part = path.substr(start, end - start);
        if (part == "..") {
            if (!parts.empty()) parts.pop_back();
        } else if (!part.empty() && part != ".") {
            parts.push_back(part);
        }
        start = end + 1;
    }
    std::string out;
    for (const std::string& p : parts) out += (out.empty() ? "" : "/") + p;
    return out;
}

// Returns the quoted name of an `#include "name"` line, or empty.
std::string_view includeTarget(std::string_view line) {
    size_t p = line.find_first_not_of(" \t");
    if (p == std::string_view::npos || line.substr(p, 8) != "#include") return {};
    size_t open = line.find('"', p + 8), close = line.rfind('"');
    if (open == std::string_view::npos || close <= open) return {};
    return line.substr(open + 1, close - open - 1);
}

struct Resolver {
    std::span<const ShaderFile> library;
    ResolvedSource out;
    std::set<std::string> included;
    std::vector<std::string> stack;

    bool fail(ConvertError& error, std::string message) {
        error = {ConvertErrorKind::Input, std::move(message)};
        return false;
    }

    // Appends `name`'s lines; `skipVersion` drops the first #version line (the stage's own,
    // already emitted).
    bool append(const std::string& name, bool skipVersion, ConvertError& error) {
        if (std::find(stack.begin(), stack.end(), name) != stack.end())
            return fail(error, "shader include cycle: " + name + " includes itself via " +
                                   stack.back());
        std::string_view text = findFile(library, name);
        if (text.empty())
            return fail(error, "shader file '" + name + "' not found" +
                                   (stack.empty() ? "" : " (included from " + stack.back() + ")"));
        stack.push_back(name);
        uint32_t fileIndex = uint32_t(out.files.size());
        out.files.push_back(name);
        size_t lineNo = 0, pos = 0;
        bool versionSeen = !skipVersion;
        while (pos < text.size()) {
            size_t end = text.find('\n', pos);
            if (end == std::string_view::npos) end = text.size();
            std::string_view line = text.substr(pos, end - pos);
            pos = end + 1;
            ++lineNo;
            if (!versionSeen && line.rfind("#version", 0) == 0) {
                versionSeen = true; // already emitted, with the #line that follows it
                continue;
            }
            std::string_view target = includeTarget(line);
            if (target.empty()) {
                out.text.append(line).append("\n");
                continue;
            }
            std::string resolved = normalisePath(directoryOf(name) + std::string(target));
            if (findFile(library, resolved).empty()) resolved = normalisePath(std::string(target));
            if (included.insert(resolved).second) {
                out.text += "#line 1 " + std::to_string(out.files.size()) + "\n";
                if (!append(resolved, false, error)) return false;
            }
            out.text += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(fileIndex) +
                        "\n";
        }
        stack.pop_back();
        return true;
    }
};

} // namespace

std::span<const ShaderFile> builtinShaderFiles() {
    static const std::vector<ShaderFile> files = [] {
        std::vector<ShaderFile> v;
        for (const EmbeddedFile& f : kRenderShaders) v.push_back({f.name, f.text});
        return v;
    }();
    return files;
}

Result<ResolvedSource, ConvertError> resolveShaderSource(std::string_view name,
                                                         std::span<const ShaderFile> library) {
    std::string_view text = findFile(library, name);
    if (text.empty())
        return ConvertError{ConvertErrorKind::Input, "shader file '" + std::string(name) +
                                                         "' not found in the shader library"};
    if (text.rfind("#version", 0) != 0)
        return ConvertError{ConvertErrorKind::Input,
                            std::string(name) + ": the first line must be #version"};
    Resolver r{library, {}, {}, {}};
    r.out.text = std::string(text.substr(0, text.find('\n'))) + "\n#line 2 0\n";
    r.included.insert(std::string(name));
    ConvertError error;
    // The version line is emitted above; the defines the player inserts go between it and the
    // #line directive, so line numbers stay true.
    if (!r.append(std::string(name), true, error)) return error;
    // The file table that `#line N F` refers to, so the player can name the file in a compile
    // error (FORMAT.md, SHDR).
    std::string table = "// pnb-files:";
    for (const std::string& f : r.out.files) table += " " + f;
    r.out.text.insert(r.out.text.find('\n') + 1, table + "\n");
    return std::move(r.out);
}

} // namespace pnb::converter
