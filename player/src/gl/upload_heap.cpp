#include "gl/upload_heap.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#if defined(__GLIBC__) && defined(__linux__)
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#define PNB_UPLOAD_HEAP 1
#endif

namespace pnb::player {

uint64_t estimateUploadBytes(const Scene& scene) {
    uint64_t bytes = 0;
    for (const TextureMip& mip : scene.textureMips) {
        const TextureDesc& desc = scene.textures[mip.texture];
        uint64_t level = textureLevelSizeBytes(desc.format, mip.width, mip.height, desc.layers);
        bytes += desc.format == TextureFormat::RGB8 ? level / 3 * 4 : level;
    }
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = fullDetailMesh(scene, m); // what a full load uploads
        for (const VertexStream& s : mesh.streams) bytes += s.data.size() + 16;
        bytes += mesh.indices.size();
    }
    return bytes;
}

namespace {

std::string firstLine(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    return line;
}

// The guest reports free blocks to the host (which discards their memory) when the kernel's
// page_reporting is loaded and a virtio balloon device negotiated feature bit 5
// (VIRTIO_BALLOON_F_REPORTING; sysfs shows the negotiated bits as a string of 0/1, bit 0 first).
bool freePageReportingActive() {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists("/sys/module/page_reporting", ec)) return false;
    for (const auto& dev : fs::directory_iterator("/sys/bus/virtio/devices", ec)) {
        if (firstLine(dev.path() / "device") != "0x0005") continue; // virtio balloon
        const std::string features = firstLine(dev.path() / "features");
        if (features.size() > 5 && features[5] == '1') return true;
    }
    return false;
}

HugePageChoice decideHugePages() { // a few reads of /sys: microseconds, once per upload
    const char* env = std::getenv("PNB_HUGE_PAGES");
    const std::string forced = env ? env : "";
    if (forced == "on") return {true, "transparent huge pages ($PNB_HUGE_PAGES=on)"};
    if (forced == "off") return {false, "$PNB_HUGE_PAGES=off"};
    const std::string thp = firstLine("/sys/kernel/mm/transparent_hugepage/enabled");
    if (thp.empty() || thp.find("[never]") != std::string::npos)
        return {false, "transparent huge pages are off in this kernel"};
    if (freePageReportingActive())
        return {false, "free page reporting: this VM gives free 2 MiB blocks back to its host"};
    return {true, "transparent huge pages"};
}

} // namespace

HugePageChoice hugePageChoice() {
    return decideHugePages();
}

std::string UploadHeap::describe() const {
    if (!mActive) return "not used (under 4 MiB, or not glibc's malloc)";
    if (mAdvised) return std::to_string(mAdvised >> 20) + " MiB in 2 MiB pages";
    return "4 KiB pages (" + mHuge.why + ")";
}

#ifdef PNB_UPLOAD_HEAP

namespace {
constexpr uint64_t kMinBytes = 4u << 20;
constexpr uintptr_t kHugePage = 2u << 20;
constexpr int kGlibcDefault = 128 << 10; // M_TRIM_THRESHOLD, M_TOP_PAD
constexpr int kGlibcDefaultMmapMax = 65536;
} // namespace

UploadHeap::UploadHeap(uint64_t bytes) {
    if (bytes < kMinBytes || bytes > (uint64_t(1) << 40)) return;
    // Every allocation comes from the heap while the upload runs — a 2048² RGBA8 texture with
    // its mips (21 MiB) or a 64 MiB shadow-map array would otherwise get a mapping of its own,
    // in 4 KiB pages — and freed memory is not given back until the upload is over.
    if (!mallopt(M_MMAP_MAX, 0)) return;
    mActive = true;
    mHuge = hugePageChoice();
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    // The heap's free top is advised as it is, and if it is smaller than the upload the heap
    // grows once by the rest (M_TOP_PAD): an allocation just larger than the free top forces
    // that growth, and freeing it leaves the whole range free for the driver. (Measured from the
    // free top, not assumed empty: the driver's own start-up may have left megabytes there.)
    const auto* heapEnd = static_cast<char*>(sbrk(0));
    const size_t top = mallinfo2().keepcost;
    void* probe = nullptr;
    if (top < bytes) {
        mallopt(M_TOP_PAD, int(std::min<uint64_t>(bytes - top, uint64_t(1) << 30)));
        probe = std::malloc(top + (1u << 20));
        mallopt(M_TOP_PAD, kGlibcDefault);
    }
    const auto* after = static_cast<char*>(sbrk(0));
    if (after >= heapEnd && uintptr_t(heapEnd) > top) {
        uintptr_t begin = (uintptr_t(heapEnd) - top + kHugePage - 1) & ~(kHugePage - 1);
        // MADV_NOHUGEPAGE when huge pages do not pay off, so that a kernel in "always" mode
        // does not use them either.
        const bool huge = mHuge.use;
        if (uintptr_t(after) > begin &&
            madvise(reinterpret_cast<void*>(begin), uintptr_t(after) - begin,
                    huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE) == 0 &&
            huge)
            mAdvised = uintptr_t(after) - begin;
    }
    std::free(probe);
}

UploadHeap::~UploadHeap() {
    if (!mActive) return;
    mallopt(M_MMAP_MAX, kGlibcDefaultMmapMax);
    mallopt(M_TRIM_THRESHOLD, kGlibcDefault);
    malloc_trim(0); // what the driver did not use goes back to the system
}

#else

UploadHeap::UploadHeap(uint64_t) {}
UploadHeap::~UploadHeap() = default;

#endif

} // namespace pnb::player
