// UploadHeap: the driver's copy of the scene lands in transparent huge pages, and malloc's
// behaviour is back to normal afterwards.
#include "../common/sanitizers.h"
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#if defined(__GLIBC__)
#include <malloc.h>
#include <unistd.h>
#endif

#include "gl/upload_heap.h"

namespace pnb::player {
namespace {

TEST(UploadHeap, EstimateCountsEveryMipAndStreamWithRgbExpandedToRgba) {
    std::vector<std::byte> bytes(4096);
    Scene scene;
    TextureDesc rgb;
    rgb.format = TextureFormat::RGB8;
    rgb.width = rgb.height = 16;
    rgb.mipCount = 2;
    TextureDesc bc;
    bc.format = TextureFormat::BC1;
    bc.width = bc.height = 8;
    scene.textures = {rgb, bc};
    scene.textureMips = {{0, 1, 8, 8, {}}, {0, 0, 16, 16, {}}, {1, 0, 8, 8, {}}};
    Mesh mesh;
    VertexStream position;
    position.data = Blob(bytes.data(), 1200);
    mesh.streams = {position};
    mesh.indices = Blob(bytes.data(), 600);
    scene.meshes = {mesh};
    // RGB8 8x8 + 16x16 as RGBA: 4 * (64 + 256); BC1 8x8: 4 blocks of 8 bytes; one stream (+16
    // alignment slack) and the indices.
    EXPECT_EQ(estimateUploadBytes(scene), 4u * (64 + 256) + 32 + (1200 + 16) + 600);
}

uint64_t anonHugePagesKib() {
    std::ifstream in("/proc/self/smaps_rollup");
    for (std::string key; in >> key;) {
        uint64_t value = 0;
        if (key == "AnonHugePages:" && in >> value) return value;
    }
    return 0;
}

bool transparentHugePagesUsable(std::string& why) {
#if !defined(__GLIBC__) || defined(PNB_ASAN) || defined(PNB_TSAN)
    why = "malloc is not glibc's here (a sanitizer's or another C library's): UploadHeap does nothing";
    return false;
#else
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(in, modes);
    if (modes.empty() || modes.find("[never]") != std::string::npos) {
        why = "transparent huge pages are off on this kernel ('" + modes + "')";
        return false;
    }
    return true;
#endif
}

// Sets $PNB_HUGE_PAGES for one scope.
struct HugePagesEnv {
    explicit HugePagesEnv(const char* value) { setenv("PNB_HUGE_PAGES", value, 1); }
    ~HugePagesEnv() { unsetenv("PNB_HUGE_PAGES"); }
};

TEST(UploadHeap, DriverAllocationsArriveInHugePagesAndMallocIsRestoredAfter) {
    std::string why;
    if (!transparentHugePagesUsable(why)) GTEST_SKIP() << why;
#if defined(__GLIBC__)
    constexpr size_t kMiB = size_t(1) << 20;
    void* heapEndBefore = sbrk(0);
    {
        HugePagesEnv on("on"); // whatever this machine's automatic choice is
        UploadHeap heap(96 * kMiB);
        EXPECT_NE(heap.describe().find("MiB in 2 MiB pages"), std::string::npos) << heap.describe();
        ASSERT_GE(heap.hugePageBytes(), 80 * kMiB) << "the heap did not grow by the upload's size";
        // What a driver does with a new texture: allocate and fill it — 40 MiB, more than glibc
        // would otherwise put in the heap (32 MiB at most) instead of a mapping of its own.
        const uint64_t hugeBefore = anonHugePagesKib();
        void* storage = std::malloc(40 * kMiB);
        ASSERT_NE(storage, nullptr);
        std::memset(storage, 1, 40 * kMiB);
        const uint64_t hugeAfter = anonHugePagesKib();
        EXPECT_GE(hugeAfter - hugeBefore, 36u * 1024) << "AnonHugePages " << hugeBefore << " -> "
                                                      << hugeAfter << " KiB";
        std::free(storage);
    }
    // Thresholds back at 128 KiB and the unused reservation given back: the heap ends within a
    // few MiB of where it ended before (not 96 MiB further).
    EXPECT_LT(uintptr_t(sbrk(0)), uintptr_t(heapEndBefore) + 8 * kMiB);
    const size_t mappedBefore = mallinfo2().hblkhd;
    void* block = std::malloc(kMiB);
    ASSERT_NE(block, nullptr);
    EXPECT_GE(mallinfo2().hblkhd, mappedBefore + kMiB) << "a 1 MiB block should be mapped again";
    std::free(block);
#endif
}

TEST(UploadHeap, WithoutHugePagesTheHeapStillGrowsButIn4KiBPages) {
    std::string why;
    if (!transparentHugePagesUsable(why)) GTEST_SKIP() << why;
#if defined(__GLIBC__)
    constexpr size_t kMiB = size_t(1) << 20;
    HugePagesEnv off("off");
    UploadHeap heap(96 * kMiB);
    EXPECT_EQ(heap.hugePageBytes(), 0u);
    EXPECT_EQ(heap.describe(), "4 KiB pages ($PNB_HUGE_PAGES=off)");
    const uint64_t hugeBefore = anonHugePagesKib();
    void* storage = std::malloc(40 * kMiB);
    ASSERT_NE(storage, nullptr);
    std::memset(storage, 1, 40 * kMiB);
    EXPECT_LT(anonHugePagesKib() - hugeBefore, 4u * 1024) << "MADV_NOHUGEPAGE was not applied";
    std::free(storage);
#endif
}

// Automatic: huge pages unless the kernel has them off or the VM reports free pages to its host,
// and the reason is always given.
TEST(UploadHeap, TheAutomaticChoiceFollowsTheKernel) {
    unsetenv("PNB_HUGE_PAGES");
    const HugePageChoice choice = hugePageChoice();
    EXPECT_FALSE(choice.why.empty());
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(in, modes);
    if (modes.find("[never]") != std::string::npos || modes.empty()) {
        EXPECT_FALSE(choice.use) << choice.why;
    } else if (!choice.use) {
        EXPECT_NE(choice.why.find("free page reporting"), std::string::npos) << choice.why;
    }
    std::printf("automatic choice here: %s (%s)\n", choice.use ? "2 MiB pages" : "4 KiB pages",
                choice.why.c_str());
    HugePagesEnv forced("on");
    EXPECT_TRUE(hugePageChoice().use);
}

TEST(UploadHeap, SmallScenesAreLeftAlone) {
    UploadHeap heap(1u << 20);
    EXPECT_EQ(heap.hugePageBytes(), 0u);
}

} // namespace
} // namespace pnb::player
