// image_prefetch.h — decodes a scene's image files on a background thread while the importer is
// still parsing, so that the texture stage finds them decoded. Internal.
//
// Why: on the 1M-triangle OBJ the parse is one thread for ~40 % of the conversion while the
// other core idles, and decoding the ten PNG textures is ~20 % (docs/CONVERTER.md, "Speed"). An
// OBJ names its MTL, and so every texture file, in its first lines: the importer reports each
// file as it learns of it (ImageFileFound, importers.h) and the decode runs beside the parse.
//
// Determinism: a decode depends on the file's bytes and maxSourceTexels only, not on the thread
// that runs it, so a prefetched image is the image processTextures would have decoded itself;
// the container's bytes do not change (ConvertPrefetch.* tests). Anything unusual falls back to
// the ordinary decode in processTextures, which then reports its usual errors: a failed or
// refused prefetch is forgotten, and an image the texture stage's memory share would refuse
// (checked again by take()) is dropped.
//
// Memory: decoded images wait (as float RGBA, 16 bytes a texel) until the texture stage takes
// them; the prefetch holds at most `maxHeldBytes` of them and decodes nothing that would exceed
// it. processTextures takes that amount off the budget its jobs share (texture_processing.cpp),
// so both together stay within --max-memory.
//
// Does NOT do: embedded images (a glTF's are in memory already; only files are prefetched),
// more than one background thread (the parse holds the other core).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "texture_internal.h"

namespace pnb::converter {

class ImagePrefetch {
public:
    ImagePrefetch(uint64_t maxSourceTexels, uint64_t maxHeldBytes);
    ~ImagePrefetch(); // abandons queued files, waits for the decode in progress
    ImagePrefetch(const ImagePrefetch&) = delete;
    ImagePrefetch& operator=(const ImagePrefetch&) = delete;

    // Queues the image file at `path` (as IrImage::path will hold it); a path queued before is
    // ignored. Starts the background thread on the first call.
    void add(const std::string& path);

    // The decoded image of `path`, if it was queued, decoded successfully and `admit` admits
    // its header; waits while it is being decoded, skips it if it was not started yet. Each
    // image is handed out once. nullopt: the caller decodes it itself.
    std::optional<texture_detail::DecodedImage> take(const std::string& path,
                                                     const texture_detail::AdmitImage& admit);

    // Waits until every queued file has been decoded (for tests: the converter never waits,
    // take() strikes files not started yet).
    void finish();

    // Whether add() was ever called (else there is nothing to take, nor to budget for).
    bool used() {
        std::lock_guard lock(mMutex);
        return !mItems.empty();
    }

    // How many images take() handed out (the summary's note, and tests).
    size_t taken() {
        std::lock_guard lock(mMutex);
        return mTaken;
    }

    // What processTextures leaves out of the budget its jobs share.
    uint64_t maxHeldBytes() const { return mMaxHeldBytes; }

private:
    enum class State { Queued, Decoding, Done };
    struct Item {
        State state = State::Queued;
        std::optional<texture_detail::DecodedImage> image; // when Done and successful
        texture_detail::ImageHeader header;
        uint64_t bytes = 0; // held by `image`
    };
    void run();

    const uint64_t mMaxSourceTexels, mMaxHeldBytes;
    std::mutex mMutex;
    std::condition_variable mChanged;
    std::map<std::string, Item> mItems;
    std::deque<std::string> mQueue;
    uint64_t mHeldBytes = 0;
    size_t mTaken = 0;
    bool mStopping = false;
    std::thread mThread;
};

} // namespace pnb::converter
