#include "mapping_guard.h"

#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <mutex>

namespace pnb::detail {

namespace {

// Lock-free slots: the handler may run on any thread at any time, so it only reads atomics.
constexpr int kSlots = 64;
struct Slot {
    std::atomic<uintptr_t> begin{0}, end{0};
    std::atomic<uint64_t> missingFrom{UINT64_MAX};
};
Slot gSlots[kSlots];
std::mutex gRegister; // serialises guard/unguard (not the handler)
struct sigaction gPrevious {};

void onSigbus(int sig, siginfo_t* info, void* context) {
    const uintptr_t addr = reinterpret_cast<uintptr_t>(info->si_addr);
    for (Slot& s : gSlots) {
        const uintptr_t begin = s.begin.load(std::memory_order_acquire);
        const uintptr_t end = s.end.load(std::memory_order_acquire);
        if (begin == 0 || addr < begin || addr >= end) continue;
        // Zero pages from the faulting page to the end of the mapping: every later page is past
        // the new end of file too. mmap is async-signal-safe.
        const uintptr_t page = uintptr_t(::sysconf(_SC_PAGESIZE));
        const uintptr_t from = addr & ~(page - 1);
        void* m = ::mmap(reinterpret_cast<void*>(from), end - from, PROT_READ,
                         MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1, 0);
        if (m == MAP_FAILED) break;
        uint64_t offset = from - begin, seen = s.missingFrom.load();
        while (offset < seen && !s.missingFrom.compare_exchange_weak(seen, offset)) {
        }
        return; // the faulting access is retried and now reads zeros
    }
    // Not ours: hand it on, or die the way SIGBUS always did.
    if ((gPrevious.sa_flags & SA_SIGINFO) && gPrevious.sa_sigaction) {
        gPrevious.sa_sigaction(sig, info, context);
    } else if (gPrevious.sa_handler != SIG_DFL && gPrevious.sa_handler != SIG_IGN &&
               gPrevious.sa_handler) {
        gPrevious.sa_handler(sig);
    } else {
        ::signal(SIGBUS, SIG_DFL); // the access faults again, with the default action
    }
}

bool installOnce() {
    static const bool installed = [] {
        struct sigaction sa {};
        sa.sa_sigaction = onSigbus;
        sa.sa_flags = SA_SIGINFO | SA_NODEFER;
        sigemptyset(&sa.sa_mask);
        return ::sigaction(SIGBUS, &sa, &gPrevious) == 0;
    }();
    return installed;
}

} // namespace

int guardMapping(const void* base, size_t size) {
    if (!base || size == 0) return kNoGuard;
    std::lock_guard lock(gRegister);
    if (!installOnce()) return kNoGuard;
    for (int i = 0; i < kSlots; ++i) {
        Slot& s = gSlots[i];
        if (s.begin.load() != 0) continue;
        s.missingFrom.store(UINT64_MAX);
        s.end.store(reinterpret_cast<uintptr_t>(base) + size);
        s.begin.store(reinterpret_cast<uintptr_t>(base), std::memory_order_release);
        return i;
    }
    return kNoGuard;
}

void unguardMapping(int slot) {
    if (slot < 0 || slot >= kSlots) return;
    std::lock_guard lock(gRegister);
    gSlots[slot].begin.store(0, std::memory_order_release);
    gSlots[slot].end.store(0);
}

uint64_t truncatedAt(int slot) {
    if (slot < 0 || slot >= kSlots) return UINT64_MAX;
    return gSlots[slot].missingFrom.load(std::memory_order_acquire);
}

} // namespace pnb::detail
