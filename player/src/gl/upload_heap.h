// upload_heap.h — process memory for the driver's copy of the scene, faulted 2 MiB at a time.
//
// Drivers that keep GL storage in process memory (Mesa llvmpipe, and the staging copies of many
// hardware drivers) allocate and zero every buffer and texture with malloc as it is created:
// each 4 KiB page is then a first-touch page fault, about 2.5 µs apiece on this project's test
// machine, which made up ~75 % of the upload of the 1 M-triangle load test. Growing malloc's heap
// once by the upload's size and advising transparent huge pages for that range makes the same
// bytes arrive in 2 MiB pages (see docs/PLAYER.md, "Upload memory").
//
// Not on a virtual machine whose guest hands free 2 MiB blocks back to the host (virtio-balloon
// free page reporting): there a huge page freed more than ~2 s earlier comes back only after
// the host has faulted in fresh memory for it, and the 1 M-triangle upload took 100–300 ms
// instead of 20 (docs/PLAYER.md). $PNB_HUGE_PAGES=on|off overrides the choice.
#pragma once

#include <cstdint>
#include <string>

#include "pnb/scene.h"

namespace pnb::player {

// Whether the upload heap asks for 2 MiB pages, and why.
struct HugePageChoice {
    bool use = false;
    std::string why; // "transparent huge pages", "free page reporting (virtio-balloon)", ...
};
// $PNB_HUGE_PAGES (on, off, auto: the default), then the kernel: transparent huge pages off
// → no; free page reporting active (the page_reporting module and a virtio balloon that offers
// VIRTIO_BALLOON_F_REPORTING) → no; otherwise yes. Read from the environment and /sys each call.
HugePageChoice hugePageChoice();

// Bytes the driver will allocate for the scene's textures and meshes (RGB8 counted as RGBA8,
// which drivers expand it to).
uint64_t estimateUploadBytes(const Scene& scene);

// While alive, every allocation comes from a heap grown by `bytes` up front (malloc makes no
// separate mappings), advised MADV_HUGEPAGE when hugePageChoice() says so and MADV_NOHUGEPAGE
// otherwise; when it is destroyed, malloc's settings return to their defaults and the part of
// the heap the driver did not use is given back.
// Does nothing below 4 MiB, on a C library other than glibc, or where the heap cannot grow.
class UploadHeap {
public:
    explicit UploadHeap(uint64_t bytes);
    ~UploadHeap();
    UploadHeap(const UploadHeap&) = delete;
    UploadHeap& operator=(const UploadHeap&) = delete;

    uint64_t hugePageBytes() const { return mAdvised; } // 0 if no 2 MiB pages were asked for
    bool active() const { return mActive; }            // false: too small, or not glibc
    // "N MiB in 2 MiB pages", "4 KiB pages (why)" or "not used (why)", for the load line.
    std::string describe() const;

private:
    bool mActive = false;
    uint64_t mAdvised = 0;
    HugePageChoice mHuge;
};

} // namespace pnb::player
