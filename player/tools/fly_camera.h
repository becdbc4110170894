// fly_camera.h — interactive camera for the pnb-play window.
//   fly (default): WASD move, Q/E down/up, Shift faster, right mouse button drag to look.
//   orbit (O toggles): left drag orbits the scene centre, scroll zooms.
// Speed scales with the scene size so the same keys work for a room and a city.
#pragma once

#include "pnb_player/camera.h"

struct GLFWwindow;

namespace pnb::player {

class FlyCamera {
public:
    FlyCamera(const CameraState& start, const Aabb& sceneBounds);
    // Applies input since the last call; `uiWantsInput` suppresses it (ImGui has focus).
    void update(GLFWwindow* window, double dtSeconds, bool uiWantsInput);
    const CameraState& camera() const { return mCamera; }
    bool orbiting() const { return mOrbit; }

private:
    CameraState mCamera;
    glm::dvec3 mCenter{0.0};
    double mSpeed = 1.0, mYaw = 0, mPitch = 0, mDistance = 1.0;
    double mSceneSize = 1.0; // diagonal of the scene bounds (scene units)
    double mLastX = 0, mLastY = 0;
    bool mOrbit = false, mOKeyDown = false, mDragging = false;
    void applyAngles();
};

} // namespace pnb::player
