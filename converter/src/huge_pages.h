// huge_pages.h — large arrays in transparent huge pages. Internal.
//
// Why: on the VMs we measure on (docs/CONVERTER.md, "Issue 30"), every 4 KiB page fault and TLB
// miss is expensive: reading the 94 MB benchmark OBJ into 4 KiB pages and scanning it once took
// 0.35 s, in huge pages 0.05 s. THP is in "madvise" mode on Debian, so memory must ask for them.
// Used by the OBJ importer (the file's bytes, its parse arrays, the primitives' streams) and the
// texture stage (decoded PNG images, mip levels).
#pragma once

#include <cstddef>
#include <utility>

namespace pnb::converter {

// `bytes` of memory, in huge pages from 2 MiB on (2 MiB-aligned mmap, MADV_HUGEPAGE), from
// operator new below; not zeroed by us (the kernel zeroes a page when it is first touched).
// Throws std::bad_alloc. freeLarge takes the same size.
void* allocateLarge(size_t bytes);
void freeLarge(void* p, size_t bytes);

// Advises the whole 2 MiB pages inside [p, p + bytes) of memory allocated elsewhere (a reserved
// std::vector the IR holds) for huge pages.
void adviseHugePages(const void* p, size_t bytes);

// A std::vector allocator on allocateLarge whose resize() default-initialises (leaves floats
// unwritten): the parse writes every element it later reads, and zeroing first would touch
// every page once more.
template <class T> struct LargeAllocator {
    using value_type = T;
    LargeAllocator() = default;
    template <class U> LargeAllocator(const LargeAllocator<U>&) {}
    T* allocate(size_t n) { return static_cast<T*>(allocateLarge(n * sizeof(T))); }
    void deallocate(T* p, size_t n) { freeLarge(p, n * sizeof(T)); }
    template <class U, class... Args> void construct(U* p, Args&&... args) {
        if constexpr (sizeof...(Args) == 0) ::new (static_cast<void*>(p)) U;
        else ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    template <class U> bool operator==(const LargeAllocator<U>&) const { return true; }
};

} // namespace pnb::converter
