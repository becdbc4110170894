// stream_ring.h — per-frame uniform and storage data (frame block, lights, object blocks) in one
// persistently mapped buffer split into kSections frame sections. A fence per section keeps the
// CPU from overwriting data the GPU may still read, without re-specifying buffers each frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "pnb_player/gl_handles.h"

namespace pnb::player {

class StreamRing {
public:
    static constexpr int kSections = 3;

    StreamRing() = default;
    ~StreamRing();
    StreamRing(const StreamRing&) = delete;
    StreamRing& operator=(const StreamRing&) = delete;

    // (Re)allocates if a section must hold more than it does. `alignment`: offset granularity.
    // False when the GL cannot allocate or map that much (GL_OUT_OF_MEMORY, a null mapping):
    // the ring is then empty (no section, nothing mapped) and the caller asks for less or stops.
    [[nodiscard]] bool reserve(size_t sectionBytes, size_t alignment);
    // Starts a frame: waits for (normally long-finished) GPU use of the next section.
    void beginFrame();
    // Reserves `bytes` in the current section for the caller to fill; returns the buffer offset
    // and (in `mapped`) where to write.
    size_t allocate(size_t bytes, std::byte*& mapped);
    // Copies `bytes` into the current section; returns the buffer offset.
    size_t push(const void* data, size_t bytes) {
        std::byte* dst = nullptr;
        size_t offset = allocate(bytes, dst);
        std::memcpy(dst, data, bytes);
        return offset;
    }
    // Fences the section.
    void endFrame();

    GLuint buffer() const { return mBuffer.id(); }
    size_t totalBytes() const { return mSectionBytes * kSections; }

private:
    GlHandle mBuffer;
    std::byte* mMapped = nullptr;
    size_t mSectionBytes = 0, mAlignment = 256, mUsed = 0;
    int mSection = 0;
    GLsync mFences[kSections] = {};
};

} // namespace pnb::player
