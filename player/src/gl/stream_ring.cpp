#include "gl/stream_ring.h"

#include <cstdio>
#include <cstdlib>

#include "gl/gl_allocation.h"

namespace pnb::player {

StreamRing::~StreamRing() {
    for (GLsync& f : mFences)
        if (f) glDeleteSync(f);
    if (mMapped) glUnmapNamedBuffer(mBuffer.id());
}

bool StreamRing::reserve(size_t sectionBytes, size_t alignment) {
    mAlignment = alignment;
    sectionBytes = (sectionBytes + alignment - 1) / alignment * alignment;
    if (sectionBytes <= mSectionBytes) return true;
    for (GLsync& f : mFences) {
        if (f) {
            glClientWaitSync(f, GL_SYNC_FLUSH_COMMANDS_BIT, ~GLuint64(0));
            glDeleteSync(f);
            f = nullptr;
        }
    }
    if (mMapped) glUnmapNamedBuffer(mBuffer.id());
    mMapped = nullptr;
    mSectionBytes = sectionBytes;
    mBuffer = createBuffer();
    GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    clearGlErrors();
    glNamedBufferStorage(mBuffer.id(), GLsizeiptr(totalBytes()), nullptr, flags);
    if (checkGlAllocation("the per-frame stream ring", totalBytes()))
        mMapped = static_cast<std::byte*>(
            glMapNamedBufferRange(mBuffer.id(), 0, GLsizeiptr(totalBytes()), flags));
    if (!mMapped) { // a ring that cannot be written to must not be handed out (it crashed)
        mBuffer = {};
        mSectionBytes = 0;
        return false;
    }
    glObjectLabel(GL_BUFFER, mBuffer.id(), -1, "per-frame stream ring");
    return true;
}

void StreamRing::beginFrame() {
    mSection = (mSection + 1) % kSections;
    if (GLsync& f = mFences[mSection]; f) {
        glClientWaitSync(f, GL_SYNC_FLUSH_COMMANDS_BIT, ~GLuint64(0));
        glDeleteSync(f);
        f = nullptr;
    }
    mUsed = 0;
}

size_t StreamRing::allocate(size_t bytes, std::byte*& mapped) {
    // Past the section is the next frame's data or past the mapping: a reservation that missed a
    // pass must stop here, not corrupt memory quietly (it did: the height map and the probes'
    // occupancy grid together pushed more object blocks than were reserved).
    if (mUsed + bytes > mSectionBytes) {
        std::fprintf(stderr, "pnb-play: internal error: the per-frame stream ring's %zu bytes were reserved too "
                             "small (%zu used, %zu more asked)\n", mSectionBytes, mUsed, bytes);
        std::abort();
    }
    size_t offset = size_t(mSection) * mSectionBytes + mUsed;
    mapped = mMapped + offset;
    mUsed += (bytes + mAlignment - 1) / mAlignment * mAlignment;
    return offset;
}

void StreamRing::endFrame() { mFences[mSection] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0); }

} // namespace pnb::player
