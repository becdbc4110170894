#include "pnb_player/gpu_timer.h"

namespace pnb::player {

GpuTimer::GpuTimer() = default;

GpuTimer::~GpuTimer() {
    for (Slot& s : mSlots)
        if (!s.queries.empty()) glDeleteQueries(GLsizei(s.queries.size()), s.queries.data());
}

void GpuTimer::beginFrame(uint64_t frame) {
    mCurrent = (mCurrent + 1) % kFrames;
    Slot& s = mSlots[mCurrent];
    if (s.pending) collect(s, true);
    s.frame = frame;
    s.used = 0;
    s.names.clear();
}

void GpuTimer::mark(const std::string& pass) {
    Slot& s = mSlots[mCurrent];
    if (s.used == s.queries.size()) {
        GLuint q = 0;
        glCreateQueries(GL_TIMESTAMP, 1, &q);
        s.queries.push_back(q);
    }
    glQueryCounter(s.queries[s.used++], GL_TIMESTAMP);
    s.names.push_back(pass);
}

void GpuTimer::endFrame() {
    mark("");
    mSlots[mCurrent].pending = true;
    // Collect whatever finished without waiting, so results flow during long runs.
    for (int i = 1; i < kFrames; ++i) {
        Slot& s = mSlots[(mCurrent + i) % kFrames];
        if (s.pending) collect(s, false);
    }
}

void GpuTimer::collect(Slot& s, bool wait) {
    GLint available = 0;
    glGetQueryObjectiv(s.queries[s.used - 1], GL_QUERY_RESULT_AVAILABLE, &available);
    if (!available) {
        if (!wait) return;
        ++mStalls;
    }
    std::vector<GLuint64> t(s.used);
    for (size_t i = 0; i < s.used; ++i) glGetQueryObjectui64v(s.queries[i], GL_QUERY_RESULT, &t[i]);
    FrameGpuTimes f;
    f.frame = s.frame;
    for (size_t i = 0; i + 1 < s.used; ++i)
        f.passes.push_back({s.names[i], double(t[i + 1] - t[i]) * 1e-6});
    f.totalMs = double(t[s.used - 1] - t[0]) * 1e-6;
    s.pending = false;
    // Slots complete in frame order except when drained; keep the queue sorted.
    auto it = mCompleted.end();
    while (it != mCompleted.begin() && std::prev(it)->frame > f.frame) --it;
    mCompleted.insert(it, std::move(f));
}

void GpuTimer::drain() {
    for (int i = 1; i <= kFrames; ++i) {
        Slot& s = mSlots[(mCurrent + i) % kFrames];
        if (s.pending) {
            GLint available = 0;
            glGetQueryObjectiv(s.queries[s.used - 1], GL_QUERY_RESULT_AVAILABLE, &available);
            if (!available) glFinish();
            collect(s, true);
        }
    }
}

} // namespace pnb::player
