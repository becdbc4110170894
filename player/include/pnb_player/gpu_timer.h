// pnb_player/gpu_timer.h — per-pass GPU times from timestamp queries, read back from a ring of
// frames so the CPU never waits for the GPU: a frame's results are collected when its slot comes
// round again (kFrames later), by which time the GPU has long finished it.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "pnb_player/gl_handles.h"

namespace pnb::player {

struct PassTime {
    std::string pass;
    double ms = 0;
};

struct FrameGpuTimes {
    uint64_t frame = 0;
    std::vector<PassTime> passes; // in execution order
    double totalMs = 0;           // first timestamp to last
};

class GpuTimer {
public:
    static constexpr int kFrames = 4;

    GpuTimer();
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    void beginFrame(uint64_t frame);
    void mark(const std::string& passStarting); // closes the previous pass, opens this one
    void endFrame();

    // Frames whose results have arrived, oldest first; the caller takes them.
    std::deque<FrameGpuTimes>& completed() { return mCompleted; }
    // Waits for every outstanding frame (end of a benchmark).
    void drain();
    // Slots that had to wait because their results were late (should stay 0).
    uint64_t stalls() const { return mStalls; }

private:
    struct Slot {
        uint64_t frame = 0;
        bool pending = false;
        std::vector<GLuint> queries; // grown as needed, never shrunk
        std::vector<std::string> names;
        size_t used = 0;
    };
    void collect(Slot& slot, bool wait);

    Slot mSlots[kFrames];
    int mCurrent = -1;
    std::deque<FrameGpuTimes> mCompleted;
    uint64_t mStalls = 0;
};

} // namespace pnb::player
