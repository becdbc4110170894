// CompressionMemo (pnb/compression_memo.h): a hash map from payload to zstd frame, confirmed
// byte for byte on every hit.

#include "pnb/compression_memo.h"

#include <algorithm>

#include <xxhash.h>

namespace pnb {

namespace {

uint64_t keyOf(std::span<const std::byte> raw, int level) {
    return XXH3_64bits_withSeed(raw.data(), raw.size(), uint64_t(uint32_t(level)));
}

} // namespace

CompressionMemo::CompressionMemo(size_t maxEntryBytes, size_t maxTotalBytes)
    : mMaxEntryBytes(maxEntryBytes), mMaxTotalBytes(maxTotalBytes) {}

std::optional<std::vector<std::byte>> CompressionMemo::find(std::span<const std::byte> raw,
                                                            int level) const {
    if (raw.size() > mMaxEntryBytes) return std::nullopt;
    const uint64_t key = keyOf(raw, level);
    std::lock_guard lock(mMutex);
    auto [first, last] = mEntries.equal_range(key);
    for (auto it = first; it != last; ++it) {
        const Entry& e = it->second;
        if (e.level == level && e.raw.size() == raw.size() &&
            std::equal(e.raw.begin(), e.raw.end(), raw.begin())) {
            ++mHits;
            return e.frame;
        }
    }
    return std::nullopt;
}

void CompressionMemo::remember(std::span<const std::byte> raw, int level,
                               std::span<const std::byte> frame) {
    if (raw.size() > mMaxEntryBytes) return;
    const uint64_t key = keyOf(raw, level);
    std::lock_guard lock(mMutex);
    if (mTotalBytes + raw.size() + frame.size() > mMaxTotalBytes) return;
    auto [first, last] = mEntries.equal_range(key);
    for (auto it = first; it != last; ++it) {
        const Entry& e = it->second;
        if (e.level == level && e.raw.size() == raw.size() &&
            std::equal(e.raw.begin(), e.raw.end(), raw.begin()))
            return; // another thread remembered it first
    }
    mEntries.emplace(key, Entry{level, {raw.begin(), raw.end()}, {frame.begin(), frame.end()}});
    mTotalBytes += raw.size() + frame.size();
}

size_t CompressionMemo::hits() const {
    std::lock_guard lock(mMutex);
    return mHits;
}

} // namespace pnb
