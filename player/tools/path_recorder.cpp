#include "path_recorder.h"

#include <filesystem>

namespace pnb::player {

void PathRecorder::start(const CameraState& camera) {
    mPath = {};
    mTime = mLastAuto = 0;
    mRecording = true;
    addKey(camera);
}

bool PathRecorder::advance(double dt, const CameraState& camera) {
    if (!mRecording) return false;
    mTime += dt;
    // A small slack so a fixed dt that divides the period lands on it despite rounding.
    if (mEvery > 0 && mTime - mLastAuto >= mEvery - 1e-9) {
        mLastAuto = mTime;
        return addKey(camera);
    }
    return false;
}

bool PathRecorder::addKey(const CameraState& camera) {
    if (!mRecording) return false;
    std::vector<CameraKey>& keys = mPath.path.keys;
    float t = float(mTime);
    if (!keys.empty() && !(double(t) >= double(keys.back().timeSeconds) + kMinKeySpacing)) return false;
    CameraKey k;
    k.timeSeconds = t;
    k.position = {float(camera.position.x), float(camera.position.y), float(camera.position.z)};
    glm::dquat q = glm::normalize(camera.rotation);
    k.rotation = {float(q.x), float(q.y), float(q.z), float(q.w)};
    k.yfovRadians = camera.yfovRadians;
    keys.push_back(k);
    return true;
}

std::optional<ScenePath> PathRecorder::stop(const CameraState& camera, const std::string& name) {
    if (!mRecording) return std::nullopt;
    addKey(camera);
    mRecording = false;
    if (mPath.path.keys.size() < 2) return std::nullopt;
    mPath.name = name;
    mPath.path.interpolation = Interpolation::CatmullRom;
    mPath.path.loop = false;
    return mPath;
}

std::string freshFileName(const std::string& wanted) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(wanted, ec)) return wanted;
    fs::path p(wanted);
    std::string stem = (p.parent_path() / p.stem()).string(), ext = p.extension().string();
    for (int n = 2;; ++n) {
        std::string candidate = stem + "-" + std::to_string(n) + ext;
        if (!fs::exists(candidate, ec)) return candidate;
    }
}

} // namespace pnb::player
