// fly_camera.h — interactive camera for the pnb-play window, driven by the held input state of
// InputMapper (input_actions.h), so scripted input moves it exactly as a user would.
//   fly (default): WASD move, Q/E down/up, Shift faster, right mouse button drag to look.
//   orbit (O toggles): left drag orbits the scene centre, W/S move in and out.
//   wheel: fly speed in log steps (x1.25 a notch); Ctrl or right button + wheel: field of view.
// Speed scales with the scene size so the same keys work for a room and a city.
#pragma once

#include "input_actions.h"
#include "pnb_player/camera.h"

namespace pnb::player {

class FlyCamera {
public:
    // Speed limits relative to the default speed (0.15 scene diagonals per second).
    static constexpr double kSpeedStep = 1.25, kMinSpeedFactor = 1e-3, kMaxSpeedFactor = 1e3;
    // Field-of-view limits (vertical, degrees) and the factor a wheel notch applies.
    static constexpr double kMinFovDegrees = 5, kMaxFovDegrees = 120, kZoomStep = 0.9;

    FlyCamera(const CameraState& start, const Aabb& sceneBounds);
    // Applies the held input over `dtSeconds`; `uiWantsInput` suppresses it (ImGui has focus).
    void update(const InputState& input, double dtSeconds, bool uiWantsInput);
    void toggleOrbit();
    // Wheel notches: speed x kSpeedStep^notches, clamped.
    void scaleSpeed(double notches);
    // Wheel notches with the modifier: fov x kZoomStep^notches, clamped (> 0 zooms in).
    void zoom(double notches);
    const CameraState& camera() const { return mCamera; }
    bool orbiting() const { return mOrbit; }
    double speed() const { return mSpeed; }  // scene units per second (without Shift)
    double fovDegrees() const;

private:
    CameraState mCamera;
    glm::dvec3 mCenter{0.0};
    double mSpeed = 1.0, mDefaultSpeed = 1.0, mYaw = 0, mPitch = 0, mDistance = 1.0;
    double mSceneSize = 1.0; // diagonal of the scene bounds (scene units)
    double mLastX = 0, mLastY = 0;
    bool mOrbit = false, mDragging = false, mHaveCursor = false;
    void applyAngles();
};

} // namespace pnb::player
