// glTF 2.0 binary writer (see gltf_writer.h).
//
// Based on: the glTF 2.0 specification (Khronos, sections 3.6 "Binary Data Storage" and 4.4
// "GLB File Format Specification") and the KHR_lights_punctual extension specification.

#include "pnb_assets/gltf_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <utility>

#include <nlohmann/json.hpp>

namespace pnb::assets::gltf {

namespace {

using nlohmann::json;

// note: the BIN chunk is a byte copy of our in-memory arrays, and glTF is little-endian.
static_assert(std::endian::native == std::endian::little, "the .glb writer assumes little-endian");

// glTF enums (OpenGL values, as the specification uses them).
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;
constexpr int kUnsignedByte = 5121;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kFloat = 5126;
constexpr int kLinear = 9729;
constexpr int kLinearMipmapLinear = 9987;
constexpr int kRepeat = 10497;

constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A; // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;  // "BIN\0"

// The float's exact value as a double: nlohmann prints the shortest decimal that round-trips
// the *double*, so readers parsing it as float or double both get the original float back.
// That matters for POSITION min/max, which validators compare against the data exactly.
json num(float f) {
    return double(f);
}
json arr(std::span<const float> v) {
    json a = json::array();
    for (float f : v)
        a.push_back(num(f));
    return a;
}

bool finite(std::span<const float> v) {
    return std::all_of(v.begin(), v.end(), [](float f) { return std::isfinite(f); });
}

// Accumulates the BIN chunk and its bufferViews/accessors.
struct BinBuilder {
    std::vector<uint8_t> bin;
    json views = json::array();
    json accessors = json::array();

    // Appends one bufferView starting on a 4-byte boundary (every component we write is at
    // most 4 bytes, so this satisfies the accessor alignment rules too). target 0 = none.
    uint32_t addView(const void* data, size_t sizeBytes, int target) {
        bin.resize((bin.size() + 3) & ~size_t(3), 0);
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", sizeBytes}};
        if (target != 0) v["target"] = target;
        const auto* p = static_cast<const uint8_t*>(data);
        bin.insert(bin.end(), p, p + sizeBytes);
        views.push_back(std::move(v));
        return uint32_t(views.size() - 1);
    }

    uint32_t addAccessor(uint32_t view, int componentType, size_t count, const char* type) {
        accessors.push_back({{"bufferView", view},
                             {"componentType", componentType},
                             {"count", count},
                             {"type", type}});
        return uint32_t(accessors.size() - 1);
    }

    template <size_t N>
    uint32_t addFloatAttribute(const std::vector<std::array<float, N>>& v, const char* type) {
        uint32_t view = addView(v.data(), v.size() * sizeof(v[0]), kArrayBuffer);
        return addAccessor(view, kFloat, v.size(), type);
    }

    uint32_t addPositions(const std::vector<Float3>& p) {
        uint32_t a = addFloatAttribute(p, "VEC3");
        Float3 lo = p[0], hi = p[0];
        for (const Float3& q : p)
            for (int c = 0; c < 3; ++c) {
                lo[c] = std::min(lo[c], q[c]);
                hi[c] = std::max(hi[c], q[c]);
            }
        accessors[a]["min"] = arr(lo);
        accessors[a]["max"] = arr(hi);
        return a;
    }

    // Non-vertex float data (inverse bind matrices, animation keys): one view without a target
    // and one accessor per distinct (type, content, with bounds) triple, so shared data is stored
    // once. `bounds`: write min/max per component (animation inputs require them).
    std::map<std::pair<std::string, std::vector<float>>, uint32_t> shared;
    uint32_t addSharedFloats(const std::vector<float>& v, const char* type, size_t components,
                             bool bounds) {
        auto key = std::make_pair(std::string(type) + (bounds ? "+bounds" : ""), v);
        if (auto it = shared.find(key); it != shared.end()) return it->second;
        uint32_t view = addView(v.data(), v.size() * sizeof(float), 0);
        uint32_t a = addAccessor(view, kFloat, v.size() / components, type);
        if (bounds) {
            std::vector<float> lo(v.begin(), v.begin() + ptrdiff_t(components)), hi = lo;
            for (size_t i = 0; i < v.size(); ++i) {
                lo[i % components] = std::min(lo[i % components], v[i]);
                hi[i % components] = std::max(hi[i % components], v[i]);
            }
            accessors[a]["min"] = arr(lo);
            accessors[a]["max"] = arr(hi);
        }
        shared.emplace(std::move(key), a);
        return a;
    }

    // JOINTS_0: UNSIGNED_BYTE when every index fits, else UNSIGNED_SHORT.
    uint32_t addJoints(const std::vector<Joints4>& j) {
        bool small = std::all_of(j.begin(), j.end(), [](const Joints4& q) {
            return std::all_of(q.begin(), q.end(), [](uint16_t i) { return i < 256; });
        });
        if (small) {
            std::vector<uint8_t> bytes;
            bytes.reserve(j.size() * 4);
            for (const Joints4& q : j)
                for (uint16_t i : q)
                    bytes.push_back(uint8_t(i));
            uint32_t view = addView(bytes.data(), bytes.size(), kArrayBuffer);
            return addAccessor(view, kUnsignedByte, j.size(), "VEC4");
        }
        uint32_t view = addView(j.data(), j.size() * sizeof(Joints4), kArrayBuffer);
        return addAccessor(view, kUnsignedShort, j.size(), "VEC4");
    }

    uint32_t addIndices(const std::vector<uint32_t>& idx, size_t vertexCount) {
        // note: 65535 is the primitive-restart value for 16-bit indices, which glTF forbids in
        // index data, hence "<= 65535 vertices" (largest index 65534).
        if (vertexCount <= 65535) {
            std::vector<uint16_t> small(idx.begin(), idx.end());
            uint32_t view = addView(small.data(), small.size() * 2, kElementArrayBuffer);
            return addAccessor(view, kUnsignedShort, idx.size(), "SCALAR");
        }
        uint32_t view = addView(idx.data(), idx.size() * 4, kElementArrayBuffer);
        return addAccessor(view, kUnsignedInt, idx.size(), "SCALAR");
    }
};

json materialJson(const Material& m) {
    json pbr = {{"baseColorFactor", arr(m.baseColorFactor)},
                {"metallicFactor", num(m.metallicFactor)},
                {"roughnessFactor", num(m.roughnessFactor)}};
    // Textures map one-to-one onto images, so the texture index is the image index.
    if (m.baseColorImage != kNone) pbr["baseColorTexture"] = {{"index", m.baseColorImage}};
    json j = {{"pbrMetallicRoughness", std::move(pbr)}};
    if (m.normalImage != kNone) j["normalTexture"] = {{"index", m.normalImage}};
    if (!m.name.empty()) j["name"] = m.name;
    if (m.alphaMode == AlphaMode::Mask) {
        j["alphaMode"] = "MASK";
        j["alphaCutoff"] = num(m.alphaCutoff);
    } else if (m.alphaMode == AlphaMode::Blend) {
        j["alphaMode"] = "BLEND";
    }
    if (m.doubleSided) j["doubleSided"] = true;
    if (m.unlit) j["extensions"]["KHR_materials_unlit"] = json::object();
    if (m.emissiveFactor != Float3{0, 0, 0}) j["emissiveFactor"] = arr(m.emissiveFactor);
    return j;
}

json nodeJson(const Node& n) {
    json j = json::object();
    if (!n.name.empty()) j["name"] = n.name;
    if (n.translation != Float3{0, 0, 0}) j["translation"] = arr(n.translation);
    if (n.rotation != Float4{0, 0, 0, 1}) j["rotation"] = arr(n.rotation);
    if (n.scale != Float3{1, 1, 1}) j["scale"] = arr(n.scale);
    if (n.mesh != kNone) j["mesh"] = n.mesh;
    if (n.camera != kNone) j["camera"] = n.camera;
    if (n.light != kNone) j["extensions"]["KHR_lights_punctual"]["light"] = n.light;
    if (n.skin != kNone) j["skin"] = n.skin;
    if (!n.children.empty()) j["children"] = n.children;
    return j;
}

json cameraJson(const Camera& c) {
    if (c.orthographic) {
        json o = {{"xmag", num(c.xmag)}, {"ymag", num(c.ymag)}, {"znear", num(c.znear)}, {"zfar", num(c.zfar)}};
        json j = {{"type", "orthographic"}, {"orthographic", std::move(o)}};
        if (!c.name.empty()) j["name"] = c.name;
        return j;
    }
    json p = {{"yfov", num(c.yfovRadians)}, {"znear", num(c.znear)}};
    if (c.zfar > 0) p["zfar"] = num(c.zfar);
    if (c.aspectRatio > 0) p["aspectRatio"] = num(c.aspectRatio);
    json j = {{"type", "perspective"}, {"perspective", std::move(p)}};
    if (!c.name.empty()) j["name"] = c.name;
    return j;
}

json lightJson(const Light& l) {
    const char* type = l.type == LightType::Directional ? "directional"
                       : l.type == LightType::Point     ? "point"
                                                        : "spot";
    json j = {{"type", type}, {"color", arr(l.color)}, {"intensity", num(l.intensity)}};
    if (l.type != LightType::Directional && l.range > 0) j["range"] = num(l.range);
    if (l.type == LightType::Spot)
        j["spot"] = {{"innerConeAngle", num(l.innerConeRadians)},
                     {"outerConeAngle", num(l.outerConeRadians)}};
    if (!l.name.empty()) j["name"] = l.name;
    return j;
}

const char* pathName(AnimationPath p) {
    switch (p) {
    case AnimationPath::Translation:
        return "translation";
    case AnimationPath::Rotation:
        return "rotation";
    case AnimationPath::Scale:
        return "scale";
    case AnimationPath::Weights:
        return "weights";
    }
    return "";
}

// Floats per key of a channel of path `p` on a node whose mesh has `targets` morph targets.
size_t componentsOf(AnimationPath p, size_t targets) {
    return p == AnimationPath::Rotation ? 4 : p == AnimationPath::Weights ? targets : 3;
}

// Morph targets of node `node`'s mesh (0 without a mesh).
size_t targetCountOf(const Document& doc, uint32_t node) {
    const Node& n = doc.nodes[node];
    return n.mesh == kNone ? 0 : doc.meshes[size_t(n.mesh)].weights.size();
}

// Root nodes: those no other node lists as a child, in index order.
std::vector<uint32_t> rootNodes(const Document& doc) {
    std::vector<bool> isChild(doc.nodes.size(), false);
    for (const Node& n : doc.nodes)
        for (uint32_t c : n.children)
            isChild[c] = true;
    std::vector<uint32_t> roots;
    for (uint32_t i = 0; i < doc.nodes.size(); ++i)
        if (!isChild[i]) roots.push_back(i);
    return roots;
}

void putU32(std::vector<uint8_t>& out, uint32_t v) {
    out.insert(out.end(), {uint8_t(v), uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24)});
}

Float3 cross(Float3 a, Float3 b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Float3 normalize(Float3 v) {
    float len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return {v[0] / len, v[1] / len, v[2] / len};
}

// The skins' and animations' part of validateDocument.
std::string validateSkinsAndAnimations(const Document& doc) {
    auto bad = [](const std::string& what, size_t i, const std::string& why) {
        return what + " " + std::to_string(i) + ": " + why;
    };
    for (size_t i = 0; i < doc.skins.size(); ++i) {
        const Skin& sk = doc.skins[i];
        if (sk.joints.empty() || sk.inverseBindMatrices.size() != sk.joints.size())
            return bad("skin", i, "has no joints or not one inverse bind matrix per joint");
        if (std::set<uint32_t>(sk.joints.begin(), sk.joints.end()).size() != sk.joints.size())
            return bad("skin", i, "lists a joint twice");
        for (uint32_t j : sk.joints)
            if (j >= doc.nodes.size()) return bad("skin", i, "joint out of range");
        for (const auto& m : sk.inverseBindMatrices)
            if (!finite(m)) return bad("skin", i, "non-finite inverse bind matrix");
        if (sk.skeleton != kNone && (sk.skeleton < 0 || size_t(sk.skeleton) >= doc.nodes.size()))
            return bad("skin", i, "skeleton out of range");
    }
    for (size_t a = 0; a < doc.animations.size(); ++a) {
        const Animation& anim = doc.animations[a];
        if (anim.samplers.empty() || anim.channels.empty())
            return bad("animation", a, "has no samplers or no channels");
        std::vector<size_t> components(anim.samplers.size(), 0);
        std::set<std::pair<uint32_t, AnimationPath>> targets;
        for (const AnimationChannel& c : anim.channels) {
            if (c.sampler >= anim.samplers.size() || c.node >= doc.nodes.size())
                return bad("animation", a, "channel sampler or node out of range");
            if (!targets.insert({c.node, c.path}).second)
                return bad("animation", a, "two channels animate one node property");
            const size_t targetCount = targetCountOf(doc, c.node);
            if (c.path == AnimationPath::Weights && targetCount == 0)
                return bad("animation", a, "weights channel on a node without morph targets");
            size_t k = componentsOf(c.path, targetCount);
            if (components[c.sampler] != 0 && components[c.sampler] != k)
                return bad("animation", a, "a sampler shared by channels of different widths");
            components[c.sampler] = k;
            if (c.path == AnimationPath::Rotation) {
                const std::vector<float>& out = anim.samplers[c.sampler].output;
                for (size_t q = 0; q + 3 < out.size(); q += 4) {
                    float len2 = out[q] * out[q] + out[q + 1] * out[q + 1] +
                                 out[q + 2] * out[q + 2] + out[q + 3] * out[q + 3];
                    if (std::fabs(len2 - 1.0f) > 1e-4f)
                        return bad("animation", a, "rotation key is not a unit quaternion");
                }
            }
        }
        for (size_t si = 0; si < anim.samplers.size(); ++si) {
            const AnimationSampler& smp = anim.samplers[si];
            if (components[si] == 0) return bad("animation", a, "a sampler no channel uses");
            if (smp.input.empty() || smp.output.size() != smp.input.size() * components[si])
                return bad("animation", a, "sampler output is not one value per key");
            if (!finite(smp.input) || !finite(smp.output) || smp.input[0] < 0)
                return bad("animation", a, "non-finite or negative key");
            for (size_t k = 1; k < smp.input.size(); ++k)
                if (!(smp.input[k] > smp.input[k - 1]))
                    return bad("animation", a, "key times are not strictly increasing");
        }
    }
    return {};
}

// Skins: joints and the inverse bind matrices (stored once per distinct content).
json skinsJson(const Document& doc, BinBuilder& b) {
    json skins = json::array();
    for (const Skin& sk : doc.skins) {
        std::vector<float> ibm;
        for (const auto& m : sk.inverseBindMatrices)
            ibm.insert(ibm.end(), m.begin(), m.end());
        json js = {{"joints", sk.joints},
                   {"inverseBindMatrices", b.addSharedFloats(ibm, "MAT4", 16, false)}};
        if (sk.skeleton != kNone) js["skeleton"] = sk.skeleton;
        if (!sk.name.empty()) js["name"] = sk.name;
        skins.push_back(std::move(js));
    }
    return skins;
}

// Animations: channels and samplers (inputs and outputs stored once per distinct content).
json animationsJson(const Document& doc, BinBuilder& b) {
    json animations = json::array();
    for (const Animation& anim : doc.animations) {
        std::vector<const char*> types(anim.samplers.size(), "VEC3");
        std::vector<size_t> widths(anim.samplers.size(), 3);
        json channels = json::array();
        for (const AnimationChannel& c : anim.channels) {
            channels.push_back({{"sampler", c.sampler},
                                {"target", {{"node", c.node}, {"path", pathName(c.path)}}}});
            widths[c.sampler] = componentsOf(c.path, targetCountOf(doc, c.node));
            types[c.sampler] = c.path == AnimationPath::Rotation  ? "VEC4"
                               : c.path == AnimationPath::Weights ? "SCALAR"
                                                                  : "VEC3";
        }
        json samplers = json::array();
        for (size_t i = 0; i < anim.samplers.size(); ++i) {
            const AnimationSampler& smp = anim.samplers[i];
            // Weights outputs are SCALAR, one per target per key (glTF's layout).
            const size_t per = types[i] == std::string("SCALAR") ? 1 : widths[i];
            samplers.push_back(
                {{"input", b.addSharedFloats(smp.input, "SCALAR", 1, true)},
                 {"output", b.addSharedFloats(smp.output, types[i], per, false)},
                 {"interpolation", smp.interpolation == Interpolation::Step ? "STEP" : "LINEAR"}});
        }
        json ja = {{"channels", std::move(channels)}, {"samplers", std::move(samplers)}};
        if (!anim.name.empty()) ja["name"] = anim.name;
        animations.push_back(std::move(ja));
    }
    return animations;
}

} // namespace

std::string validateDocument(const Document& doc) {
    auto bad = [](const std::string& what, size_t i, const std::string& why) {
        return what + " " + std::to_string(i) + ": " + why;
    };
    for (size_t m = 0; m < doc.meshes.size(); ++m) {
        const Mesh& mesh = doc.meshes[m];
        if (mesh.primitives.empty()) return bad("mesh", m, "has no primitives");
        for (const Primitive& p : mesh.primitives) {
            const size_t n = p.positions.size();
            if (n == 0 || p.indices.empty()) return bad("mesh", m, "has an empty primitive");
            if (n > 0xFFFFFFFEu) return bad("mesh", m, "has more than 2^32-2 vertices");
            if (p.normals.size() != n) return bad("mesh", m, "normals and positions differ");
            if (!p.uv0.empty() && p.uv0.size() != n) return bad("mesh", m, "uv0 size differs");
            if (p.indices.size() % 3 != 0) return bad("mesh", m, "index count not a multiple of 3");
            if (p.material >= doc.materials.size()) return bad("mesh", m, "material out of range");
            for (uint32_t i : p.indices)
                if (i >= n) return bad("mesh", m, "index out of range");
            for (size_t v = 0; v < n; ++v) {
                const Float3& nv = p.normals[v];
                float len2 = nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2];
                if (!finite(p.positions[v]) || !finite(nv) || std::fabs(len2 - 1.0f) > 1e-3f)
                    return bad("mesh", m, "non-finite position or non-unit normal");
            }
            for (const Float2& uv : p.uv0)
                if (!finite(uv)) return bad("mesh", m, "non-finite uv");
            if (p.joints0.size() != p.weights0.size() ||
                (!p.joints0.empty() && p.joints0.size() != n))
                return bad("mesh", m, "joints0/weights0 sizes differ from positions");
            for (const Float4& w : p.weights0) {
                if (!finite(w) || std::any_of(w.begin(), w.end(), [](float x) { return x < 0; }))
                    return bad("mesh", m, "negative or non-finite weight");
                if (std::fabs(w[0] + w[1] + w[2] + w[3] - 1.0f) > 1e-5f)
                    return bad("mesh", m, "weights do not sum to 1");
            }
            if (p.targets.size() != mesh.weights.size())
                return bad("mesh", m, "a primitive's morph targets differ from the mesh's weights");
            for (const MorphTarget& t : p.targets) {
                if (t.positionDeltas.size() != n ||
                    (!t.normalDeltas.empty() && t.normalDeltas.size() != n))
                    return bad("mesh", m, "morph target sizes differ from positions");
                for (const Float3& d : t.positionDeltas)
                    if (!finite(d)) return bad("mesh", m, "non-finite morph delta");
                for (const Float3& d : t.normalDeltas)
                    if (!finite(d)) return bad("mesh", m, "non-finite morph delta");
            }
        }
        if (!finite(mesh.weights)) return bad("mesh", m, "non-finite morph weight");
        const bool skinned = !mesh.primitives[0].joints0.empty();
        for (const Primitive& p : mesh.primitives)
            if (p.joints0.empty() == skinned)
                return bad("mesh", m, "some primitives skinned, some not");
    }
    for (size_t i = 0; i < doc.materials.size(); ++i) {
        const Material& mat = doc.materials[i];
        if (mat.baseColorImage != kNone &&
            (mat.baseColorImage < 0 || size_t(mat.baseColorImage) >= doc.images.size()))
            return bad("material", i, "baseColorImage out of range");
        if (mat.normalImage != kNone &&
            (mat.normalImage < 0 || size_t(mat.normalImage) >= doc.images.size()))
            return bad("material", i, "normalImage out of range");
        if (!finite(mat.baseColorFactor) || !finite(mat.emissiveFactor))
            return bad("material", i, "non-finite factor");
    }
    for (size_t i = 0; i < doc.images.size(); ++i)
        if (doc.images[i].png.empty()) return bad("image", i, "has no bytes");
    for (size_t i = 0; i < doc.cameras.size(); ++i) {
        const Camera& c = doc.cameras[i];
        if (c.orthographic) {
            if (!(c.xmag > 0) || !(c.ymag > 0) || !(c.znear >= 0) || !(c.zfar > c.znear))
                return bad("camera", i, "invalid orthographic projection");
            continue;
        }
        if (!(c.yfovRadians > 0 && c.yfovRadians < 3.14159f) || !(c.znear > 0) ||
            (c.zfar != 0 && !(c.zfar > c.znear)) || !(c.aspectRatio >= 0))
            return bad("camera", i, "invalid projection");
    }
    for (size_t i = 0; i < doc.lights.size(); ++i) {
        const Light& l = doc.lights[i];
        if (!(l.intensity >= 0) || !(l.range >= 0))
            return bad("light", i, "negative intensity or range");
        // KHR_lights_punctual: 0 <= innerConeAngle < outerConeAngle <= pi/2.
        if (l.type == LightType::Spot &&
            !(l.innerConeRadians >= 0 && l.innerConeRadians < l.outerConeRadians &&
              l.outerConeRadians <= 1.5707964f))
            return bad("light", i, "spot cone angles outside 0 <= inner < outer <= pi/2");
    }
    std::vector<int> parents(doc.nodes.size(), 0);
    for (size_t i = 0; i < doc.nodes.size(); ++i) {
        const Node& n = doc.nodes[i];
        auto outOf = [](int32_t ref, size_t size) {
            return ref != kNone && (ref < 0 || size_t(ref) >= size);
        };
        if (outOf(n.mesh, doc.meshes.size()) || outOf(n.camera, doc.cameras.size()) ||
            outOf(n.light, doc.lights.size()))
            return bad("node", i, "mesh, camera or light out of range");
        if (!finite(n.translation) || !finite(n.rotation) || !finite(n.scale))
            return bad("node", i, "non-finite transform");
        const bool skinnedMesh =
            n.mesh != kNone && !doc.meshes[size_t(n.mesh)].primitives[0].joints0.empty();
        if (n.skin != kNone) {
            if (n.skin < 0 || size_t(n.skin) >= doc.skins.size() || !skinnedMesh)
                return bad("node", i, "skin out of range or its mesh has no joints0");
            const size_t joints = doc.skins[size_t(n.skin)].joints.size();
            for (const Primitive& p : doc.meshes[size_t(n.mesh)].primitives)
                for (const Joints4& q : p.joints0)
                    for (uint16_t j : q)
                        if (j >= joints) return bad("node", i, "a joint index is outside its skin");
        } else if (skinnedMesh) {
            return bad("node", i, "draws a skinned mesh without a skin");
        }
        const Float4& q = n.rotation;
        if (std::fabs(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1.0f) > 1e-4f)
            return bad("node", i, "rotation is not a unit quaternion");
        for (uint32_t c : n.children) {
            if (c >= doc.nodes.size() || c == i) return bad("node", i, "child out of range");
            if (++parents[c] > 1) return bad("node", c, "has more than one parent");
        }
    }
    if (std::string why = validateSkinsAndAnimations(doc); !why.empty()) return why;
    // With at most one parent each, a node is unreachable from the roots iff it is on a cycle.
    std::vector<uint32_t> stack = rootNodes(doc);
    size_t reached = 0;
    while (!stack.empty()) {
        uint32_t n = stack.back();
        stack.pop_back();
        ++reached;
        for (uint32_t c : doc.nodes[n].children)
            stack.push_back(c);
    }
    if (reached != doc.nodes.size()) return "the node hierarchy has a cycle";
    return {};
}

uint64_t countRenderedTriangles(const Document& doc) {
    uint64_t total = 0;
    std::vector<uint32_t> stack = rootNodes(doc);
    while (!stack.empty()) {
        const Node& n = doc.nodes[stack.back()];
        stack.pop_back();
        if (n.mesh != kNone)
            for (const Primitive& p : doc.meshes[size_t(n.mesh)].primitives)
                total += p.triangleCount();
        stack.insert(stack.end(), n.children.begin(), n.children.end());
    }
    return total;
}

std::vector<uint8_t> encodeGlb(const Document& doc, GlbStats* stats) {
    assert(validateDocument(doc).empty());
    GlbStats st;
    BinBuilder b;
    json root;
    root["asset"] = {{"version", "2.0"}, {"generator", "penumbra assets_src"}};

    if (!doc.meshes.empty()) {
        json meshes = json::array();
        for (const Mesh& m : doc.meshes) {
            json prims = json::array();
            for (const Primitive& p : m.primitives) {
                json attributes = {{"POSITION", b.addPositions(p.positions)},
                                   {"NORMAL", b.addFloatAttribute(p.normals, "VEC3")}};
                if (!p.uv0.empty()) attributes["TEXCOORD_0"] = b.addFloatAttribute(p.uv0, "VEC2");
                if (!p.joints0.empty()) {
                    attributes["JOINTS_0"] = b.addJoints(p.joints0);
                    attributes["WEIGHTS_0"] = b.addFloatAttribute(p.weights0, "VEC4");
                }
                json targets = json::array();
                for (const MorphTarget& t : p.targets) {
                    json jt = {{"POSITION", b.addPositions(t.positionDeltas)}};
                    if (!t.normalDeltas.empty())
                        jt["NORMAL"] = b.addFloatAttribute(t.normalDeltas, "VEC3");
                    targets.push_back(std::move(jt));
                }
                // mode is omitted: 4 (TRIANGLES) is the default.
                json jp = {{"attributes", std::move(attributes)},
                           {"indices", b.addIndices(p.indices, p.positions.size())},
                           {"material", p.material}};
                if (!targets.empty()) jp["targets"] = std::move(targets);
                prims.push_back(std::move(jp));
                st.uniqueTriangles += p.triangleCount();
                st.vertices += p.positions.size();
            }
            json jm = {{"primitives", std::move(prims)}};
            if (!m.name.empty()) jm["name"] = m.name;
            if (!m.weights.empty()) jm["weights"] = arr(m.weights);
            meshes.push_back(std::move(jm));
        }
        root["meshes"] = std::move(meshes);
    }
    if (!doc.images.empty()) {
        json images = json::array(), textures = json::array();
        for (size_t i = 0; i < doc.images.size(); ++i) {
            const Image& im = doc.images[i];
            json ji = {{"bufferView", b.addView(im.png.data(), im.png.size(), 0)},
                       {"mimeType", "image/png"}};
            if (!im.name.empty()) ji["name"] = im.name;
            images.push_back(std::move(ji));
            textures.push_back({{"source", i}, {"sampler", 0}});
        }
        root["images"] = std::move(images);
        root["textures"] = std::move(textures);
        root["samplers"] = json::array({{{"magFilter", kLinear},
                                         {"minFilter", kLinearMipmapLinear},
                                         {"wrapS", kRepeat},
                                         {"wrapT", kRepeat}}});
    }
    // glTF forbids empty top-level arrays, so each one is written only when it has elements.
    auto putArray = [&](const char* key, const auto& items, auto toJson) {
        if (items.empty()) return;
        json a = json::array();
        for (const auto& item : items)
            a.push_back(toJson(item));
        root[key] = std::move(a);
    };
    putArray("materials", doc.materials, materialJson);
    putArray("nodes", doc.nodes, nodeJson);
    bool instancing = false;
    for (size_t i = 0; i < doc.nodes.size(); ++i)
        if (!doc.nodes[i].instanceTranslations.empty()) {
            root["nodes"][i]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] =
                b.addFloatAttribute(doc.nodes[i].instanceTranslations, "VEC3");
            instancing = true;
        }
    putArray("cameras", doc.cameras, cameraJson);
    if (!doc.skins.empty()) root["skins"] = skinsJson(doc, b);
    if (!doc.animations.empty()) root["animations"] = animationsJson(doc, b);
    if (!doc.lights.empty()) {
        json lights = json::array();
        for (const Light& l : doc.lights)
            lights.push_back(lightJson(l));
        root["extensions"]["KHR_lights_punctual"]["lights"] = std::move(lights);
        root["extensionsUsed"] = json::array({"KHR_lights_punctual"});
    }
    if (instancing) root["extensionsUsed"].push_back("EXT_mesh_gpu_instancing");
    if (std::any_of(doc.materials.begin(), doc.materials.end(), [](const Material& m) { return m.unlit; }))
        root["extensionsUsed"].push_back("KHR_materials_unlit");
    json scene = json::object();
    if (!doc.nodes.empty()) scene["nodes"] = rootNodes(doc);
    if (!doc.sceneName.empty()) scene["name"] = doc.sceneName;
    root["scenes"] = json::array({std::move(scene)});
    root["scene"] = 0;

    b.bin.resize((b.bin.size() + 3) & ~size_t(3), 0);
    if (!b.bin.empty()) {
        root["buffers"] = json::array({{{"byteLength", b.bin.size()}}});
        root["bufferViews"] = std::move(b.views);
        root["accessors"] = std::move(b.accessors);
    }

    std::string text = root.dump();
    text.resize((text.size() + 3) & ~size_t(3), ' '); // JSON chunk pads with spaces
    const size_t total = 12 + 8 + text.size() + (b.bin.empty() ? 0 : 8 + b.bin.size());
    assert(total <= 0xFFFFFFFFu); // the GLB header's length field is 32-bit

    std::vector<uint8_t> out;
    out.reserve(total);
    putU32(out, kGlbMagic);
    putU32(out, 2);
    putU32(out, uint32_t(total));
    putU32(out, uint32_t(text.size()));
    putU32(out, kChunkJson);
    out.insert(out.end(), text.begin(), text.end());
    if (!b.bin.empty()) {
        putU32(out, uint32_t(b.bin.size()));
        putU32(out, kChunkBin);
        out.insert(out.end(), b.bin.begin(), b.bin.end());
    }
    assert(out.size() == total);

    st.renderedTriangles = countRenderedTriangles(doc);
    st.sizeBytes = out.size();
    if (stats) *stats = st;
    return out;
}

Float4 lookRotation(Float3 forward, Float3 up) {
    // Columns of the rotation matrix: local X, Y, Z in world space; local -Z is `forward`.
    Float3 z = normalize({-forward[0], -forward[1], -forward[2]});
    Float3 x = normalize(cross(up, z));
    Float3 y = cross(z, x);
    // Matrix to quaternion (Shepperd's method: branch on the largest diagonal term for
    // precision). m[row][col] with columns x, y, z.
    float m00 = x[0], m01 = y[0], m02 = z[0];
    float m10 = x[1], m11 = y[1], m12 = z[1];
    float m20 = x[2], m21 = y[2], m22 = z[2];
    Float4 q;
    float trace = m00 + m11 + m22;
    if (trace > 0) {
        float s = std::sqrt(trace + 1.0f) * 2;
        q = {(m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25f * s};
    } else if (m00 > m11 && m00 > m22) {
        float s = std::sqrt(1.0f + m00 - m11 - m22) * 2;
        q = {0.25f * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s};
    } else if (m11 > m22) {
        float s = std::sqrt(1.0f + m11 - m00 - m22) * 2;
        q = {(m01 + m10) / s, 0.25f * s, (m12 + m21) / s, (m02 - m20) / s};
    } else {
        float s = std::sqrt(1.0f + m22 - m00 - m11) * 2;
        q = {(m02 + m20) / s, (m12 + m21) / s, 0.25f * s, (m10 - m01) / s};
    }
    float len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    float sign = q[3] < 0 ? -1.0f : 1.0f; // canonical form: w >= 0
    return {sign * q[0] / len, sign * q[1] / len, sign * q[2] / len, sign * q[3] / len};
}

Float3 rotate(Float4 q, Float3 v) {
    // v' = v + 2w (u x v) + 2 u x (u x v), with u = q.xyz.
    Float3 u{q[0], q[1], q[2]};
    Float3 t = cross(u, v);
    t = {2 * t[0], 2 * t[1], 2 * t[2]};
    Float3 ut = cross(u, t);
    return {v[0] + q[3] * t[0] + ut[0], v[1] + q[3] * t[1] + ut[1], v[2] + q[3] * t[2] + ut[2]};
}

Float4 rotationY(float radians) {
    return {0, std::sin(radians / 2), 0, std::cos(radians / 2)};
}

Float4 rotationAxis(Float3 axis, float radians) {
    const float s = std::sin(radians / 2);
    return {axis[0] * s, axis[1] * s, axis[2] * s, std::cos(radians / 2)};
}

Float4 multiply(Float4 a, Float4 b) {
    return {a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
            a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
            a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
            a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}

} // namespace pnb::assets::gltf
