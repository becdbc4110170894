// The animation state of a benchmark frame (pnb_player/frame_animation.h).
#include "pnb_player/frame_animation.h"

#include <charconv>
#include <cmath>

#include "pnb/animation_pose.h"
#include "pnb/chunks.h"
#include "pnb/reader.h"

namespace pnb::player {

namespace {

std::optional<double> number(const std::string& v) {
    double out = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
    if (ec != std::errc() || end != v.data() + v.size() || !std::isfinite(out)) return std::nullopt;
    return out;
}

std::optional<bool> boolean(const std::string& v) {
    if (v == "true" || v == "1" || v == "on") return true;
    if (v == "false" || v == "0" || v == "off") return false;
    return std::nullopt;
}

} // namespace

AnimationClock animationClock(const std::vector<std::pair<std::string, std::string>>& entries) {
    AnimationClock c;
    for (const auto& [key, value] : entries) {
        if (key == "anim.enabled") c.enabled = boolean(value).value_or(c.enabled);
        else if (key == "anim.play") c.play = boolean(value).value_or(c.play);
        else if (key == "anim.clip") c.clip = value;
        else if (key == "anim.time") c.time = number(value).value_or(c.time);
        else if (key == "anim.speed") c.speed = number(value).value_or(c.speed);
    }
    return c;
}

std::vector<ClipInfo> containerClips(const std::string& path) {
    std::vector<ClipInfo> clips;
    auto container = Container::open(path);
    if (!container) return clips;
    std::vector<std::string> strings;
    if (const ChunkInfo* s = container->findFirst(tags::kStrings))
        if (auto payload = container->load(*s))
            if (auto table = decodeChunk<StringTable>(payload->bytes(), s->header))
                strings.assign(table->strings.begin(), table->strings.end());
    for (const ChunkInfo* a : container->find(tags::kAnimation)) {
        auto payload = container->load(*a);
        if (!payload) return {};
        auto clip = decodeChunk<Animation>(payload->bytes(), a->header);
        if (!clip) return {};
        clips.push_back({clip->name < strings.size() ? strings[clip->name] : std::string(), clipDuration(*clip)});
    }
    return clips;
}

FrameAnimation frameAnimation(const AnimationClock& clock, const std::vector<ClipInfo>& clips, uint32_t frame,
                              double step) {
    FrameAnimation a;
    a.enabled = clock.enabled;
    if (!clock.enabled) return a;
    uint32_t index = 0;
    const auto [end, ec] = std::from_chars(clock.clip.data(), clock.clip.data() + clock.clip.size(), index);
    if (ec == std::errc() && end == clock.clip.data() + clock.clip.size()) {
        if (index < clips.size()) a.clip = index;
    } else {
        for (uint32_t k = 0; k < clips.size(); ++k)
            if (clips[k].name == clock.clip) {
                a.clip = k;
                break;
            }
    }
    if (!a.clip) return a; // the rest pose: no clip time
    const double t = clock.play ? clock.time + clock.speed * double(frame) * step : clock.time;
    a.clipName = clips[*a.clip].name;
    a.time = clipTime(clips[*a.clip].duration, t);
    return a;
}

} // namespace pnb::player
