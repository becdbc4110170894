// image_prefetch.cpp — ImagePrefetch (image_prefetch.h): one background thread decoding the
// queued image files in the order they were reported.
#include "image_prefetch.h"

#include <algorithm>
#include <exception>
#include <filesystem>

namespace pnb::converter {

using namespace texture_detail;

ImagePrefetch::ImagePrefetch(uint64_t maxSourceTexels, uint64_t maxHeldBytes)
    : mMaxSourceTexels(maxSourceTexels), mMaxHeldBytes(maxHeldBytes) {}

ImagePrefetch::~ImagePrefetch() {
    {
        std::lock_guard lock(mMutex);
        mStopping = true;
    }
    mChanged.notify_all();
    if (mThread.joinable()) mThread.join();
}

void ImagePrefetch::add(const std::string& path) {
    std::lock_guard lock(mMutex);
    if (mStopping || !mItems.emplace(path, Item{}).second) return;
    mQueue.push_back(path);
    if (!mThread.joinable()) {
        try {
            mThread = std::thread([this] { run(); });
        } catch (const std::exception&) {
            mQueue.clear(); // no thread: everything is decoded by the texture stage
            mItems.clear();
            return;
        }
    }
    mChanged.notify_all();
}

void ImagePrefetch::run() {
    std::unique_lock lock(mMutex);
    for (;;) {
        mChanged.wait(lock, [&] { return mStopping || !mQueue.empty(); });
        if (mStopping) return;
        const std::string path = mQueue.front();
        mQueue.pop_front();
        mItems[path].state = State::Decoding;
        const uint64_t room = mMaxHeldBytes - mHeldBytes;
        lock.unlock();

        // Admitted only if its decoded float RGBA fits in what the prefetch may still hold.
        ImageHeader header;
        auto admit = [&](const ImageHeader& h) -> std::optional<std::string> {
            header = h;
            if (h.texels() > room / 16) return std::string("no room to prefetch");
            return std::nullopt;
        };
        std::optional<DecodedImage> decoded;
        try {
            IrImage image;
            image.name = std::filesystem::path(path).filename().string();
            image.path = path;
            auto r = decodeImage(image, mMaxSourceTexels, admit);
            if (r) decoded = std::move(*r);
        } catch (const std::exception&) {
            // forgotten: the texture stage decodes it again and reports what goes wrong
        }

        lock.lock();
        Item& item = mItems[path];
        item.state = State::Done;
        if (decoded) {
            item.bytes = uint64_t(decoded->image.texels.size()) * sizeof(float);
            item.header = header;
            item.image = std::move(decoded);
            mHeldBytes += item.bytes;
        }
        mChanged.notify_all();
    }
}

void ImagePrefetch::finish() {
    std::unique_lock lock(mMutex);
    mChanged.wait(lock, [&] {
        if (!mQueue.empty()) return false;
        for (const auto& [path, item] : mItems)
            if (item.state != State::Done) return false;
        return true;
    });
}

std::optional<DecodedImage> ImagePrefetch::take(const std::string& path, const AdmitImage& admit) {
    std::unique_lock lock(mMutex);
    auto it = mItems.find(path);
    if (it == mItems.end()) return std::nullopt;
    if (it->second.state == State::Queued) { // not started: the caller is as fast
        std::erase(mQueue, path);
        it->second.state = State::Done;
        return std::nullopt;
    }
    mChanged.wait(lock, [&] { return it->second.state == State::Done; });
    Item& item = it->second;
    if (!item.image) return std::nullopt;
    std::optional<DecodedImage> out = std::move(item.image);
    item.image.reset();
    mHeldBytes -= item.bytes;
    const ImageHeader header = item.header;
    lock.unlock();
    // The texture stage's own limit, as its decode would have applied it.
    if (admit && admit(header)) return std::nullopt;
    lock.lock();
    ++mTaken;
    return out;
}

} // namespace pnb::converter
