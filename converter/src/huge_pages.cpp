// huge_pages.cpp — see huge_pages.h.
#include "huge_pages.h"

#include <sys/mman.h>

#include <cstdint>
#include <new>

namespace pnb::converter {

namespace {

constexpr size_t kHugePage = size_t(2) << 20;

size_t roundToHugePages(size_t bytes) { return (bytes + kHugePage - 1) & ~(kHugePage - 1); }

} // namespace

void* allocateLarge(size_t bytes) {
    if (bytes < kHugePage) return ::operator new(bytes);
    // Aligned to 2 MiB, or the kernel cannot back the ends with huge pages: map one more, trim.
    const size_t size = roundToHugePages(bytes);
    void* raw = ::mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const uintptr_t start = reinterpret_cast<uintptr_t>(raw);
    const uintptr_t aligned = (start + kHugePage - 1) & ~uintptr_t(kHugePage - 1);
    if (aligned > start) ::munmap(raw, aligned - start);
    if (const size_t tail = start + size + kHugePage - (aligned + size); tail > 0)
        ::munmap(reinterpret_cast<void*>(aligned + size), tail);
    ::madvise(reinterpret_cast<void*>(aligned), size, MADV_HUGEPAGE); // a hint: may be refused
    return reinterpret_cast<void*>(aligned);
}

void adviseHugePages(const void* p, size_t bytes) {
    const uintptr_t start = reinterpret_cast<uintptr_t>(p);
    const uintptr_t first = (start + kHugePage - 1) & ~uintptr_t(kHugePage - 1);
    const uintptr_t last = (start + bytes) & ~uintptr_t(kHugePage - 1);
    if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

void freeLarge(void* p, size_t bytes) {
    if (bytes < kHugePage) ::operator delete(p);
    else ::munmap(p, roundToHugePages(bytes));
}

} // namespace pnb::converter
