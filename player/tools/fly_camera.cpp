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
    mSpeed = mSceneSize * 0.15;
    glm::dvec3 forward = start.rotation * glm::dvec3(0, 0, -1);
    mYaw = std::atan2(-forward.x, -forward.z);
    mPitch = std::asin(std::clamp(forward.y, -1.0, 1.0));
    mDistance = std::max(glm::length(start.position - mCenter), 1e-3 * mSceneSize);
}

void FlyCamera::applyAngles() {
    mPitch = std::clamp(mPitch, -1.55, 1.55);
    mCamera.rotation = glm::angleAxis(mYaw, glm::dvec3(0, 1, 0)) * glm::angleAxis(mPitch, glm::dvec3(1, 0, 0));
}

void FlyCamera::update(GLFWwindow* w, double dt, bool uiWantsInput) {
    double x = 0, y = 0;
    glfwGetCursorPos(w, &x, &y);
    double dx = x - mLastX, dy = y - mLastY;
    mLastX = x;
    mLastY = y;
    if (uiWantsInput) return;
    bool o = glfwGetKey(w, GLFW_KEY_O) == GLFW_PRESS;
    if (o && !mOKeyDown) {
        mOrbit = !mOrbit;
        mDistance = std::max(glm::length(mCamera.position - mCenter), 1e-3 * mSceneSize);
    }
    mOKeyDown = o;
    int button = mOrbit ? GLFW_MOUSE_BUTTON_LEFT : GLFW_MOUSE_BUTTON_RIGHT;
    bool drag = glfwGetMouseButton(w, button) == GLFW_PRESS;
    if (drag && mDragging) {
        mYaw -= dx * 0.005;
        mPitch -= dy * 0.005;
    }
    mDragging = drag;
    applyAngles();
    glm::dvec3 forward = mCamera.rotation * glm::dvec3(0, 0, -1);
    glm::dvec3 right = mCamera.rotation * glm::dvec3(1, 0, 0);
    if (mOrbit) {
        if (glfwGetKey(w, GLFW_KEY_W) == GLFW_PRESS) mDistance *= std::pow(0.3, dt);
        if (glfwGetKey(w, GLFW_KEY_S) == GLFW_PRESS) mDistance /= std::pow(0.3, dt);
        mCamera.position = mCenter - forward * mDistance;
        return;
    }
    double speed = mSpeed * dt * (glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 4.0 : 1.0);
    glm::dvec3 move(0.0);
    if (glfwGetKey(w, GLFW_KEY_W) == GLFW_PRESS) move += forward;
    if (glfwGetKey(w, GLFW_KEY_S) == GLFW_PRESS) move -= forward;
    if (glfwGetKey(w, GLFW_KEY_D) == GLFW_PRESS) move += right;
    if (glfwGetKey(w, GLFW_KEY_A) == GLFW_PRESS) move -= right;
    if (glfwGetKey(w, GLFW_KEY_E) == GLFW_PRESS) move.y += 1;
    if (glfwGetKey(w, GLFW_KEY_Q) == GLFW_PRESS) move.y -= 1;
    mCamera.position += move * speed;
}

} // namespace pnb::player
