// parallel_for.h — runs fn(i) for i in [0, count) on up to `jobs` threads. Internal.
//
// Work is taken from an atomic counter and results are written by index, so output never
// depends on the thread count or on scheduling.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace pnb::converter {

inline unsigned resolveJobs(unsigned jobs) {
    return jobs ? jobs : std::max(1u, std::thread::hardware_concurrency());
}

template <class Fn> void parallelFor(size_t count, unsigned jobs, Fn fn) {
    unsigned threads = unsigned(std::min<size_t>(resolveJobs(jobs), count));
    if (threads <= 1) {
        for (size_t i = 0; i < count; ++i) fn(i);
        return;
    }
    std::atomic<size_t> next{0};
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
        pool.emplace_back([&] {
            for (size_t i = next++; i < count; i = next++) fn(i);
        });
    for (std::thread& t : pool) t.join();
}

} // namespace pnb::converter
