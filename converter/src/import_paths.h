// converter/src/import_paths.h — what the assimp and OBJ importers share: resolving the file
// references written inside a source file (textures, mtllib) and printf-style messages.
// Private to converter/src.
//
// Resolution order (resolveReference): '\' → '/', surrounding blanks and "file://" removed;
// then relative to the source file's directory (or as the absolute path it is), first exactly,
// then case-insensitively component by component (exports from Windows, where "Tex/Wood.PNG"
// and "tex/wood.png" are the same file); then the file name alone next to the source file
// (absolute paths from another machine, "C:/Users/..."), which the caller reports as a warning.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "pnb_converter/scene_ir.h"

namespace pnb::converter::import_detail {

// printf into a std::string.
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

// ASCII case-insensitive equality.
bool iequals(const std::string& a, const std::string& b);

bool isRegularFile(const std::filesystem::path& p);

// Walks `rel` one component at a time from `base`, taking the exact name when it exists and
// otherwise the directory entry equal to it ignoring ASCII case. Several case variants: the
// smallest name, so the result does not depend on directory order. nullopt unless the result is
// a regular file.
std::optional<std::filesystem::path> findIgnoringCase(const std::filesystem::path& base,
                                                      const std::filesystem::path& rel);

struct ResolvedPath {
    std::filesystem::path path;
    bool byNameOnly = false; // found only as the bare file name next to the source
};

// Resolves a file reference written inside a source file whose directory is `sourceDir` (see the
// header block for the order); nullopt when nothing matches.
std::optional<ResolvedPath> resolveReference(const std::filesystem::path& sourceDir,
                                             std::string ref);

// The scene image for texture file reference `ref`, resolved as above and added to `scene` once
// per resolved path (`imageByPath` remembers them); -1 with a warning in scene.warnings when
// nothing matches, and a warning when only the bare file name matched. `what` starts each
// warning ("material 'wood'").
int imageForReference(const std::filesystem::path& sourceDir, const std::string& ref,
                      const std::string& what, IrScene& scene,
                      std::map<std::string, int>& imageByPath);

} // namespace pnb::converter::import_detail
