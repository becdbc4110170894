// converter/src/import_assimp_animation.cpp — assimp bones and node animations into the scene IR
// (skins and clips; import_assimp_internal.h). Runs after the node tree, because both refer to
// nodes by name.
//
// Bones: each aiBone names its joint node (a mesh with a bone naming no node stays unskinned,
// warned); its offset matrix (mesh space to bone space in the
// bind pose) is the joint's inverse bind matrix. An IR mesh made of several aiMeshes gets one
// skin whose joints are the union of their bones (by name). Per vertex the 4 largest influences
// are kept (mesh processing renormalises them), with one warning per mesh when more were cut.
// Node animations: position, rotation and scaling keys become a channel each, times in seconds
// (ticks / mTicksPerSecond, 25 ticks per second when the file says 0), assimp's quaternions
// (w, x, y, z) turned into xyzw. This assimp has no per-key interpolation: every channel is
// linear. Morph animations (aiAnimMesh, aiMeshMorphAnim) are not imported: the base shape, noted.
#include <algorithm>
#include <array>
#include <cmath>

#include "import_assimp_internal.h"
#include "import_paths.h"

namespace pnb::converter::assimp_detail {

using import_detail::format;

namespace {

std::array<float, 16> columnMajor(const aiMatrix4x4& m) {
    // assimp: row-major, a4/b4/c4 the translation; the container: column-major.
    return {m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2,
            m.a3, m.b3, m.c3, m.d3, m.a4, m.b4, m.c4, m.d4};
}

// One vertex's influences, the 4 largest kept in descending order.
struct Influences {
    std::array<uint32_t, 4> joint{};
    std::array<float, 4> weight{};
    unsigned count = 0, total = 0;
    void add(uint32_t j, float w) {
        ++total;
        if (!(w > 0)) return;
        unsigned slot = count < 4 ? count++ : 4;
        if (slot == 4) {
            if (w <= weight[3]) return;
            slot = 3;
        }
        joint[slot] = j;
        weight[slot] = w;
        for (unsigned k = slot; k > 0 && weight[k] > weight[k - 1]; --k) {
            std::swap(weight[k], weight[k - 1]);
            std::swap(joint[k], joint[k - 1]);
        }
    }
};

} // namespace

Check skinMeshes(Context& ctx, const std::map<std::vector<unsigned>, int>& meshByList,
                 const std::map<std::string, int>& nodeByName) {
    IrScene& out = *ctx.out;
    for (const auto& [list, meshIndex] : meshByList) {
        bool bones = false;
        for (unsigned m : list) bones |= ctx.scene->mMeshes[m]->mNumBones > 0;
        if (!bones) continue;
        IrMesh& mesh = out.meshes[size_t(meshIndex)];
        IrSkin skin;
        std::vector<std::string> names;
        size_t cut = 0;
        std::string missingBone;
        for (size_t k = 0; k < list.size() && k < mesh.primitives.size() && missingBone.empty(); ++k) {
            const aiMesh* src = ctx.scene->mMeshes[list[k]];
            IrPrimitive& prim = mesh.primitives[k];
            std::vector<Influences> influences(src->mNumVertices);
            for (unsigned b = 0; b < src->mNumBones && missingBone.empty(); ++b) {
                const aiBone* bone = src->mBones[b];
                if (bone == nullptr) continue;
                const std::string name = str(bone->mName);
                auto known = std::find(names.begin(), names.end(), name);
                const uint32_t joint = uint32_t(known - names.begin());
                if (known == names.end()) {
                    auto node = nodeByName.find(name);
                    if (node == nodeByName.end()) {
                        missingBone = name;
                        break;
                    }
                    if (!finite(bone->mOffsetMatrix))
                        return ConvertError{ConvertErrorKind::Input,
                                            format("%s: mesh '%s' bone '%s': the offset matrix is not finite",
                                                   ctx.path.c_str(), mesh.name.c_str(), name.c_str())};
                    names.push_back(name);
                    skin.joints.push_back(node->second);
                    skin.inverseBindMatrices.push_back(columnMajor(bone->mOffsetMatrix));
                }
                for (unsigned w = 0; w < bone->mNumWeights; ++w) {
                    const aiVertexWeight& vw = bone->mWeights[w];
                    if (vw.mVertexId >= src->mNumVertices)
                        return ConvertError{ConvertErrorKind::Input,
                                            format("%s: mesh '%s' bone '%s' weights vertex %u of %u", ctx.path.c_str(),
                                                   mesh.name.c_str(), name.c_str(), vw.mVertexId, src->mNumVertices)};
                    influences[vw.mVertexId].add(joint, std::isfinite(vw.mWeight) ? vw.mWeight : 0.0f);
                }
            }
            // Vertices past the primitive's own (it keeps every vertex of its aiMesh).
            const size_t n = prim.vertexCount();
            prim.joints.assign(n * 4, 0);
            prim.weights.assign(n * 4, 0.0f);
            for (size_t v = 0; v < n && v < influences.size(); ++v) {
                cut += influences[v].total > 4 ? 1 : 0;
                for (int i = 0; i < 4; ++i) {
                    prim.joints[v * 4 + size_t(i)] = influences[v].joint[size_t(i)];
                    prim.weights[v * 4 + size_t(i)] = influences[v].weight[size_t(i)];
                }
            }
        }
        // A bone without its node (some loaders name bones after nodes they do not create):
        // the mesh cannot be posed, so it stays unskinned, in its bind pose.
        if (!missingBone.empty()) {
            for (IrPrimitive& prim : mesh.primitives) {
                prim.joints.clear();
                prim.weights.clear();
            }
            ctx.warn(format("mesh '%s': bone '%s' names no node of the scene; the mesh is drawn "
                            "unskinned, in its bind pose", mesh.name.c_str(), missingBone.c_str()));
            continue;
        }
        if (skin.joints.size() > kMaxJoints)
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: mesh '%s': %zu bones, at most %u joints are supported", ctx.path.c_str(),
                                       mesh.name.c_str(), skin.joints.size(), kMaxJoints)};
        if (cut)
            ctx.warn(format("mesh '%s': %zu vertices have more than 4 bone influences; the 4 largest are kept",
                            mesh.name.c_str(), cut));
        mesh.skinned = true;
        skin.name = mesh.name;
        out.skins.push_back(std::move(skin));
        for (IrNode& node : out.nodes)
            if (node.mesh == meshIndex) node.skin = int(out.skins.size() - 1);
    }
    return std::nullopt;
}

Check convertAnimations(Context& ctx, const std::map<std::string, int>& nodeByName, bool rootConverted) {
    IrScene& out = *ctx.out;
    for (unsigned a = 0; a < ctx.scene->mNumAnimations; ++a) {
        const aiAnimation* src = ctx.scene->mAnimations[a];
        if (src == nullptr) continue;
        IrAnimation clip;
        clip.name = str(src->mName);
        const std::string who = clip.name.empty() ? format("animation %u", a) : "animation '" + clip.name + "'";
        const double tps = src->mTicksPerSecond > 0 && std::isfinite(src->mTicksPerSecond) ? src->mTicksPerSecond : 25.0;
        size_t missing = 0, dropped = 0;
        for (unsigned c = 0; c < src->mNumChannels; ++c) {
            const aiNodeAnim* ch = src->mChannels[c];
            if (ch == nullptr) continue;
            auto node = nodeByName.find(str(ch->mNodeName));
            if (node == nodeByName.end()) {
                ++missing;
                continue;
            }
            if (rootConverted && out.nodes[size_t(node->second)].parent < 0)
                ctx.warn(format("%s channel %u: animates the root node '%s', whose axis conversion the keys "
                                "replace", who.c_str(), c, str(ch->mNodeName).c_str()));
            // One channel per key kind; `read` gives key k's time (ticks) and appends its value.
            auto add = [&](AnimatedProperty property, unsigned keys, auto time, auto value) -> Check {
                if (keys == 0) return std::nullopt;
                IrAnimationChannel channel;
                channel.node = node->second;
                channel.property = property;
                for (unsigned k = 0; k < keys; ++k) {
                    const double t = time(k) / tps;
                    const std::string channelWho =
                        format("%s channel %u (node '%s') key %u", who.c_str(), c, str(ch->mNodeName).c_str(), k);
                    if (!std::isfinite(t) || t < 0)
                        return ConvertError{ConvertErrorKind::Input,
                                            format("%s: %s: time %g s is not a finite time >= 0", ctx.path.c_str(),
                                                   channelWho.c_str(), t)};
                    // assimp repeats a key at the same time in some files: the first is kept.
                    if (!channel.times.empty() && !(float(t) > channel.times.back())) {
                        ++dropped;
                        continue;
                    }
                    const size_t before = channel.values.size();
                    value(k, channel.values);
                    for (size_t i = before; i < channel.values.size(); ++i)
                        if (!std::isfinite(channel.values[i]))
                            return ConvertError{ConvertErrorKind::Input,
                                                format("%s: %s: a value is not finite", ctx.path.c_str(),
                                                       channelWho.c_str())};
                    channel.times.push_back(float(t));
                }
                clip.channels.push_back(std::move(channel));
                return std::nullopt;
            };
            auto vec = [](const aiVectorKey* keys) {
                return [keys](unsigned k, std::vector<float>& v) {
                    v.insert(v.end(), {keys[k].mValue.x, keys[k].mValue.y, keys[k].mValue.z});
                };
            };
            if (auto e = add(AnimatedProperty::Translation, ch->mPositionKeys ? ch->mNumPositionKeys : 0,
                             [&](unsigned k) { return ch->mPositionKeys[k].mTime; }, vec(ch->mPositionKeys)))
                return e;
            if (auto e = add(AnimatedProperty::Rotation, ch->mRotationKeys ? ch->mNumRotationKeys : 0,
                             [&](unsigned k) { return ch->mRotationKeys[k].mTime; },
                             [&](unsigned k, std::vector<float>& v) {
                                 const aiQuaternion& q = ch->mRotationKeys[k].mValue; // wxyz
                                 const double len = std::sqrt(double(q.x) * q.x + double(q.y) * q.y +
                                                              double(q.z) * q.z + double(q.w) * q.w);
                                 if (len > 1e-12 && std::isfinite(len))
                                     v.insert(v.end(), {float(q.x / len), float(q.y / len), float(q.z / len),
                                                        float(q.w / len)});
                                 else
                                     v.insert(v.end(), {0.0f, 0.0f, 0.0f, 1.0f});
                             }))
                return e;
            if (auto e = add(AnimatedProperty::Scale, ch->mScalingKeys ? ch->mNumScalingKeys : 0,
                             [&](unsigned k) { return ch->mScalingKeys[k].mTime; }, vec(ch->mScalingKeys)))
                return e;
        }
        if (missing) ctx.warn(format("%s: %zu channels animate no node of the scene; dropped", who.c_str(), missing));
        if (dropped)
            ctx.warn(format("%s: %zu keys at the time of the key before them; dropped", who.c_str(), dropped));
        if (src->mNumMorphMeshChannels > 0 || src->mNumMeshChannels > 0)
            out.noteNotRendered("morph and mesh animations", 1, "clips", "the base shape");
        if (clip.channels.empty()) {
            ctx.warn(who + ": no node channel to play; dropped");
            continue;
        }
        out.animations.push_back(std::move(clip));
    }
    return std::nullopt;
}

} // namespace pnb::converter::assimp_detail
