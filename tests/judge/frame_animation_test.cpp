// The animation state a benchmark frame records in frame.json (pnb_player/frame_animation.h):
// the player's clock of anim.* (fixed step, looped clip time), what the truth poses.
#include <gtest/gtest.h>

#include "pnb_player/frame_animation.h"

namespace pnb::player {
namespace {

const std::vector<ClipInfo> kClips = {{"walk", 2.0}, {"wave", 0.5}};

TEST(FrameAnimation, SettingsAreReadAsRawEntriesLaterWins) {
    const AnimationClock c = animationClock({{"anim.speed", "2"}, {"anim.clip", "wave"}, {"anim.time", "0.25"},
                                             {"anim.play", "false"}, {"anim.speed", "0.5"}, {"gi.enabled", "true"},
                                             {"anim.enabled", "nonsense"}});
    EXPECT_TRUE(c.enabled); // a value that does not parse keeps the default
    EXPECT_EQ(c.clip, "wave");
    EXPECT_FALSE(c.play);
    EXPECT_EQ(c.time, 0.25);
    EXPECT_EQ(c.speed, 0.5);
}

TEST(FrameAnimation, FrameIIsAtTimePlusSpeedTimesIStepsLooped) {
    AnimationClock c; // clip 0, playing from 0 at speed 1
    FrameAnimation a = frameAnimation(c, kClips, 30, 0.05); // 1.5 s
    ASSERT_TRUE(a.clip);
    EXPECT_EQ(*a.clip, 0u);
    EXPECT_EQ(a.clipName, "walk");
    EXPECT_DOUBLE_EQ(a.time, 1.5);
    a = frameAnimation(c, kClips, 50, 0.05); // 2.5 s: looped into the 2 s clip
    EXPECT_NEAR(a.time, 0.5, 1e-12);
    c.time = 0.1;
    c.speed = 2;
    c.clip = "1";
    a = frameAnimation(c, kClips, 1, 0.1); // 0.1 + 2 x 0.1 = 0.3 in clip 1
    ASSERT_TRUE(a.clip);
    EXPECT_EQ(*a.clip, 1u);
    EXPECT_NEAR(a.time, 0.3, 1e-12);
    c.play = false; // held at anim.time
    EXPECT_NEAR(frameAnimation(c, kClips, 99, 0.1).time, 0.1, 1e-12);
}

TEST(FrameAnimation, NoneDisabledOrMissingClipsAreTheRestOrTheStoredContainer) {
    AnimationClock c;
    c.clip = "none";
    FrameAnimation a = frameAnimation(c, kClips, 10, 0.1);
    EXPECT_TRUE(a.enabled);
    EXPECT_FALSE(a.clip);
    EXPECT_EQ(a.time, 0);
    c.clip = "0";
    EXPECT_FALSE(frameAnimation(c, {}, 10, 0.1).clip); // a container without clips
    c.clip = "run";
    EXPECT_FALSE(frameAnimation(c, kClips, 10, 0.1).clip);
    c.clip = "0";
    c.enabled = false;
    a = frameAnimation(c, kClips, 10, 0.1);
    EXPECT_FALSE(a.enabled);
    EXPECT_FALSE(a.clip);
}

} // namespace
} // namespace pnb::player
