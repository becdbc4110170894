#include "pnb_player/camera_path.h"

#include <algorithm>
#include <cmath>

namespace pnb::player {

namespace {

struct Key {
    double t;
    glm::dvec3 p;
    glm::dvec4 q; // xyzw
    double fov;
};

Key key(const CameraPath& path, size_t i) {
    const CameraKey& k = path.keys[i];
    return {k.timeSeconds, {k.position.x, k.position.y, k.position.z},
            {k.rotation.x, k.rotation.y, k.rotation.z, k.rotation.w}, k.yfovRadians};
}

double loopGap(const CameraPath& path) {
    size_t n = path.keys.size();
    return (double(path.keys[n - 1].timeSeconds) - path.keys[0].timeSeconds) / double(n - 1);
}

// Key i of the (possibly looped) sequence, for i in [-1, n]; times shift by a period on wrap.
Key keyAt(const CameraPath& path, long i) {
    long n = long(path.keys.size());
    if (!path.loop) return key(path, size_t(std::clamp(i, 0L, n - 1)));
    double period = pathDuration(path);
    long wrapped = ((i % n) + n) % n;
    Key k = key(path, size_t(wrapped));
    k.t += period * double((i - wrapped) / n);
    return k;
}

template <class T> T hermite(const T& p0, const T& p1, const T& m0, const T& m1, double s, double dt) {
    double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * dt * m0 + (-2 * s3 + 3 * s2) * p1 +
           (s3 - s2) * dt * m1;
}

} // namespace

double pathDuration(const CameraPath& path) {
    size_t n = path.keys.size();
    if (n < 2) return 0;
    double span = double(path.keys[n - 1].timeSeconds) - path.keys[0].timeSeconds;
    return path.loop ? span + loopGap(path) : span;
}

void evaluatePath(const CameraPath& path, double time, CameraState& camera) {
    long n = long(path.keys.size());
    Key first = key(path, 0);
    if (n == 1) {
        camera.position = first.p;
        camera.rotation = glm::dquat(first.q.w, first.q.x, first.q.y, first.q.z);
        camera.yfovRadians = float(first.fov);
        return;
    }
    double duration = pathDuration(path);
    double t = time - first.t;
    t = path.loop ? t - duration * std::floor(t / duration) : std::clamp(t, 0.0, duration);
    t += first.t;
    long i = 0; // segment [i, i + 1]
    while (i + 1 < (path.loop ? n : n - 1) && keyAt(path, i + 1).t <= t) ++i;
    Key k0 = keyAt(path, i), k1 = keyAt(path, i + 1);
    double dt = k1.t - k0.t;
    double s = dt > 0 ? std::clamp((t - k0.t) / dt, 0.0, 1.0) : 0.0;
    // Quaternions on one hemisphere so interpolation takes the short way round.
    if (glm::dot(k0.q, k1.q) < 0) k1.q = -k1.q;

    glm::dvec3 p;
    glm::dvec4 q;
    double fov;
    if (path.interpolation == Interpolation::Linear) {
        p = glm::mix(k0.p, k1.p, s);
        glm::dquat a(k0.q.w, k0.q.x, k0.q.y, k0.q.z), b(k1.q.w, k1.q.x, k1.q.y, k1.q.z);
        glm::dquat r = glm::slerp(a, b, s);
        q = {r.x, r.y, r.z, r.w};
        fov = glm::mix(k0.fov, k1.fov, s);
    } else {
        Key km = keyAt(path, i - 1), kp = keyAt(path, i + 2);
        if (glm::dot(km.q, k0.q) < 0) km.q = -km.q;
        if (glm::dot(kp.q, k1.q) < 0) kp.q = -kp.q;
        // Catmull-Rom tangents over the neighbours' times; one-sided at open ends.
        auto tangent = [](const auto& prev, const auto& next, double tPrev, double tNext) {
            double span = tNext - tPrev;
            return span > 0 ? (next - prev) / span : next - next;
        };
        double t0m = km.t < k0.t ? km.t : k0.t, t1p = kp.t > k1.t ? kp.t : k1.t;
        auto pm = km.t < k0.t ? km.p : k0.p, pp = kp.t > k1.t ? kp.p : k1.p;
        auto qm = km.t < k0.t ? km.q : k0.q, qp = kp.t > k1.t ? kp.q : k1.q;
        double fm = km.t < k0.t ? km.fov : k0.fov, fp = kp.t > k1.t ? kp.fov : k1.fov;
        p = hermite(k0.p, k1.p, tangent(pm, k1.p, t0m, k1.t), tangent(k0.p, pp, k0.t, t1p), s, dt);
        q = hermite(k0.q, k1.q, tangent(qm, k1.q, t0m, k1.t), tangent(k0.q, qp, k0.t, t1p), s, dt);
        fov = hermite(k0.fov, k1.fov, tangent(fm, k1.fov, t0m, k1.t), tangent(k0.fov, fp, k0.t, t1p),
                      s, dt);
        q = glm::normalize(q);
    }
    camera.position = p;
    camera.rotation = glm::dquat(q.w, q.x, q.y, q.z);
    camera.yfovRadians = float(fov);
}

} // namespace pnb::player
