// converter/src/import_gltf_animation.cpp — glTF skins and animations into the scene IR (the
// glTF importer's last stage, after the node trees: both refer to nodes by their IR index).
//
// Skins: joints, inverse bind matrices (identity when the accessor is absent), and the check
// that every joint index of a skinned node's mesh is below the skin's joint count. Animations:
// node TRS and morph-weight channels with their keys as pnb::AnimationChannel stores them.
// KHR_animation_pointer channels are skipped (the rest pose; checkExtensions notes the
// extension). Malformed data is an error naming the file, the animation, the channel and the
// accessor; a channel of a node outside the imported scene is dropped with a warning.
//
// Index: [SECTION] skins, [SECTION] animations
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "import_gltf_internal.h"

namespace pnb::converter::gltf_internal {

namespace {

// [SECTION] skins

constexpr std::array<float, 16> kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

// glTF skin `index` as an IR skin.
Result<IrSkin, ConvertError> importSkin(Ctx& ctx, int index) {
    const tinygltf::Skin& src = ctx.model.skins[size_t(index)];
    const std::string who = label("skin", index, ctx.model.skins);
    if (src.joints.empty()) return ctx.fail(who + ": no joints");
    if (src.joints.size() > kMaxJoints)
        return ctx.fail(strf("%s: %zu joints, at most %u are supported", who.c_str(),
                             src.joints.size(), kMaxJoints));
    IrSkin skin;
    skin.name = src.name;
    for (size_t k = 0; k < src.joints.size(); ++k) {
        const int j = src.joints[k];
        if (j < 0 || size_t(j) >= ctx.model.nodes.size())
            return ctx.fail(strf("%s joint %zu: node %d does not exist (%zu nodes)", who.c_str(), k,
                                 j, ctx.model.nodes.size()));
        if (ctx.nodeMap[size_t(j)] < 0)
            return ctx.fail(strf("%s joint %zu: %s is not in the imported scene", who.c_str(), k,
                                 label("node", j, ctx.model.nodes).c_str()));
        skin.joints.push_back(ctx.nodeMap[size_t(j)]);
    }
    skin.inverseBindMatrices.assign(src.joints.size(), kIdentity);
    if (src.inverseBindMatrices >= 0) {
        const std::string where = who + " inverseBindMatrices";
        int components = 0;
        auto m = readFloats(ctx, src.inverseBindMatrices, where, {16, 16, false}, components);
        if (!m) return m.error();
        const size_t count = m->size() / 16;
        if (count < src.joints.size())
            return ctx.fail(strf("%s: %zu matrices for %zu joints",
                                 accessorWho(src.inverseBindMatrices, where).c_str(), count,
                                 src.joints.size()));
        if (count > src.joints.size())
            ctx.warn(strf("%s: %zu matrices for %zu joints; the extra ones ignored",
                          accessorWho(src.inverseBindMatrices, where).c_str(), count,
                          src.joints.size()));
        for (size_t k = 0; k < src.joints.size(); ++k) {
            for (size_t c = 0; c < 16; ++c) {
                const float v = (*m)[k * 16 + c];
                if (!std::isfinite(v))
                    return ctx.fail(strf("%s: matrix %zu is not finite",
                                         accessorWho(src.inverseBindMatrices, where).c_str(), k));
                skin.inverseBindMatrices[k][c] = v;
            }
        }
    }
    return skin;
}

// Every joint index of IR mesh `mesh` is below `jointCount`, or an error naming the node, the
// skin, the mesh, the primitive and the vertex.
Check checkJointIndices(Ctx& ctx, const IrMesh& mesh, size_t jointCount, const std::string& who) {
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const std::vector<uint32_t>& joints = mesh.primitives[p].joints;
        for (size_t k = 0; k < joints.size(); ++k)
            if (joints[k] >= jointCount)
                return ctx.fail(strf("%s: mesh '%s' primitive %zu JOINTS_0 vertex %zu names joint "
                                     "%u, but the skin has %zu joints",
                                     who.c_str(), mesh.name.c_str(), p, k / 4, joints[k],
                                     jointCount));
    }
    return std::nullopt;
}

// [SECTION] animations

const char* propertyName(AnimatedProperty p) {
    switch (p) {
    case AnimatedProperty::Translation: return "translation";
    case AnimatedProperty::Rotation: return "rotation";
    case AnimatedProperty::Scale: return "scale";
    default: return "weights";
    }
}

// One channel's keys, read and checked. `who` names the animation and the channel.
Result<IrAnimationChannel, ConvertError> importChannel(Ctx& ctx, const tinygltf::Animation& anim,
                                                       const tinygltf::AnimationChannel& c,
                                                       AnimatedProperty property, int irNode,
                                                       const std::string& who, size_t& repaired) {
    IrAnimationChannel out;
    out.node = irNode;
    out.property = property;
    if (c.sampler < 0 || size_t(c.sampler) >= anim.samplers.size())
        return ctx.fail(strf("%s: sampler %d does not exist (%zu samplers)", who.c_str(), c.sampler,
                             anim.samplers.size()));
    const tinygltf::AnimationSampler& s = anim.samplers[size_t(c.sampler)];
    const std::string samplerWho = strf("%s sampler %d", who.c_str(), c.sampler);
    if (s.interpolation == "STEP") out.interpolation = KeyInterpolation::Step;
    else if (s.interpolation == "LINEAR" || s.interpolation.empty()) out.interpolation = KeyInterpolation::Linear;
    else if (s.interpolation == "CUBICSPLINE") out.interpolation = KeyInterpolation::CubicSpline;
    else return ctx.fail(samplerWho + ": interpolation '" + s.interpolation + "' is unknown");

    size_t width = 3;
    if (property == AnimatedProperty::Rotation) width = 4;
    if (property == AnimatedProperty::Weights) {
        const IrNode& node = ctx.scene.nodes[size_t(irNode)];
        width = node.mesh >= 0 ? ctx.scene.meshes[size_t(node.mesh)].morphWeights.size() : 0;
    }
    int components = 0;
    auto times = readFloats(ctx, s.input, samplerWho + " input", {1, 1, false}, components);
    if (!times) return times.error();
    const int valueComponents = property == AnimatedProperty::Weights ? 1 : int(width);
    auto values = readFloats(ctx, s.output, samplerWho + " output",
                             {valueComponents, valueComponents, false}, components);
    if (!values) return values.error();
    const size_t keys = times->size();
    const size_t perKey = width * (out.interpolation == KeyInterpolation::CubicSpline ? 3 : 1);
    if (values->size() != keys * perKey)
        return ctx.fail(strf("%s: input %s has %zu keys, output %s has %zu values, %zu needed "
                             "(%zu per key)",
                             samplerWho.c_str(), strf("accessor %d", s.input).c_str(), keys,
                             strf("accessor %d", s.output).c_str(), values->size(), keys * perKey,
                             perKey));
    for (size_t k = 0; k < keys; ++k) {
        const float t = (*times)[k];
        if (!std::isfinite(t) || t < 0)
            return ctx.fail(strf("%s: %s key %zu time %g is not a finite time >= 0", samplerWho.c_str(),
                                 accessorWho(s.input, "input").c_str(), k, double(t)));
        if (k > 0 && !(t > (*times)[k - 1]))
            return ctx.fail(strf("%s: %s key %zu time %g does not increase (key %zu is at %g)",
                                 samplerWho.c_str(), accessorWho(s.input, "input").c_str(), k,
                                 double(t), k - 1, double((*times)[k - 1])));
    }
    for (size_t v = 0; v < values->size(); ++v)
        if (!std::isfinite((*values)[v]))
            return ctx.fail(strf("%s: %s key %zu holds a value that is not finite", samplerWho.c_str(),
                                 accessorWho(s.output, "output").c_str(), v / perKey));
    // Rotation values (not tangents) normalised: a zero quaternion becomes the identity.
    if (property == AnimatedProperty::Rotation) {
        const bool cubic = out.interpolation == KeyInterpolation::CubicSpline;
        for (size_t k = 0; k < keys; ++k) {
            float* q = &(*values)[k * perKey + (cubic ? 4 : 0)];
            const double len = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] +
                                         double(q[2]) * q[2] + double(q[3]) * q[3]);
            if (len > 1e-12 && std::isfinite(len)) {
                if (std::abs(len - 1.0) > 1e-3) ++repaired;
                for (int i = 0; i < 4; ++i) q[i] = float(q[i] / len);
            } else {
                ++repaired;
                q[0] = q[1] = q[2] = 0;
                q[3] = 1;
            }
        }
    }
    out.times = std::move(times).value();
    out.values = std::move(values).value();
    return out;
}

Result<std::optional<IrAnimation>, ConvertError> importAnimation(Ctx& ctx, int index) {
    const tinygltf::Animation& src = ctx.model.animations[size_t(index)];
    const std::string who = label("animation", index, ctx.model.animations);
    IrAnimation clip;
    clip.name = src.name;
    size_t pointers = 0, outside = 0, repaired = 0, noMorph = 0;
    std::map<std::pair<int, AnimatedProperty>, size_t> seen; // (node, property) → channel
    for (size_t ci = 0; ci < src.channels.size(); ++ci) {
        const tinygltf::AnimationChannel& c = src.channels[ci];
        const std::string& path = c.target_path;
        if (path == "pointer") {
            ++pointers;
            continue;
        }
        AnimatedProperty property;
        if (path == "translation") property = AnimatedProperty::Translation;
        else if (path == "rotation") property = AnimatedProperty::Rotation;
        else if (path == "scale") property = AnimatedProperty::Scale;
        else if (path == "weights") property = AnimatedProperty::Weights;
        else return ctx.fail(strf("%s channel %zu: target path '%s' is unknown", who.c_str(), ci, path.c_str()));
        if (c.target_node < 0 || size_t(c.target_node) >= ctx.model.nodes.size())
            return ctx.fail(strf("%s channel %zu: target node %d does not exist (%zu nodes)",
                                 who.c_str(), ci, c.target_node, ctx.model.nodes.size()));
        const int irNode = ctx.nodeMap[size_t(c.target_node)];
        if (irNode < 0) {
            ++outside;
            continue;
        }
        const std::string channelWho =
            strf("%s channel %zu (%s %s)", who.c_str(), ci,
                 label("node", c.target_node, ctx.model.nodes).c_str(), propertyName(property));
        if (property == AnimatedProperty::Weights) {
            const IrNode& node = ctx.scene.nodes[size_t(irNode)];
            if (node.mesh < 0 || ctx.scene.meshes[size_t(node.mesh)].morphWeights.empty()) {
                ++noMorph;
                continue;
            }
        }
        auto channel = importChannel(ctx, src, c, property, irNode, channelWho, repaired);
        if (!channel) return channel.error();
        auto [it, fresh] = seen.emplace(std::make_pair(irNode, property), clip.channels.size());
        if (!fresh) {
            ctx.warn(channelWho + ": animates what an earlier channel of the clip does; this one is kept");
            clip.channels[it->second] = std::move(channel).value();
            continue;
        }
        clip.channels.push_back(std::move(channel).value());
    }
    if (pointers)
        ctx.warn(strf("%s: %zu KHR_animation_pointer channels not played (the rest pose)", who.c_str(), pointers));
    if (outside)
        ctx.warn(strf("%s: %zu channels animate nodes outside the imported scene; dropped", who.c_str(), outside));
    if (noMorph)
        ctx.warn(strf("%s: %zu weights channels animate nodes without morph targets; dropped", who.c_str(), noMorph));
    if (repaired)
        ctx.warn(strf("%s: %zu rotation keys were not unit quaternions; normalised (a zero one is the identity)",
                      who.c_str(), repaired));
    if (clip.channels.empty()) {
        ctx.warn(who + ": no channel left to play; dropped");
        return std::optional<IrAnimation>();
    }
    for (const IrAnimationChannel& c : clip.channels) {
        const uint64_t bytes = (c.times.size() + c.values.size()) * sizeof(float);
        if (auto e = ctx.fits(bytes, who)) return *e;
        ctx.retainedBytes += bytes;
    }
    return std::optional<IrAnimation>(std::move(clip));
}

} // namespace

Check importSkins(Ctx& ctx) {
    std::vector<int> irSkin(ctx.model.skins.size(), -1);
    std::set<std::pair<int, int>> checked; // (IR mesh, IR skin) pairs whose joints were checked
    for (IrNode& node : ctx.scene.nodes) {
        if (node.skin < 0) continue;
        const int gltfSkin = node.skin;
        if (irSkin[size_t(gltfSkin)] < 0) {
            auto skin = importSkin(ctx, gltfSkin);
            if (!skin) return skin.error();
            ctx.scene.skins.push_back(std::move(skin).value());
            irSkin[size_t(gltfSkin)] = int(ctx.scene.skins.size() - 1);
        }
        node.skin = irSkin[size_t(gltfSkin)];
        if (checked.emplace(node.mesh, node.skin).second) {
            const std::string who =
                strf("node '%s' (%s, %zu joints)", node.name.c_str(),
                     label("skin", gltfSkin, ctx.model.skins).c_str(),
                     ctx.scene.skins[size_t(node.skin)].joints.size());
            if (auto e = checkJointIndices(ctx, ctx.scene.meshes[size_t(node.mesh)],
                                           ctx.scene.skins[size_t(node.skin)].joints.size(), who))
                return e;
        }
    }
    return std::nullopt;
}

Check importAnimations(Ctx& ctx) {
    for (size_t i = 0; i < ctx.model.animations.size(); ++i) {
        auto clip = importAnimation(ctx, int(i));
        if (!clip) return clip.error();
        if (clip->has_value()) ctx.scene.animations.push_back(std::move(**clip));
    }
    return std::nullopt;
}

} // namespace pnb::converter::gltf_internal
