// Clip sampling, joint matrices and CPU deformation (pnb/animation_pose.h).

#include "pnb/animation_pose.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "vertex_read.h"

namespace pnb {

namespace {

using detail::findStream;
// General 4x4 inverse (cofactors); the identity for a singular matrix.
Matrix4d inverse(const Matrix4d& m) {
    Matrix4d inv{};
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    const double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    if (det == 0 || !std::isfinite(det)) return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    for (double& v : inv) v /= det;
    return inv;
}

// Keys k and k + 1 around time t, and the fraction between them (clamped outside the keys).
struct Span {
    size_t k0 = 0, k1 = 0;
    double s = 0, dt = 0;
};
Span findSpan(const std::vector<float>& times, double t) {
    if (t <= times.front() || times.size() == 1) return {};
    if (t >= times.back()) return {times.size() - 1, times.size() - 1, 0, 0};
    const size_t k1 = size_t(std::upper_bound(times.begin(), times.end(), float(t)) - times.begin());
    const size_t k0 = k1 - 1;
    const double dt = double(times[k1]) - double(times[k0]);
    return {k0, k1, std::clamp((t - double(times[k0])) / dt, 0.0, 1.0), dt};
}

// Samples channel `c` (`width` floats per value) at t into `out`.
void sampleChannel(const AnimationChannel& c, size_t width, double t, std::vector<double>& out) {
    out.assign(width, 0.0);
    const Span sp = findSpan(c.times, t);
    const bool cubic = c.interpolation == KeyInterpolation::CubicSpline;
    const size_t stride = cubic ? 3 * width : width, valueAt = cubic ? width : 0;
    auto value = [&](size_t k, size_t i) { return double(c.values[k * stride + valueAt + i]); };
    if (sp.k0 == sp.k1 || c.interpolation == KeyInterpolation::Step) {
        for (size_t i = 0; i < width; ++i) out[i] = value(sp.k0, i);
        return;
    }
    const double s = sp.s;
    if (cubic) {
        const double s2 = s * s, s3 = s2 * s;
        for (size_t i = 0; i < width; ++i) {
            const double outTangent = c.values[sp.k0 * stride + 2 * width + i];
            const double inTangent = c.values[sp.k1 * stride + i];
            const double v = (2 * s3 - 3 * s2 + 1) * value(sp.k0, i) + (s3 - 2 * s2 + s) * sp.dt * outTangent +
                             (-2 * s3 + 3 * s2) * value(sp.k1, i) + (s3 - s2) * sp.dt * inTangent;
            out[i] = v;
        }
    } else if (c.property == AnimatedProperty::Rotation) {
        double a[4], b[4], dot = 0;
        for (int i = 0; i < 4; ++i) a[i] = value(sp.k0, size_t(i)), b[i] = value(sp.k1, size_t(i)), dot += a[i] * b[i];
        if (dot < 0) {
            for (double& x : b) x = -x;
            dot = -dot;
        }
        double wa = 1 - s, wb = s;
        if (dot < 0.9995) { // slerp; nearly parallel keys interpolate linearly (then normalise)
            const double theta = std::acos(std::min(dot, 1.0)), sinTheta = std::sin(theta);
            wa = std::sin((1 - s) * theta) / sinTheta, wb = std::sin(s * theta) / sinTheta;
        }
        for (int i = 0; i < 4; ++i) out[size_t(i)] = wa * a[i] + wb * b[i];
    } else {
        for (size_t i = 0; i < width; ++i) out[i] = (1 - s) * value(sp.k0, i) + s * value(sp.k1, i);
    }
    // A value float cannot hold (extreme tangents) takes the nearer key's.
    for (size_t i = 0; i < width; ++i)
        if (!std::isfinite(float(out[i]))) out[i] = value(s < 0.5 ? sp.k0 : sp.k1, i);
}

Vec3 transformPoint(const std::array<float, 16>& m, Vec3 p) {
    return {m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
            m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]};
}
Vec3 transformVector(const std::array<float, 16>& m, Vec3 p) {
    return {m[0] * p.x + m[4] * p.y + m[8] * p.z, m[1] * p.x + m[5] * p.y + m[9] * p.z,
            m[2] * p.x + m[6] * p.y + m[10] * p.z};
}
Vec3 normalised(Vec3 v) {
    const float l = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    return l > 0 && std::isfinite(l) ? Vec3{v.x / l, v.y / l, v.z / l} : Vec3{0, 0, 1};
}

} // namespace

double clipDuration(const Animation& clip) {
    double d = 0;
    for (const AnimationChannel& c : clip.channels)
        if (!c.times.empty()) d = std::max(d, double(c.times.back()));
    return d;
}

double clipTime(double duration, double t, bool loop) {
    if (!(duration > 0) || !std::isfinite(t)) return 0;
    if (!loop) return std::clamp(t, 0.0, duration);
    const double r = std::fmod(t, duration);
    return r < 0 ? r + duration : r;
}

const Skin* skinOf(const Scene& scene, uint32_t node) {
    for (const Skin& s : scene.skins)
        if (std::find(s.nodes.begin(), s.nodes.end(), node) != s.nodes.end()) return &s;
    return nullptr;
}

const MorphTargets* morphTargetsOf(const Scene& scene, uint32_t mesh) {
    for (const MorphTargets& t : scene.morphTargets)
        if (t.mesh == mesh) return &t;
    return nullptr;
}

bool isDeformed(const Scene& scene, uint32_t node) {
    const uint32_t mesh = scene.nodes.nodes[node].mesh;
    return mesh != kNone && (skinOf(scene, node) || morphTargetsOf(scene, mesh));
}

Pose restPose(const Scene& scene) {
    Pose p;
    p.graph = scene.nodes;
    p.weights.resize(scene.nodes.nodes.size());
    for (size_t n = 0; n < scene.nodes.nodes.size(); ++n)
        if (const uint32_t mesh = scene.nodes.nodes[n].mesh; mesh != kNone)
            if (const MorphTargets* t = morphTargetsOf(scene, mesh)) p.weights[n] = t->weights;
    return p;
}

void applyClip(const Scene& scene, const Animation& clip, double t, Pose& pose) {
    std::vector<double> v;
    for (const AnimationChannel& c : clip.channels) {
        if (c.node >= pose.graph.nodes.size() || c.times.empty()) continue;
        Node& n = pose.graph.nodes[c.node];
        switch (c.property) {
        case AnimatedProperty::Translation:
            sampleChannel(c, 3, t, v);
            n.translation = {float(v[0]), float(v[1]), float(v[2])};
            break;
        case AnimatedProperty::Scale:
            sampleChannel(c, 3, t, v);
            n.scale = {float(v[0]), float(v[1]), float(v[2])};
            break;
        case AnimatedProperty::Rotation: {
            sampleChannel(c, 4, t, v);
            const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
            n.rotation = l > 0 ? Vec4{float(v[0] / l), float(v[1] / l), float(v[2] / l), float(v[3] / l)}
                               : Vec4{0, 0, 0, 1};
            break;
        }
        case AnimatedProperty::Weights: {
            std::vector<float>& w = pose.weights[c.node];
            if (w.empty()) break;
            sampleChannel(c, w.size(), t, v);
            for (size_t i = 0; i < w.size(); ++i) w[i] = float(v[i]);
            break;
        }
        default: break;
        }
    }
    (void)scene;
}

Pose poseAt(const Scene& scene, std::optional<uint32_t> clip, double t) {
    Pose p = restPose(scene);
    if (clip && *clip < scene.animations.size()) {
        const Animation& a = scene.animations[*clip];
        applyClip(scene, a, clipTime(clipDuration(a), t), p);
    }
    return p;
}

Matrix4d skinnedPlacement(const Matrix4d& w) {
    return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, w[12], w[13], w[14], 1};
}

std::vector<std::array<float, 16>> jointMatrices(const Skin& skin, const std::vector<Matrix4d>& world, uint32_t node) {
    const Matrix4d toPlacement = inverse(skinnedPlacement(world[node]));
    std::vector<std::array<float, 16>> out(skin.joints.size());
    for (size_t k = 0; k < skin.joints.size(); ++k) {
        Matrix4d ibm;
        for (int i = 0; i < 16; ++i) ibm[size_t(i)] = skin.inverseBindMatrices[k][size_t(i)];
        const Matrix4d j = multiply(toPlacement, multiply(world[skin.joints[k]], ibm));
        for (int i = 0; i < 16; ++i) out[k][size_t(i)] = float(j[size_t(i)]);
    }
    return out;
}

Matrix4d drawingMatrix(const Scene& scene, uint32_t node, const std::vector<Matrix4d>& world) {
    return skinOf(scene, node) ? skinnedPlacement(world[node]) : world[node];
}

DeformedVertices deformVertices(const Scene& scene, uint32_t node, const Pose& pose, const std::vector<Matrix4d>& world) {
    DeformedVertices out;
    const uint32_t meshIndex = scene.nodes.nodes[node].mesh;
    if (meshIndex == kNone) return out;
    const Mesh& mesh = scene.meshes[meshIndex];
    const size_t n = mesh.vertexCount;
    auto read3 = [&](VertexSemantic s, std::vector<Vec3>& dst) {
        const VertexStream* st = findStream(mesh, s);
        if (!st || st->componentType != ComponentType::F32 || st->componentCount < 3) return;
        dst.resize(n);
        for (size_t v = 0; v < n; ++v)
            dst[v] = {detail::streamFloat(st->data, v * st->componentCount), detail::streamFloat(st->data, v * st->componentCount + 1),
                      detail::streamFloat(st->data, v * st->componentCount + 2)};
    };
    read3(VertexSemantic::Position, out.positions);
    read3(VertexSemantic::Normal, out.normals);
    if (const VertexStream* st = findStream(mesh, VertexSemantic::Tangent);
        st && st->componentType == ComponentType::F32 && st->componentCount == 4) {
        out.tangents.resize(n);
        for (size_t v = 0; v < n; ++v)
            out.tangents[v] = {detail::streamFloat(st->data, v * 4), detail::streamFloat(st->data, v * 4 + 1),
                               detail::streamFloat(st->data, v * 4 + 2), detail::streamFloat(st->data, v * 4 + 3)};
    }
    // Morph targets at the node's weights.
    if (const MorphTargets* targets = morphTargetsOf(scene, meshIndex)) {
        const std::vector<float>& w = pose.weights[node];
        for (size_t k = 0; k < targets->targets.size() && k < w.size(); ++k) {
            if (w[k] == 0) continue;
            for (const VertexStream& d : targets->targets[k].deltas) {
                for (size_t v = 0; v < n; ++v) {
                    const Vec3 delta{detail::streamFloat(d.data, 3 * v) * w[k], detail::streamFloat(d.data, 3 * v + 1) * w[k],
                                     detail::streamFloat(d.data, 3 * v + 2) * w[k]};
                    auto add = [&](auto& p) { p.x += delta.x, p.y += delta.y, p.z += delta.z; };
                    if (d.semantic == VertexSemantic::Position && !out.positions.empty()) add(out.positions[v]);
                    if (d.semantic == VertexSemantic::Normal && !out.normals.empty()) add(out.normals[v]);
                    if (d.semantic == VertexSemantic::Tangent && !out.tangents.empty()) add(out.tangents[v]);
                }
            }
        }
    }
    const Skin* skin = skinOf(scene, node);
    const VertexStream* joints = findStream(mesh, VertexSemantic::Joints0);
    const VertexStream* weights = findStream(mesh, VertexSemantic::Weights0);
    if (skin && joints && weights) {
        const auto jm = jointMatrices(*skin, world, node);
        for (size_t v = 0; v < n; ++v) {
            std::array<float, 16> m{};
            float sum = 0;
            for (size_t i = 0; i < 4; ++i) sum += detail::streamFloat(weights->data, 4 * v + i);
            if (!(sum > 0)) continue;
            for (size_t i = 0; i < 4; ++i) {
                const float w = detail::streamFloat(weights->data, 4 * v + i) / sum;
                const uint32_t j = std::min<uint32_t>(detail::streamJoint(*joints, 4 * v + i), uint32_t(jm.size() - 1));
                for (size_t e = 0; e < 16; ++e) m[e] += w * jm[j][e];
            }
            if (!out.positions.empty()) out.positions[v] = transformPoint(m, out.positions[v]);
            if (!out.normals.empty()) out.normals[v] = transformVector(m, out.normals[v]);
            if (!out.tangents.empty()) {
                const Vec3 t = transformVector(m, {out.tangents[v].x, out.tangents[v].y, out.tangents[v].z});
                out.tangents[v] = {t.x, t.y, t.z, out.tangents[v].w};
            }
        }
    }
    // A vertex carried beyond float (extreme but finite joints or deltas) stays where the mesh
    // stores it, so no frame holds a NaN (FORMAT.md "SKIN"; deform.comp does the same).
    if (const VertexStream* stored = findStream(mesh, VertexSemantic::Position))
        for (size_t v = 0; v < out.positions.size(); ++v) {
            const Vec3& p = out.positions[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                out.positions[v] = {detail::streamFloat(stored->data, 3 * v), detail::streamFloat(stored->data, 3 * v + 1),
                                    detail::streamFloat(stored->data, 3 * v + 2)};
        }
    for (Vec3& nrm : out.normals) nrm = normalised(nrm);
    for (Vec4& t : out.tangents) {
        const Vec3 d = normalised({t.x, t.y, t.z});
        t = {d.x, d.y, d.z, t.w};
    }
    return out;
}

DeformBounds deformBounds(const Scene& scene, uint32_t node) {
    DeformBounds b;
    const uint32_t meshIndex = scene.nodes.nodes[node].mesh;
    if (meshIndex == kNone) return b;
    const Mesh& mesh = scene.meshes[meshIndex];
    const VertexStream* pos = findStream(mesh, VertexSemantic::Position);
    if (!pos || pos->componentType != ComponentType::F32) return b;
    auto position = [&](size_t v) {
        return Vec3{detail::streamFloat(pos->data, 3 * v), detail::streamFloat(pos->data, 3 * v + 1), detail::streamFloat(pos->data, 3 * v + 2)};
    };
    const Skin* skin = skinOf(scene, node);
    const VertexStream* joints = findStream(mesh, VertexSemantic::Joints0);
    const VertexStream* weights = findStream(mesh, VertexSemantic::Weights0);
    if (skin && joints && weights) {
        b.jointBoxes.resize(skin->joints.size());
        for (size_t v = 0; v < mesh.vertexCount; ++v) {
            float sum = 0;
            for (size_t i = 0; i < 4; ++i) sum += detail::streamFloat(weights->data, 4 * v + i);
            if (!(sum > 0)) { // deformVertices leaves it unskinned: no joint moves it
                b.unskinned.grow(position(v));
                continue;
            }
            for (size_t i = 0; i < 4; ++i)
                if (detail::streamFloat(weights->data, 4 * v + i) > 0) {
                    const uint32_t j = std::min<uint32_t>(detail::streamJoint(*joints, 4 * v + i), uint32_t(b.jointBoxes.size() - 1));
                    b.jointBoxes[j].grow(position(v));
                }
        }
    } else {
        b.jointBoxes.resize(1);
        for (size_t v = 0; v < mesh.vertexCount; ++v) b.jointBoxes[0].grow(position(v));
    }
    if (const MorphTargets* targets = morphTargetsOf(scene, meshIndex))
        for (const MorphTarget& t : targets->targets) {
            float reach = 0;
            for (const VertexStream& d : t.deltas)
                if (d.semantic == VertexSemantic::Position)
                    for (size_t v = 0; v < mesh.vertexCount; ++v) {
                        const float x = detail::streamFloat(d.data, 3 * v), y = detail::streamFloat(d.data, 3 * v + 1),
                                    z = detail::streamFloat(d.data, 3 * v + 2);
                        reach = std::max(reach, std::sqrt(x * x + y * y + z * z));
                    }
            b.targetReach.push_back(reach);
        }
    return b;
}

Aabb deformedBounds(const DeformBounds& b, const std::vector<std::array<float, 16>>& joints, const std::vector<float>& weights) {
    float grow = 0;
    for (size_t k = 0; k < b.targetReach.size() && k < weights.size(); ++k) grow += std::abs(weights[k]) * b.targetReach[k];
    Aabb out;
    if (!b.unskinned.empty())
        for (int c = 0; c < 8; ++c)
            out.grow({c & 1 ? b.unskinned.max.x + grow : b.unskinned.min.x - grow,
                      c & 2 ? b.unskinned.max.y + grow : b.unskinned.min.y - grow,
                      c & 4 ? b.unskinned.max.z + grow : b.unskinned.min.z - grow});
    for (size_t j = 0; j < b.jointBoxes.size(); ++j) {
        const Aabb& box = b.jointBoxes[j];
        if (box.empty()) continue;
        const Vec3 lo{box.min.x - grow, box.min.y - grow, box.min.z - grow};
        const Vec3 hi{box.max.x + grow, box.max.y + grow, box.max.z + grow};
        for (int c = 0; c < 8; ++c) {
            const Vec3 p{c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z};
            out.grow(joints.empty() ? p : transformPoint(joints[std::min(j, joints.size() - 1)], p));
        }
    }
    return out;
}

} // namespace pnb
