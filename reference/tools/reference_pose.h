// pnb-reference's instant traced (docs/REFERENCE.md "Moving frames"): frame.json's "anim", with
// --anim-clip and --anim-time applied, checked against the scene; and its record in metrics.json.
#pragma once

#include <nlohmann/json.hpp>

#include "pnb/scene.h"
#include "pnb_reference/frame_pose.h"
#include "reference_cli.h"
#include "reference_io.h"

namespace pnb::reference_tool {

// The pose every tracer of this run builds at. Without --anim-*: frame.json's "anim" (absent or
// enabled false: the container as stored). With them: animated; --anim-clip's clip (an index, a
// name, or none) else frame.json's else the player's default (the first clip, if any);
// --anim-time's time looped into the clip's length as the player's clock loops it, else
// frame.json's sampled time, else 0. Errors (exit 2): a clip that is not in the scene, a
// frame.json clip whose recorded name is not the scene's (another container than the frame's).
Expected<pnb::reference::FramePose> resolvePose(const Settings& settings, const Frame& frame, const pnb::Scene& scene,
                                                const std::string& framePath);

// metrics.json's "pose": {"animated", "clip", "clip_name", "time"}.
nlohmann::ordered_json poseJson(const pnb::reference::FramePose& pose, const pnb::Scene& scene);

} // namespace pnb::reference_tool
