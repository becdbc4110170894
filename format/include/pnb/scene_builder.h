// pnb/scene_builder.h — builds a Scene for writing, owning the strings and bulk data that the
// Scene's StringRefs and Blobs point at. Used by generators, the converter and tests.
#pragma once

#include <bit>
#include <cstring>
#include <deque>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "pnb/scene.h"

// Bulk arrays (vertex streams, indices, texels) are stored little-endian and viewed in place.
static_assert(std::endian::native == std::endian::little,
              "pnb bulk data views assume a little-endian host");

namespace pnb {

class SceneBuilder {
public:
    Scene scene;

    SceneBuilder() = default;
    SceneBuilder(const SceneBuilder&) = delete; // scene points into this object's storage
    SceneBuilder& operator=(const SceneBuilder&) = delete;

    // Index of `s` in the string table, adding it once.
    StringRef intern(std::string_view s) {
        auto it = mIndex.find(std::string(s));
        if (it != mIndex.end()) return it->second;
        const std::string& kept = mStrings.emplace_back(s);
        StringRef ref = StringRef(scene.strings.strings.size());
        scene.strings.strings.push_back(kept);
        mIndex.emplace(kept, ref);
        return ref;
    }

    // Keeps a copy of `data` alive as long as the builder and returns a Blob of it.
    template <class T> Blob keep(const std::vector<T>& data) {
        std::vector<std::byte>& b = mBlobs.emplace_back(data.size() * sizeof(T));
        if (!b.empty()) std::memcpy(b.data(), data.data(), b.size());
        return b;
    }
    Blob keep(std::string_view text) {
        std::vector<std::byte>& b = mBlobs.emplace_back(text.size());
        if (!b.empty()) std::memcpy(b.data(), text.data(), b.size());
        return b;
    }

private:
    std::deque<std::string> mStrings; // deque: stable addresses for the string_views
    std::deque<std::vector<std::byte>> mBlobs;
    std::unordered_map<std::string, StringRef> mIndex;
};

} // namespace pnb
