// path_recorder.h — recording a camera path in the pnb-play window (F9 start/stop, K adds a key,
// --record-every S adds one every S seconds). Keys hold the camera's position, rotation and field
// of view at the window time since the recording started (the first key is at 0, the last at the
// stop); saved as the keyframe JSON that `pnb-play --path FILE` and `pnb-convert --path FILE`
// read (pnb_player/path_json.h).
#pragma once

#include <optional>
#include <string>

#include "pnb_player/camera.h"
#include "pnb_player/gpu_scene.h"

namespace pnb::player {

class PathRecorder {
public:
    // Keys closer in time than this are merged away (the converter needs strictly increasing
    // times, and they are stored as float).
    static constexpr double kMinKeySpacing = 1e-3;

    explicit PathRecorder(double everySeconds = 0) : mEvery(everySeconds) {}
    bool recording() const { return mRecording; }
    size_t keyCount() const { return mPath.path.keys.size(); }
    double time() const { return mTime; }

    // Starts a recording with a key at time 0.
    void start(const CameraState& camera);
    // Advances the recording clock by `dt` (the camera is where it is after that time) and adds
    // the periodic key when one is due. Returns true if a key was added.
    bool advance(double dt, const CameraState& camera);
    // A key now; false (nothing added) when not recording or too close to the previous key.
    bool addKey(const CameraState& camera);
    // Ends the recording with a key at the current time; the path (named `name`) if it has at
    // least two keys, else nullopt.
    std::optional<ScenePath> stop(const CameraState& camera, const std::string& name);

private:
    double mEvery = 0, mTime = 0, mLastAuto = 0;
    bool mRecording = false;
    ScenePath mPath;
};

// `wanted` if no file exists there, else the first free "<stem>-2<ext>", "<stem>-3<ext>", ...
std::string freshFileName(const std::string& wanted);

} // namespace pnb::player
