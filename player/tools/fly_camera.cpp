#include "fly_camera.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>

namespace pnb::player {

FlyCamera::FlyCamera(const CameraState& start, const Aabb& b) : mCamera(start) {
    glm::dvec3 lo(b.min.x, b.min.y, b.min.z), hi(b.max.x, b.max.y, b.max.z);
    if (b.empty()) lo = hi = glm::dvec3(0.0);
    mCenter = (lo + hi) * 0.5;
    // Speed and the closest orbit are relative to the scene, whatever its unit of length (an
    // empty or one-point scene gets a unit size).
    mSceneSize = glm::length(hi - lo) > 0 ? glm::length(hi - lo) : 1.0;
    mSpeed = mDefaultSpeed = mSceneSize * 0.15;
    glm::dvec3 forward = start.rotation * glm::dvec3(0, 0, -1);
    mYaw = std::atan2(-forward.x, -forward.z);
    mPitch = std::asin(std::clamp(forward.y, -1.0, 1.0));
    mDistance = std::max(glm::length(start.position - mCenter), 1e-3 * mSceneSize);
}

void FlyCamera::applyAngles() {
    mPitch = std::clamp(mPitch, -1.55, 1.55);
    mCamera.rotation = glm::angleAxis(mYaw, glm::dvec3(0, 1, 0)) * glm::angleAxis(mPitch, glm::dvec3(1, 0, 0));
}

void FlyCamera::toggleOrbit() {
    mOrbit = !mOrbit;
    mDistance = std::max(glm::length(mCamera.position - mCenter), 1e-3 * mSceneSize);
}

void FlyCamera::scaleSpeed(double notches) {
    mSpeed = std::clamp(mSpeed * std::pow(kSpeedStep, notches), mDefaultSpeed * kMinSpeedFactor,
                        mDefaultSpeed * kMaxSpeedFactor);
}

void FlyCamera::zoom(double notches) {
    double degrees = std::clamp(fovDegrees() * std::pow(kZoomStep, notches), kMinFovDegrees, kMaxFovDegrees);
    mCamera.yfovRadians = float(glm::radians(degrees));
}

double FlyCamera::fovDegrees() const { return glm::degrees(double(mCamera.yfovRadians)); }

void FlyCamera::update(const InputState& in, double dt, bool uiWantsInput) {
    double dx = mHaveCursor ? in.cursorX - mLastX : 0, dy = mHaveCursor ? in.cursorY - mLastY : 0;
    mLastX = in.cursorX;
    mLastY = in.cursorY;
    mHaveCursor = true;
    if (uiWantsInput) return;
    bool drag = in.button(mOrbit ? GLFW_MOUSE_BUTTON_LEFT : GLFW_MOUSE_BUTTON_RIGHT);
    if (drag && mDragging) {
        mYaw -= dx * 0.005;
        mPitch -= dy * 0.005;
    }
    mDragging = drag;
    applyAngles();
    glm::dvec3 forward = mCamera.rotation * glm::dvec3(0, 0, -1);
    glm::dvec3 right = mCamera.rotation * glm::dvec3(1, 0, 0);
    if (mOrbit) {
        if (in.key(GLFW_KEY_W)) mDistance *= std::pow(0.3, dt);
        if (in.key(GLFW_KEY_S)) mDistance /= std::pow(0.3, dt);
        mCamera.position = mCenter - forward * mDistance;
        return;
    }
    bool fast = in.key(GLFW_KEY_LEFT_SHIFT) || in.key(GLFW_KEY_RIGHT_SHIFT);
    double speed = mSpeed * dt * (fast ? 4.0 : 1.0);
    glm::dvec3 move(0.0);
    if (in.key(GLFW_KEY_W)) move += forward;
    if (in.key(GLFW_KEY_S)) move -= forward;
    if (in.key(GLFW_KEY_D)) move += right;
    if (in.key(GLFW_KEY_A)) move -= right;
    if (in.key(GLFW_KEY_E)) move.y += 1;
    if (in.key(GLFW_KEY_Q)) move.y -= 1;
    mCamera.position += move * speed;
}

} // namespace pnb::player
