// pnb_converter/shader_validation_cache.h — remembers which shader programs glslang accepted, so
// that each program variant is validated once per content, not once per conversion.
//
// A key is a hash of everything the verdict depends on (computed by validateShaders: every
// stage's exact text with its defines, the stages, the glslang version and our validation
// settings). Keys live in memory for the life of the process (a batch conversion validates each
// variant once) and, when a directory is given, as one small file per key under
// <directory>/shader-validation/ (later processes skip glslang for variants seen before).
//
// Only successes are remembered: a failing program is compiled again every time, so its error
// message is always fresh. The disk is best effort. An entry that is missing, unreadable,
// truncated or altered is a miss (the program is validated again and the entry rewritten); a
// directory that cannot be created or written only costs the saving. None of these fails a
// conversion; each leaves a note (notes()) that `pnb-convert -v` prints.
//
// Thread safety: every member may be called from several threads.
#pragma once

#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace pnb::converter {

class ShaderValidationCache {
public:
    // `directory` "" keeps the cache in memory only.
    explicit ShaderValidationCache(std::string directory);

    // True if `key` was remembered by this object or is stored intact on disk.
    bool contains(const std::string& key);
    // Remembers `key` in memory and stores it on disk (atomically; failures become notes).
    void remember(const std::string& key);

    // Problems met with the disk since the last call, for verbose output; clears them.
    std::vector<std::string> takeNotes();

    const std::string& directory() const { return mDirectory; }

    // The entry file of `key` and the exact bytes a valid entry holds (for tests).
    std::string entryPath(const std::string& key) const;
    static std::string entryContents(const std::string& key);

private:
    std::string mDirectory; // "" = memory only
    std::mutex mMutex;
    std::set<std::string> mKnown;
    std::vector<std::string> mNotes;
};

// One cache per directory for the whole process, so conversions in one batch share what they
// validated. `directory` as for the constructor.
ShaderValidationCache& processShaderValidationCache(const std::string& directory);

} // namespace pnb::converter
