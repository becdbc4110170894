// A glTF posed on the CPU from its own accessors (see gltf_cpu_pose.h). The tinygltf
// implementation comes from pnb_converter, which this test links for the conversion.
#include "gltf_cpu_pose.h"

#include <algorithm>
#include <cstring>
#include <functional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
// As pnb_converter compiled the implementation (import_gltf_internal.h): no stb.
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

namespace pnb::player::test {

namespace {

// Element `i` of a float-valued accessor (float, or a normalised integer type), `n` components.
std::vector<float> readAccessor(const tinygltf::Model& m, int index, int* components, std::string* error) {
    const tinygltf::Accessor& a = m.accessors[size_t(index)];
    if (a.sparse.isSparse) {
        *error = "sparse accessor " + std::to_string(index);
        return {};
    }
    const int n = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    *components = n;
    std::vector<float> out(a.count * size_t(n), 0.0f);
    if (a.bufferView < 0) return out; // all zeros (glTF)
    const tinygltf::BufferView& view = m.bufferViews[size_t(a.bufferView)];
    const auto* base = m.buffers[size_t(view.buffer)].data.data() + view.byteOffset + a.byteOffset;
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    const size_t stride = view.byteStride ? view.byteStride : size_t(size * n);
    for (size_t e = 0; e < a.count; ++e)
        for (int c = 0; c < n; ++c) {
            const unsigned char* p = base + e * stride + size_t(c * size);
            float v = 0;
            switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, p, 4); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = a.normalized ? *p / 255.0f : float(*p); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t u;
                std::memcpy(&u, p, 2);
                v = a.normalized ? u / 65535.0f : float(u);
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
                uint32_t u;
                std::memcpy(&u, p, 4);
                v = float(u);
                break;
            }
            default: *error = "accessor " + std::to_string(index) + ": a component type this reader skips"; return {};
            }
            out[e * size_t(n) + size_t(c)] = v;
        }
    return out;
}

std::vector<uint32_t> readIndices(const tinygltf::Model& m, const tinygltf::Primitive& p, size_t vertices, std::string* error) {
    std::vector<uint32_t> out;
    if (p.indices < 0) {
        for (uint32_t i = 0; i < vertices; ++i) out.push_back(i);
        return out;
    }
    int n = 0;
    for (float f : readAccessor(m, p.indices, &n, error)) out.push_back(uint32_t(f));
    return out;
}

struct Trs {
    glm::dvec3 t{0.0}, s{1.0};
    glm::dquat r{1, 0, 0, 0};
    bool matrix = false;
    glm::dmat4 m{1.0};
    std::vector<double> weights;
};

// Channel `c` of animation `a` sampled at t into `out` (width values).
std::vector<double> sample(const tinygltf::Model& m, const tinygltf::AnimationSampler& s, size_t width, double t,
                           bool rotation, std::string* error) {
    int n = 0;
    const std::vector<float> times = readAccessor(m, s.input, &n, error);
    const std::vector<float> values = readAccessor(m, s.output, &n, error);
    const bool cubic = s.interpolation == "CUBICSPLINE";
    const size_t stride = (cubic ? 3 : 1) * width, at = cubic ? width : 0;
    auto value = [&](size_t k, size_t i) { return double(values[k * stride + at + i]); };
    std::vector<double> out(width);
    size_t k1 = 0;
    while (k1 < times.size() && times[k1] <= t) ++k1;
    if (k1 == 0 || k1 == times.size() || s.interpolation == "STEP") {
        const size_t k = k1 == 0 ? 0 : k1 - 1;
        for (size_t i = 0; i < width; ++i) out[i] = value(k, i);
        return out;
    }
    const size_t k0 = k1 - 1;
    const double dt = times[k1] - times[k0], u = (t - times[k0]) / dt;
    if (cubic) {
        const double u2 = u * u, u3 = u2 * u;
        for (size_t i = 0; i < width; ++i)
            out[i] = (2 * u3 - 3 * u2 + 1) * value(k0, i) + (u3 - 2 * u2 + u) * dt * values[k0 * stride + 2 * width + i] +
                     (-2 * u3 + 3 * u2) * value(k1, i) + (u3 - u2) * dt * values[k1 * stride + i];
    } else if (rotation) {
        const glm::dquat a(value(k0, 3), value(k0, 0), value(k0, 1), value(k0, 2));
        const glm::dquat b(value(k1, 3), value(k1, 0), value(k1, 1), value(k1, 2));
        const glm::dquat q = glm::slerp(a, glm::dot(a, b) < 0 ? -b : b, u);
        out = {q.x, q.y, q.z, q.w};
    } else {
        for (size_t i = 0; i < width; ++i) out[i] = (1 - u) * value(k0, i) + u * value(k1, i);
    }
    return out;
}

} // namespace

std::vector<glm::dvec3> gltfPosedPositions(const std::string& path, int animation, double t, std::string* error) {
    tinygltf::Model m;
    tinygltf::TinyGLTF loader;
    // Images are not this reader's concern: keep none.
    loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                             void*) { return true; },
                          nullptr);
    std::string warn;
    const bool binary = path.size() > 4 && path.substr(path.size() - 4) == ".glb";
    const bool ok = binary ? loader.LoadBinaryFromFile(&m, error, &warn, path) : loader.LoadASCIIFromFile(&m, error, &warn, path);
    if (!ok) return {};
    if (m.extensionsRequired.size()) {
        *error = "extension required: " + m.extensionsRequired[0];
        return {};
    }
    std::vector<Trs> local(m.nodes.size());
    for (size_t i = 0; i < m.nodes.size(); ++i) {
        const tinygltf::Node& n = m.nodes[i];
        Trs& l = local[i];
        if (n.matrix.size() == 16) l.matrix = true, l.m = glm::make_mat4(n.matrix.data());
        if (n.translation.size() == 3) l.t = {n.translation[0], n.translation[1], n.translation[2]};
        if (n.scale.size() == 3) l.s = {n.scale[0], n.scale[1], n.scale[2]};
        if (n.rotation.size() == 4) l.r = glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
        if (n.mesh >= 0) {
            l.weights = n.weights.empty() ? m.meshes[size_t(n.mesh)].weights : n.weights;
        }
    }
    if (animation >= 0 && size_t(animation) < m.animations.size()) {
        const tinygltf::Animation& a = m.animations[size_t(animation)];
        for (const tinygltf::AnimationChannel& c : a.channels) {
            if (c.target_node < 0) continue;
            Trs& l = local[size_t(c.target_node)];
            const tinygltf::AnimationSampler& s = a.samplers[size_t(c.sampler)];
            if (c.target_path == "translation") {
                auto v = sample(m, s, 3, t, false, error);
                l.t = {v[0], v[1], v[2]};
            } else if (c.target_path == "scale") {
                auto v = sample(m, s, 3, t, false, error);
                l.s = {v[0], v[1], v[2]};
            } else if (c.target_path == "rotation") {
                auto v = sample(m, s, 4, t, true, error);
                l.r = glm::normalize(glm::dquat(v[3], v[0], v[1], v[2]));
            } else if (c.target_path == "weights") {
                l.weights = sample(m, s, l.weights.size(), t, false, error);
            }
        }
    }
    std::vector<glm::dmat4> world(m.nodes.size(), glm::dmat4(1.0));
    std::function<void(int, const glm::dmat4&)> walk = [&](int i, const glm::dmat4& parent) {
        const Trs& l = local[size_t(i)];
        const glm::dmat4 lm = l.matrix ? l.m
                                       : glm::translate(glm::dmat4(1.0), l.t) * glm::mat4_cast(l.r) *
                                             glm::scale(glm::dmat4(1.0), l.s);
        world[size_t(i)] = parent * lm;
        for (int c : m.nodes[size_t(i)].children) walk(c, world[size_t(i)]);
    };
    const int sceneIndex = m.defaultScene >= 0 ? m.defaultScene : 0;
    if (!m.scenes.empty())
        for (int root : m.scenes[size_t(sceneIndex)].nodes) walk(root, glm::dmat4(1.0));
    std::vector<glm::dvec3> out;
    for (size_t i = 0; i < m.nodes.size(); ++i) {
        const tinygltf::Node& n = m.nodes[i];
        if (n.mesh < 0) continue;
        std::vector<glm::dmat4> joints;
        if (n.skin >= 0) {
            const tinygltf::Skin& skin = m.skins[size_t(n.skin)];
            int c = 0;
            std::vector<float> ibm;
            if (skin.inverseBindMatrices >= 0) ibm = readAccessor(m, skin.inverseBindMatrices, &c, error);
            for (size_t j = 0; j < skin.joints.size(); ++j)
                joints.push_back(world[size_t(skin.joints[j])] *
                                 (ibm.empty() ? glm::dmat4(1.0) : glm::dmat4(glm::make_mat4(ibm.data() + 16 * j))));
        }
        for (const tinygltf::Primitive& p : m.meshes[size_t(n.mesh)].primitives) {
            if (p.mode != TINYGLTF_MODE_TRIANGLES || !p.attributes.count("POSITION")) continue;
            int c = 0;
            std::vector<float> pos = readAccessor(m, p.attributes.at("POSITION"), &c, error);
            const size_t count = pos.size() / 3;
            for (size_t k = 0; k < p.targets.size() && k < local[i].weights.size(); ++k)
                if (p.targets[k].count("POSITION")) {
                    const std::vector<float> d = readAccessor(m, p.targets[k].at("POSITION"), &c, error);
                    for (size_t v = 0; v < pos.size() && v < d.size(); ++v) pos[v] += float(local[i].weights[k] * d[v]);
                }
            std::vector<float> jw, ww;
            if (!joints.empty()) {
                jw = readAccessor(m, p.attributes.at("JOINTS_0"), &c, error);
                ww = readAccessor(m, p.attributes.at("WEIGHTS_0"), &c, error);
            }
            for (uint32_t v : readIndices(m, p, count, error)) {
                if (v >= count) continue;
                const glm::dvec4 rest(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2], 1.0);
                glm::dvec4 placed = world[i] * rest;
                if (!joints.empty()) {
                    glm::dmat4 blend(0.0);
                    for (int k = 0; k < 4; ++k) blend += double(ww[4 * v + k]) * joints[size_t(jw[4 * v + k])];
                    placed = blend * rest;
                }
                out.emplace_back(placed);
            }
        }
    }
    if (!error->empty()) return {};
    return out;
}

} // namespace pnb::player::test
