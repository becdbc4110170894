// Remembered shader validations (shader_validation_cache.h).
//
// One file per key rather than one index file: entries never need a read-modify-write, two
// converters running at once (Ninja converting scenes in parallel) cannot lose each other's
// entries, and a damaged file costs one re-validation, not the whole cache.

#include "pnb_converter/shader_validation_cache.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <span>

#include "pnb/atomic_file.h"

namespace pnb::converter {

namespace {

namespace fs = std::filesystem;

// Bump when the entry format changes; old entries then read as corrupt and are replaced.
constexpr const char* kEntryHeader = "pnb shader validation v1\n";

} // namespace

ShaderValidationCache::ShaderValidationCache(std::string directory)
    : mDirectory(std::move(directory)) {}

std::string ShaderValidationCache::entryPath(const std::string& key) const {
    return mDirectory + "/shader-validation/" + key;
}

std::string ShaderValidationCache::entryContents(const std::string& key) {
    return std::string(kEntryHeader) + key + "\n";
}

bool ShaderValidationCache::contains(const std::string& key) {
    std::lock_guard lock(mMutex);
    if (mKnown.count(key)) return true;
    if (mDirectory.empty()) return false;
    const std::string path = entryPath(key), expected = entryContents(key);
    std::error_code ec;
    if (!fs::exists(path, ec)) return false;
    std::ifstream f(path, std::ios::binary);
    // One byte more than a valid entry holds, so a longer (appended-to) file is told apart.
    std::string bytes(expected.size() + 1, '\0');
    f.read(bytes.data(), std::streamsize(bytes.size()));
    if (f.bad() || (!f && !f.eof())) {
        mNotes.push_back("shader cache: cannot read " + path + "; validating again");
        return false;
    }
    bytes.resize(size_t(f.gcount()));
    if (bytes != expected) {
        mNotes.push_back("shader cache: " + path + " is damaged; validating again");
        return false;
    }
    mKnown.insert(key);
    return true;
}

void ShaderValidationCache::remember(const std::string& key) {
    std::lock_guard lock(mMutex);
    mKnown.insert(key);
    if (mDirectory.empty()) return;
    const std::string path = entryPath(key);
    std::error_code ec;
    fs::create_directories(fs::path(path).parent_path(), ec);
    if (ec) {
        mNotes.push_back("shader cache: cannot create " + fs::path(path).parent_path().string() +
                         ": " + ec.message() + " (not saved)");
        return;
    }
    // A directory or other non-file squatting on the entry's name cannot be renamed over.
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec)) fs::remove_all(path, ec);
    const std::string text = entryContents(key);
    Status st = writeFileAtomic(
        path, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    if (!isOk(st)) mNotes.push_back("shader cache: " + st.message + " (not saved)");
}

std::vector<std::string> ShaderValidationCache::takeNotes() {
    std::lock_guard lock(mMutex);
    return std::exchange(mNotes, {});
}

ShaderValidationCache& processShaderValidationCache(const std::string& directory) {
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<ShaderValidationCache>> caches;
    std::lock_guard lock(mutex);
    auto& cache = caches[directory];
    if (!cache) cache = std::make_unique<ShaderValidationCache>(directory);
    return *cache;
}

} // namespace pnb::converter
