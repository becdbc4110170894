// upload_heap.h — process memory for the driver's copy of the scene, faulted 2 MiB at a time.
//
// Drivers that keep GL storage in process memory (Mesa llvmpipe, and the staging copies of many
// hardware drivers) allocate and zero every buffer and texture with malloc as it is created:
// each 4 KiB page is then a first-touch page fault, about 2.5 µs apiece on this project's test
// machine, which made up ~75 % of the upload of the 1 M-triangle load test. Growing malloc's heap
// once by the upload's size and advising transparent huge pages for that range makes the same
// bytes arrive in 2 MiB pages (see docs/PLAYER.md, "Loading").
#pragma once

#include <cstdint>

#include "pnb/scene.h"

namespace pnb::player {

// Bytes the driver will allocate for the scene's textures and meshes (RGB8 counted as RGBA8,
// which drivers expand it to).
uint64_t estimateUploadBytes(const Scene& scene);

// While alive, every allocation comes from a heap grown by `bytes` up front and advised
// MADV_HUGEPAGE (malloc makes no separate mappings); when it is destroyed, malloc's settings
// return to their defaults and the part of the heap the driver did not use is given back.
// Does nothing below 4 MiB, on a C library other than glibc, or where the heap cannot grow.
class UploadHeap {
public:
    explicit UploadHeap(uint64_t bytes);
    ~UploadHeap();
    UploadHeap(const UploadHeap&) = delete;
    UploadHeap& operator=(const UploadHeap&) = delete;

    uint64_t hugePageBytes() const { return mAdvised; } // 0 if nothing was reserved

private:
    bool mActive = false;
    uint64_t mAdvised = 0;
};

} // namespace pnb::player
