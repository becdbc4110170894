// judged_scene.h — what the truth judges keep of a container to trace it again at every new
// instant they judge (issue 42: moving frames): the decoded scene (and the mapping its blobs
// point into), and the instant the renderer's last frame was drawn at.
#pragma once

#include <memory>
#include <string>

#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_player/renderer.h"
#include "pnb_reference/frame_pose.h"

namespace pnb::player {

struct JudgedScene {
    std::unique_ptr<Container> container; // what the scene's blobs and strings point into
    Scene scene;

    // Errors: Input (the container does not open or read).
    static PlayResult<std::unique_ptr<JudgedScene>> read(const std::string& path);
};

// The instant `renderer`'s last frame was drawn at, as the truth traces it (the frame.json
// "anim" of a dump, docs/REFERENCE.md "Moving frames"). This is the one place the judges learn it:
// it follows the player's clock (anim.enabled, the clip played and its clip time); until the
// renderer reports one, every frame is the container as stored.
reference::FramePose judgedPose(const Renderer& renderer);

} // namespace pnb::player
