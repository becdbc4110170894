// pnb/compression_memo.h — remembers zstd results, so that a process writing many containers
// (pnb-convert's batch mode) compresses a payload it has compressed before only once.
//
// Why: every container carries the packed shader programs (SHDR chunks, zstd level 9), whose
// bytes rarely depend on the scene; compressing them again was ~17 % of a batch's CPU time
// (docs/CONVERTER.md, "Speed"). zstd is deterministic (same input, level and library → same
// frame), so a remembered frame is the frame ZSTD_compress would return: the bytes written do
// not change.
//
// Does NOT do: eviction (once full, new payloads are compressed and not remembered), any I/O.
// A hit is confirmed by comparing the whole payload, not only its hash. Thread-safe.
#pragma once

#include <cstddef>
#include <mutex>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

namespace pnb {

class CompressionMemo {
public:
    // Payloads larger than `maxEntryBytes` are never remembered (meshes and textures, which
    // differ per scene); remembering stops once payloads and frames held reach `maxTotalBytes`.
    explicit CompressionMemo(size_t maxEntryBytes = size_t(1) << 20,
                             size_t maxTotalBytes = size_t(64) << 20);

    // The frame remembered for `raw` at `level`, if any.
    std::optional<std::vector<std::byte>> find(std::span<const std::byte> raw, int level) const;
    // Remembers `frame` as the result of compressing `raw` at `level` (if it fits the limits).
    void remember(std::span<const std::byte> raw, int level, std::span<const std::byte> frame);

    size_t hits() const;

private:
    struct Entry {
        int level = 0;
        std::vector<std::byte> raw, frame;
    };
    const size_t mMaxEntryBytes, mMaxTotalBytes;
    mutable std::mutex mMutex;
    std::unordered_multimap<uint64_t, Entry> mEntries; // by XXH3-64 of the payload
    size_t mTotalBytes = 0;
    mutable size_t mHits = 0;
};

} // namespace pnb
