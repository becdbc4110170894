// The cameras a run starts from (pnb_player/scene_cameras.h).
#include "pnb_player/scene_cameras.h"

#include "pnb_player/camera_path.h"

namespace pnb::player {

CameraState sceneCamera(const GpuScene& scene, size_t index) {
    const SceneCamera& c = scene.cameras[index];
    CameraState cam;
    cam.position = c.position;
    cam.rotation = c.rotation;
    cam.yfovRadians = c.desc.yfovRadians;
    cam.znear = c.desc.znear;
    cam.zfar = c.desc.zfar;
    cam.projection = c.desc.projection;
    cam.ymag = c.desc.ymag;
    return cam;
}

CameraState initialCamera(const GpuScene& scene, const std::string& pathName) {
    CameraState cam;
    if (!scene.cameras.empty()) {
        cam = sceneCamera(scene, 0);
    } else {
        cam = framingCamera(scene.bounds, 0.8f);
    }
    if (const ScenePath* p = scene.findPath(pathName); p && !p->path.keys.empty())
        evaluatePath(p->path, p->path.keys.front().timeSeconds, cam);
    return cam;
}

} // namespace pnb::player
