// The frame's pass list (player/src/renderer/frame.cpp): for every combination of the facts that
// decide which passes run, every pass reads only what an earlier pass (or the prepare step) wrote,
// and nothing a pass read is rewritten after it. No GL: the list is data.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/frame.h"

namespace pnb::player {
namespace {

std::vector<FrameShape> everyShape() {
    std::vector<FrameShape> shapes;
    for (uint32_t bits = 0; bits < 64; ++bits) {
        FrameShape s;
        s.shadows = bits & 1;
        s.sdsm = s.shadows && (bits & 2);
        s.deferred = bits & 4;
        s.gi = bits & 8;
        s.giProbes = s.gi && (bits & 16);
        s.giCameraSurfels = bits & 32;
        shapes.push_back(s);
    }
    return shapes;
}

size_t indexOf(const std::vector<std::string>& names, const std::string& name) {
    return size_t(std::find(names.begin(), names.end(), name) - names.begin());
}

TEST(FramePasses, OrderHoldsForEveryShape) {
    for (const FrameShape& s : everyShape())
        EXPECT_EQ(checkFrameOrder(framePasses(), s), "")
            << "shadows " << s.shadows << " sdsm " << s.sdsm << " deferred " << s.deferred << " gi " << s.gi
            << " probes " << s.giProbes << " surfels " << s.giCameraSurfels;
}

TEST(FramePasses, SdsmFitsBetweenTheFirstGBufferAndItsLighting) {
    FrameShape s;
    s.shadows = s.sdsm = s.deferred = true;
    const auto names = framePassNames(s);
    EXPECT_LT(indexOf(names, "deferred.gbuffer(first)"), indexOf(names, "shadows.sdsm_fit"));
    EXPECT_LT(indexOf(names, "shadows.sdsm_fit"), indexOf(names, "shadows.maps(sdsm)"));
    EXPECT_LT(indexOf(names, "shadows.maps(sdsm)"), indexOf(names, "deferred.lighting(first)"));
    EXPECT_EQ(indexOf(names, "shadows.maps"), names.size()); // not also before the targets
    // Without deferred geometry SDSM fits to the previous frame's depth, before the clear.
    s.deferred = false;
    const auto early = framePassNames(s);
    EXPECT_LT(indexOf(early, "shadows.sdsm_fit(previous)"), indexOf(early, "frame.clear"));
    EXPECT_LT(indexOf(early, "shadows.maps"), indexOf(early, "forward"));
}

TEST(FramePasses, GiFinishesOnceAtItsPlace) {
    FrameShape s;
    s.gi = s.deferred = s.giCameraSurfels = true;
    auto names = framePassNames(s);
    EXPECT_EQ(indexOf(names, "gi.finish"), names.size());
    EXPECT_LT(indexOf(names, "deferred.gbuffer(first)"), indexOf(names, "gi.finish(camera surfels)"));
    EXPECT_LT(indexOf(names, "gi.finish(camera surfels)"), indexOf(names, "deferred.lighting(first)"));
    s.giCameraSurfels = false;
    names = framePassNames(s);
    EXPECT_LT(indexOf(names, "gi.finish"), indexOf(names, "frame.clear"));
    EXPECT_EQ(indexOf(names, "gi.finish(camera surfels)"), names.size());
    // The probes technique gathers instead: no injection, no finishing.
    s.giProbes = true;
    names = framePassNames(s);
    EXPECT_LT(indexOf(names, "gi.probes"), names.size());
    EXPECT_EQ(indexOf(names, "gi.inject"), names.size());
    EXPECT_EQ(indexOf(names, "gi.finish"), names.size());
}

// The check sees a misplaced pass: the sun's maps drawn after the lighting that reads them, the
// light list rewritten after a pass read it, a G-buffer drawn before the clear of its depth.
TEST(FramePasses, TheCheckFindsMisorderedPasses) {
    std::vector<FramePass> passes(framePasses().begin(), framePasses().end());
    auto move = [&](const std::string& name, const std::string& after) {
        auto from = std::find_if(passes.begin(), passes.end(), [&](const FramePass& p) { return p.name == name; });
        FramePass p = *from;
        passes.erase(from);
        auto to = std::find_if(passes.begin(), passes.end(), [&](const FramePass& q) { return q.name == after; });
        passes.insert(to + 1, p);
    };
    FrameShape s;
    s.shadows = s.deferred = true;
    ASSERT_EQ(checkFrameOrder(passes, s), "");
    move("shadows.maps", "deferred.lighting(first)");
    EXPECT_EQ(checkFrameOrder(passes, s), "deferred.lighting(first) reads shadow maps before any pass writes it");

    passes.assign(framePasses().begin(), framePasses().end());
    FrameShape sdsm;
    sdsm.shadows = sdsm.sdsm = true; // no deferred layer: SDSM fits to the previous frame's depth
    move("shadows.sdsm_fit(previous)", "shadows.maps"); // the maps drawn with the fit before it
    EXPECT_EQ(checkFrameOrder(passes, sdsm), "shadows.sdsm_fit(previous) writes shadow fit after a pass has read it");

    passes.assign(framePasses().begin(), framePasses().end());
    move("frame.clear", "deferred.gbuffer(first)");
    EXPECT_EQ(checkFrameOrder(passes, s), "deferred.gbuffer(first) reads depth before any pass writes it");
}

} // namespace
} // namespace pnb::player
