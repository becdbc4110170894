// The rules of the animation chunks (FORMAT.md "MRPH", "SKIN", "ANIM"): what a reader checks
// before any deforming or sampling code sees the data, so that a clip, a skin or a morph can
// neither index out of bounds nor put a NaN into a frame.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "pnb/scene.h"
#include "vertex_read.h"

namespace pnb {

namespace {

Error bad(const char* fmt, auto... args) { return makeError(FormatError::BadReference, 0, fmt, args...); }

bool allFinite(std::span<const float> v) {
    return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

// The floats of an F32 stream (the blob is 16-byte aligned in a payload; copy to be safe with
// any blob a caller built by hand).
std::vector<float> floats(const Blob& data) {
    std::vector<float> out(data.size() / 4);
    if (!out.empty()) std::memcpy(out.data(), data.data(), out.size() * 4);
    return out;
}

using detail::findStream;

bool hasDetail(const Scene& s, uint32_t mesh) {
    return std::any_of(s.meshDetails.begin(), s.meshDetails.end(),
                       [&](const MeshDetail& d) { return d.mesh == mesh; });
}

// A deforming mesh's own position, normal and tangent streams: what the deforming pass reads and
// rewrites, so F32 Plain (FORMAT.md "MRPH").
Status checkDeformedStreams(const Mesh& m, const char* what, size_t i) {
    for (const VertexStream& v : m.streams) {
        const bool moved = v.semantic == VertexSemantic::Position || v.semantic == VertexSemantic::Normal ||
                           v.semantic == VertexSemantic::Tangent;
        if (moved && (v.componentType != ComponentType::F32 || v.encoding != VertexEncoding::Plain ||
                      v.normalized))
            return bad("%s %zu: the deformed mesh's stream %u is not F32 Plain", what, i, unsigned(v.semantic));
    }
    return {};
}

} // namespace

Status validateMorphTargets(const Scene& s, const MorphTargets& t, size_t i) {
    if (t.mesh >= s.meshes.size()) return bad("morph targets %zu: mesh = %u, but there are %zu", i, t.mesh, s.meshes.size());
    const Mesh& mesh = s.meshes[t.mesh];
    if (t.targets.empty() || t.targets.size() > kMaxMorphTargets)
        return bad("morph targets %zu: %zu targets, not 1..%u", i, t.targets.size(), kMaxMorphTargets);
    if (t.weights.size() != t.targets.size())
        return bad("morph targets %zu: %zu default weights for %zu targets", i, t.weights.size(), t.targets.size());
    if (!allFinite(t.weights)) return bad("morph targets %zu: a default weight is not finite", i);
    if (hasDetail(s, t.mesh)) return bad("morph targets %zu: mesh %u has a mesh detail (MDET)", i, t.mesh);
    if (Status st = checkDeformedStreams(mesh, "morph targets", i); !isOk(st)) return st;
    for (size_t k = 0; k < t.targets.size(); ++k) {
        const MorphTarget& target = t.targets[k];
        if (target.name != kNone && target.name >= s.strings.strings.size())
            return bad("morph targets %zu target %zu: name = %u, but there are %zu strings", i, k, target.name,
                       s.strings.strings.size());
        bool seen[3] = {};
        for (const VertexStream& d : target.deltas) {
            const unsigned sem = unsigned(d.semantic);
            if (sem > unsigned(VertexSemantic::Tangent) || seen[sem])
                return bad("morph targets %zu target %zu: delta of semantic %u (Position, Normal, Tangent once each)",
                           i, k, sem);
            seen[sem] = true;
            if (!findStream(mesh, d.semantic))
                return bad("morph targets %zu target %zu: a delta for stream %u, which mesh %u lacks", i, k, sem, t.mesh);
            if (d.componentType != ComponentType::F32 || d.componentCount != 3 || d.normalized ||
                d.encoding != VertexEncoding::Plain || d.data.size() != uint64_t(mesh.vertexCount) * 12)
                return bad("morph targets %zu target %zu: delta %u is not F32 x 3 Plain for %u vertices", i, k,
                           sem, mesh.vertexCount);
            if (!allFinite(floats(d.data)))
                return bad("morph targets %zu target %zu: delta %u holds a value that is not finite", i, k, sem);
        }
    }
    return {};
}

Status validateSkin(const Scene& s, const Skin& skin, size_t i) {
    const size_t nodes = s.nodes.nodes.size();
    if (skin.name != kNone && skin.name >= s.strings.strings.size())
        return bad("skin %zu: name = %u, but there are %zu strings", i, skin.name, s.strings.strings.size());
    if (skin.joints.empty() || skin.joints.size() > kMaxJoints)
        return bad("skin %zu: %zu joints, not 1..%u", i, skin.joints.size(), kMaxJoints);
    for (uint32_t j : skin.joints)
        if (j >= nodes) return bad("skin %zu: joint node = %u, but there are %zu nodes", i, j, nodes);
    if (skin.inverseBindMatrices.size() != skin.joints.size())
        return bad("skin %zu: %zu inverse bind matrices for %zu joints", i, skin.inverseBindMatrices.size(),
                   skin.joints.size());
    for (const auto& m : skin.inverseBindMatrices)
        if (!allFinite(m)) return bad("skin %zu: an inverse bind matrix is not finite", i);
    if (skin.nodes.empty()) return bad("skin %zu: deforms no node", i);
    for (uint32_t n : skin.nodes) {
        if (n >= nodes || s.nodes.nodes[n].mesh == kNone)
            return bad("skin %zu: node %u is not a node with a mesh", i, n);
        if (std::any_of(s.nodes.instances.begin(), s.nodes.instances.end(),
                        [&](const NodeInstances& in) { return in.node == n; }))
            return bad("skin %zu: node %u is instanced (EXT_mesh_gpu_instancing), which a skin cannot deform", i, n);
        const uint32_t meshIndex = s.nodes.nodes[n].mesh;
        const Mesh& mesh = s.meshes[meshIndex];
        if (hasDetail(s, meshIndex)) return bad("skin %zu: mesh %u has a mesh detail (MDET)", i, meshIndex);
        if (Status st = checkDeformedStreams(mesh, "skin", i); !isOk(st)) return st;
        const VertexStream* joints = findStream(mesh, VertexSemantic::Joints0);
        const VertexStream* weights = findStream(mesh, VertexSemantic::Weights0);
        if (!joints || joints->componentCount != 4 || joints->normalized ||
            (joints->componentType != ComponentType::U8 && joints->componentType != ComponentType::U16))
            return bad("skin %zu: mesh %u of node %u has no Joints0 stream of U8 or U16 x 4", i, meshIndex, n);
        if (!weights || weights->componentCount != 4 || weights->componentType != ComponentType::F32 ||
            weights->normalized)
            return bad("skin %zu: mesh %u of node %u has no Weights0 stream of F32 x 4", i, meshIndex, n);
        const size_t values = size_t(mesh.vertexCount) * 4;
        for (size_t k = 0; k < values; ++k) {
            const uint32_t j = detail::streamJoint(*joints, k);
            if (j >= skin.joints.size())
                return bad("skin %zu: mesh %u vertex %zu names joint %u, but the skin has %zu", i, meshIndex, k / 4, j,
                           skin.joints.size());
        }
        const std::vector<float> w = floats(weights->data);
        for (size_t k = 0; k < w.size(); ++k)
            if (!std::isfinite(w[k]) || w[k] < 0)
                return bad("skin %zu: mesh %u vertex %zu has weight %g (finite and >= 0 only)", i, meshIndex, k / 4,
                           double(w[k]));
    }
    return {};
}

namespace {

uint32_t animatedWidth(const Scene& s, const AnimationChannel& c) {
    switch (c.property) {
    case AnimatedProperty::Rotation: return 4;
    case AnimatedProperty::Weights: {
        const uint32_t mesh = s.nodes.nodes[c.node].mesh;
        for (const MorphTargets& t : s.morphTargets)
            if (t.mesh == mesh) return uint32_t(t.targets.size());
        return 0;
    }
    default: return 3;
    }
}

} // namespace

Status validateAnimation(const Scene& s, const Animation& clip, size_t i) {
    if (clip.name != kNone && clip.name >= s.strings.strings.size())
        return bad("animation %zu: name = %u, but there are %zu strings", i, clip.name, s.strings.strings.size());
    if (clip.channels.empty()) return bad("animation %zu: no channels", i);
    std::vector<std::pair<uint32_t, AnimatedProperty>> targets;
    for (size_t k = 0; k < clip.channels.size(); ++k) {
        const AnimationChannel& c = clip.channels[k];
        if (c.node >= s.nodes.nodes.size())
            return bad("animation %zu channel %zu: node = %u, but there are %zu nodes", i, k, c.node,
                       s.nodes.nodes.size());
        targets.emplace_back(c.node, c.property);
        const uint32_t width = animatedWidth(s, c);
        if (width == 0)
            return bad("animation %zu channel %zu: animates the weights of node %u, whose mesh has no morph targets",
                       i, k, c.node);
        if (c.times.empty()) return bad("animation %zu channel %zu: no keys", i, k);
        if (!allFinite(c.times) || !(c.times[0] >= 0))
            return bad("animation %zu channel %zu: a key time is not finite and >= 0", i, k);
        for (size_t t = 1; t < c.times.size(); ++t)
            if (!(c.times[t] > c.times[t - 1]))
                return bad("animation %zu channel %zu: key %zu time %g does not increase", i, k, t, double(c.times[t]));
        const uint64_t expect = uint64_t(c.times.size()) * width * (c.interpolation == KeyInterpolation::CubicSpline ? 3 : 1);
        if (c.values.size() != expect)
            return bad("animation %zu channel %zu: %zu values, %zu keys of %u need %llu", i, k, c.values.size(),
                       c.times.size(), width, (unsigned long long)expect);
        if (!allFinite(c.values)) return bad("animation %zu channel %zu: a key value is not finite", i, k);
    }
    std::sort(targets.begin(), targets.end());
    if (std::adjacent_find(targets.begin(), targets.end()) != targets.end())
        return bad("animation %zu: two channels animate the same property of one node", i);
    return {};
}

Status validateAnimationChunks(const Scene& s) {
    std::vector<bool> morphed(s.meshes.size()), skinned(s.nodes.nodes.size());
    for (size_t i = 0; i < s.morphTargets.size(); ++i) {
        if (Status st = validateMorphTargets(s, s.morphTargets[i], i); !isOk(st)) return st;
        if (morphed[s.morphTargets[i].mesh]) return bad("morph targets %zu: mesh %u has some already", i, s.morphTargets[i].mesh);
        morphed[s.morphTargets[i].mesh] = true;
    }
    for (size_t i = 0; i < s.skins.size(); ++i) {
        if (Status st = validateSkin(s, s.skins[i], i); !isOk(st)) return st;
        for (uint32_t n : s.skins[i].nodes) {
            if (skinned[n]) return bad("skin %zu: node %u is deformed by another skin", i, n);
            skinned[n] = true;
        }
    }
    for (size_t i = 0; i < s.animations.size(); ++i)
        if (Status st = validateAnimation(s, s.animations[i], i); !isOk(st)) return st;
    return {};
}

} // namespace pnb
