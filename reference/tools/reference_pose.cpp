// pnb-reference's instant traced (reference_pose.h).
#include "reference_pose.h"

#include <charconv>
#include <string>

#include "pnb/animation_pose.h"

namespace pnb::reference_tool {

namespace {

std::string clipName(const pnb::Scene& scene, uint32_t clip) {
    const pnb::StringRef ref = scene.animations[clip].name;
    return ref < scene.strings.strings.size() ? std::string(scene.strings.strings[ref]) : std::string();
}

// --anim-clip's value: "none", an index, or a clip's name.
Expected<std::optional<uint32_t>> clipNamed(const std::string& value, const pnb::Scene& scene,
                                            const std::string& sceneName) {
    if (value == "none") return std::optional<uint32_t>{};
    uint32_t index = 0;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), index);
    if (ec == std::errc() && end == value.data() + value.size()) {
        if (index < scene.animations.size()) return std::optional<uint32_t>(index);
    } else {
        for (uint32_t c = 0; c < scene.animations.size(); ++c)
            if (clipName(scene, c) == value) return std::optional<uint32_t>(c);
    }
    return Failure{kExitInput, "--anim-clip " + value + ": " + sceneName + " has no such clip (" +
                                   std::to_string(scene.animations.size()) + " clip(s))"};
}

} // namespace

Expected<pnb::reference::FramePose> resolvePose(const Settings& settings, const Frame& frame, const pnb::Scene& scene,
                                                const std::string& framePath) {
    pnb::reference::FramePose pose;
    const bool recorded = frame.anim && frame.anim->enabled;
    if (recorded) {
        const Frame::Animation& a = *frame.anim;
        if (a.clip && *a.clip >= scene.animations.size())
            return Failure{kExitInput, framePath + ": \"anim\" clip " + std::to_string(*a.clip) + " is not in " +
                                           settings.scene + " (" + std::to_string(scene.animations.size()) +
                                           " clip(s)): is it the container the frame was drawn from?"};
        if (a.clip && !a.clipName.empty() && !clipName(scene, *a.clip).empty() && clipName(scene, *a.clip) != a.clipName)
            return Failure{kExitInput, framePath + ": \"anim\" clip " + std::to_string(*a.clip) + " is '" + a.clipName +
                                           "', " + settings.scene + "'s is '" + clipName(scene, *a.clip) +
                                           "': is it the container the frame was drawn from?"};
        pose = {true, a.clip, a.time};
    }
    if (!settings.animClip && !settings.animTime) return pose;
    pose.animated = true;
    if (settings.animClip) {
        auto clip = clipNamed(*settings.animClip, scene, settings.scene);
        if (!clip) return clip.error();
        pose.clip = *clip;
    } else if (!recorded) {
        pose.clip = scene.animations.empty() ? std::nullopt : std::optional<uint32_t>(0); // anim.clip's default
    }
    if (settings.animTime)
        pose.clipTime = pose.clip ? pnb::clipTime(pnb::clipDuration(scene.animations[*pose.clip]), *settings.animTime)
                                  : *settings.animTime;
    return pose;
}

nlohmann::ordered_json poseJson(const pnb::reference::FramePose& pose, const pnb::Scene& scene) {
    nlohmann::ordered_json j = {{"animated", pose.animated}};
    if (!pose.animated) return j;
    j["clip"] = pose.clip ? nlohmann::ordered_json(*pose.clip) : nlohmann::ordered_json(nullptr);
    j["clip_name"] = pose.clip && *pose.clip < scene.animations.size() ? clipName(scene, *pose.clip) : "";
    j["time"] = pose.clipTime;
    return j;
}

} // namespace pnb::reference_tool
