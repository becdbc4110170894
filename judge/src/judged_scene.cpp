// The truth judges' scene and instant (judged_scene.h).
#include "judged_scene.h"

namespace pnb::player {

PlayResult<std::unique_ptr<JudgedScene>> JudgedScene::read(const std::string& path) {
    auto container = Container::open(path);
    if (!container) return PlayError{PlayErrorKind::Input, container.error().describe()};
    auto out = std::make_unique<JudgedScene>();
    out->container = std::make_unique<Container>(std::move(*container));
    auto scene = readScene(*out->container);
    if (!scene) return PlayError{PlayErrorKind::Input, scene.error().describe()};
    out->scene = std::move(*scene);
    return out;
}

reference::FramePose judgedPose(const Renderer& renderer) {
    const DrawnPose drawn = renderer.drawnPose();
    reference::FramePose at;
    at.animated = drawn.enabled;
    at.clip = drawn.clip;
    at.clipTime = drawn.clipTime;
    return at;
}

} // namespace pnb::player
