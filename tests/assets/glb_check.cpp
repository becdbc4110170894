// Independent .glb reader/validator for tests (see glb_check.h).
//
// Based on: glTF 2.0 specification sections 3.6 (buffers, views, accessors: alignment and
// bounds), 3.7 (meshes; index restart values), 4.4 (GLB container).

#include "glb_check.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

namespace pnb::test {

using nlohmann::json;

namespace {

uint32_t u32(std::span<const uint8_t> b, size_t at) {
    return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 |
           uint32_t(b[at + 3]) << 24;
}

size_t componentSize(int type) {
    switch (type) {
    case 5120:
    case 5121:
        return 1;
    case 5122:
    case 5123:
        return 2;
    case 5125:
    case 5126:
        return 4;
    default:
        return 0;
    }
}

size_t componentCount(const std::string& type) {
    if (type == "SCALAR") return 1;
    if (type == "VEC2") return 2;
    if (type == "VEC3") return 3;
    if (type == "VEC4") return 4;
    if (type == "MAT4") return 16;
    return 0;
}

// Index validity for an optional reference into a top-level array.
bool validRef(const json& j, const char* key, const json& root, const char* array) {
    if (!j.contains(key)) return true;
    if (!j[key].is_number_unsigned()) return false;
    return root.contains(array) && j[key].get<size_t>() < root[array].size();
}

Mat4 identity() {
    return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
}

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int rr = 0; rr < 4; ++rr) {
            double s = 0;
            for (int k = 0; k < 4; ++k)
                s += a[k * 4 + rr] * b[c * 4 + k];
            r[c * 4 + rr] = s;
        }
    return r;
}

Mat4 localMatrix(const json& node) {
    std::array<double, 3> t{0, 0, 0}, s{1, 1, 1};
    std::array<double, 4> q{0, 0, 0, 1};
    if (node.contains("translation"))
        for (int i = 0; i < 3; ++i)
            t[i] = node["translation"][i];
    if (node.contains("scale"))
        for (int i = 0; i < 3; ++i)
            s[i] = node["scale"][i];
    if (node.contains("rotation"))
        for (int i = 0; i < 4; ++i)
            q[i] = node["rotation"][i];
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    // Columns of R scaled by S, then the translation column.
    return {(1 - 2 * (y * y + z * z)) * s[0],
            (2 * (x * y + z * w)) * s[0],
            (2 * (x * z - y * w)) * s[0],
            0,
            (2 * (x * y - z * w)) * s[1],
            (1 - 2 * (x * x + z * z)) * s[1],
            (2 * (y * z + x * w)) * s[1],
            0,
            (2 * (x * z + y * w)) * s[2],
            (2 * (y * z - x * w)) * s[2],
            (1 - 2 * (x * x + y * y)) * s[2],
            0,
            t[0],
            t[1],
            t[2],
            1};
}

std::string validateAccessors(const ParsedGlb& g) {
    const json& j = g.json;
    if (!g.bin.empty()) {
        if (!j.contains("buffers") || j["buffers"].size() != 1) return "need exactly one buffer";
        const json& buf = j["buffers"][0];
        if (buf.contains("uri")) return "the GLB buffer must not have a uri";
        size_t len = buf.at("byteLength");
        if (len > g.bin.size() || g.bin.size() - len > 3)
            return "buffer byteLength does not match the BIN chunk";
    } else if (j.contains("buffers")) {
        return "buffers declared but no BIN chunk";
    }
    const size_t bufferLength = g.bin.empty() ? 0 : j["buffers"][0]["byteLength"].get<size_t>();
    if (j.contains("bufferViews"))
        for (const json& v : j["bufferViews"]) {
            if (v.at("buffer") != 0) return "bufferView refers to a missing buffer";
            size_t off = v.value("byteOffset", size_t(0)), len = v.at("byteLength");
            if (len == 0 || off + len > bufferLength) return "bufferView runs past its buffer";
            if (off % 4 != 0) return "bufferView not 4-byte aligned";
            if (v.contains("target") && v["target"] != 34962 && v["target"] != 34963)
                return "bufferView target is neither ARRAY_BUFFER nor ELEMENT_ARRAY_BUFFER";
        }
    if (j.contains("accessors"))
        for (const json& a : j["accessors"]) {
            if (!validRef(a, "bufferView", j, "bufferViews") || !a.contains("bufferView"))
                return "accessor without a valid bufferView";
            const json& v = j["bufferViews"][a["bufferView"].get<size_t>()];
            size_t cs = componentSize(a.at("componentType"));
            size_t cc = componentCount(a.at("type"));
            size_t count = a.at("count");
            if (cs == 0 || cc == 0 || count == 0) return "accessor type or count invalid";
            size_t off = a.value("byteOffset", size_t(0));
            size_t elem = cs * cc, stride = v.value("byteStride", elem);
            if (off % cs != 0) return "accessor byteOffset misaligned";
            if (off + (count - 1) * stride + elem > v["byteLength"].get<size_t>())
                return "accessor runs past its bufferView";
        }
    return "";
}

std::string validateMeshes(const ParsedGlb& g) {
    const json& j = g.json;
    if (!j.contains("meshes")) return "";
    auto viewTarget = [&](size_t accessor) {
        return j["bufferViews"][j["accessors"][accessor]["bufferView"].get<size_t>()].value(
            "target", 0);
    };
    for (const json& m : j["meshes"]) {
        if (!m.contains("primitives") || m["primitives"].empty()) return "mesh without primitives";
        for (const json& p : m["primitives"]) {
            if (p.value("mode", 4) != 4) return "primitive is not a triangle list";
            const json& attr = p.at("attributes");
            if (!attr.contains("POSITION")) return "primitive without POSITION";
            size_t vertexCount = 0;
            for (auto it = attr.begin(); it != attr.end(); ++it) {
                size_t ai = it.value();
                if (ai >= j["accessors"].size()) return "attribute accessor out of range";
                const json& a = j["accessors"][ai];
                if (vertexCount == 0) vertexCount = a["count"];
                if (a["count"] != vertexCount) return "attributes differ in count";
                if (it.key() == "JOINTS_0") {
                    if (a["type"] != "VEC4" || (a["componentType"] != 5121 && a["componentType"] != 5123))
                        return "JOINTS_0 must be VEC4 of unsigned byte or short";
                } else if (a["componentType"] != 5126) {
                    return "attribute " + it.key() + " is not float";
                }
                if (it.key() == "WEIGHTS_0" && a["type"] != "VEC4") return "WEIGHTS_0 must be VEC4";
                if (viewTarget(ai) != 34962) return "attribute view lacks ARRAY_BUFFER target";
            }
            const json& pos = j["accessors"][attr["POSITION"].get<size_t>()];
            if (pos["type"] != "VEC3" || !pos.contains("min") || !pos.contains("max"))
                return "POSITION must be VEC3 with min and max";
            std::vector<double> data = readAccessor(g, attr["POSITION"]);
            for (int c = 0; c < 3; ++c) {
                double lo = 1e300, hi = -1e300;
                for (size_t i = c; i < data.size(); i += 3) {
                    lo = std::min(lo, data[i]);
                    hi = std::max(hi, data[i]);
                }
                // Exact: the writer promises min/max that round-trip the float data.
                if (pos["min"][c].get<double>() != lo || pos["max"][c].get<double>() != hi)
                    return "POSITION min/max do not match the data";
            }
            if (attr.contains("NORMAL")) {
                std::vector<double> n = readAccessor(g, attr["NORMAL"]);
                for (size_t i = 0; i < n.size(); i += 3)
                    if (std::fabs(
                            std::sqrt(n[i] * n[i] + n[i + 1] * n[i + 1] + n[i + 2] * n[i + 2]) -
                            1.0) > 1e-3)
                        return "NORMAL is not unit length";
            }
            if (attr.contains("TEXCOORD_0") &&
                j["accessors"][attr["TEXCOORD_0"].get<size_t>()]["type"] != "VEC2")
                return "TEXCOORD_0 must be VEC2";
            if (!p.contains("indices")) return "primitive without indices";
            size_t ii = p["indices"];
            if (ii >= j["accessors"].size()) return "indices accessor out of range";
            const json& ia = j["accessors"][ii];
            int ct = ia["componentType"];
            if (ia["type"] != "SCALAR" || (ct != 5123 && ct != 5125))
                return "indices must be SCALAR u16/u32";
            if (viewTarget(ii) != 34963) return "index view lacks ELEMENT_ARRAY_BUFFER target";
            if (ia["count"].get<size_t>() % 3 != 0) return "index count not a multiple of 3";
            const double restart = ct == 5123 ? 65535.0 : 4294967295.0;
            for (double idx : readAccessor(g, ii))
                if (idx >= double(vertexCount) || idx == restart) return "index out of range";
            if (!validRef(p, "material", j, "materials")) return "material out of range";
            if (attr.contains("JOINTS_0") != attr.contains("WEIGHTS_0"))
                return "JOINTS_0 without WEIGHTS_0 or the other way round";
            const size_t targets = p.value("targets", json::array()).size();
            if (targets != m.value("weights", json::array()).size())
                return "a primitive's morph targets differ from the mesh's weights";
            for (const json& t : p.value("targets", json::array())) {
                if (!t.contains("POSITION")) return "morph target without POSITION";
                for (auto it = t.begin(); it != t.end(); ++it) {
                    size_t ai = it.value();
                    if (ai >= j["accessors"].size() || j["accessors"][ai]["count"] != vertexCount ||
                        j["accessors"][ai]["type"] != "VEC3" || j["accessors"][ai]["componentType"] != 5126)
                        return "morph target attribute is not float VEC3 of the vertex count";
                }
            }
        }
    }
    return "";
}

// Skins and animations (glTF 2.0 sections 3.7.3 and 3.11): references in range, one inverse bind
// matrix per joint, animation inputs SCALAR float with min/max and strictly increasing, outputs
// one value per key of the width the channel's path needs.
std::string validateSkinsAndAnimations(const ParsedGlb& g) {
    const json& j = g.json;
    const size_t nodeCount = j.contains("nodes") ? j["nodes"].size() : 0;
    if (j.contains("skins"))
        for (const json& s : j["skins"]) {
            std::vector<size_t> joints = s.at("joints");
            if (joints.empty()) return "skin without joints";
            for (size_t n : joints)
                if (n >= nodeCount) return "skin joint out of range";
            if (!validRef(s, "skeleton", j, "nodes")) return "skin skeleton out of range";
            if (s.contains("inverseBindMatrices")) {
                const json& a = j["accessors"][s["inverseBindMatrices"].get<size_t>()];
                if (a["type"] != "MAT4" || a["componentType"] != 5126 || a["count"] != joints.size())
                    return "inverseBindMatrices is not one float MAT4 per joint";
            }
        }
    for (size_t i = 0; i < nodeCount; ++i) {
        const json& n = j["nodes"][i];
        if (!validRef(n, "skin", j, "skins")) return "node skin out of range";
        if (n.contains("skin") && !n.contains("mesh")) return "node with a skin but no mesh";
    }
    if (!j.contains("animations")) return "";
    for (const json& anim : j["animations"]) {
        const json& samplers = anim.at("samplers");
        const json& channels = anim.at("channels");
        if (samplers.empty() || channels.empty()) return "animation without samplers or channels";
        for (const json& c : channels) {
            size_t si = c.at("sampler");
            const json& target = c.at("target");
            if (si >= samplers.size() || !target.contains("node") || target["node"].get<size_t>() >= nodeCount)
                return "animation channel sampler or node out of range";
            const json& node = j["nodes"][target["node"].get<size_t>()];
            const std::string path = target.at("path");
            size_t width = 0;
            if (path == "translation" || path == "scale") width = 3;
            else if (path == "rotation") width = 4;
            else if (path == "weights" && node.contains("mesh"))
                width = j["meshes"][node["mesh"].get<size_t>()].value("weights", json::array()).size();
            if (width == 0) return "animation channel path invalid for its node";
            const json& smp = samplers[si];
            std::string interp = smp.value("interpolation", "LINEAR");
            if (interp != "LINEAR" && interp != "STEP" && interp != "CUBICSPLINE")
                return "bad sampler interpolation";
            const json& in = j["accessors"][smp.at("input").get<size_t>()];
            const json& out = j["accessors"][smp.at("output").get<size_t>()];
            if (in["type"] != "SCALAR" || in["componentType"] != 5126 || !in.contains("min") ||
                !in.contains("max"))
                return "animation input is not SCALAR float with min and max";
            std::vector<double> times = readAccessor(g, smp["input"]);
            for (size_t k = 1; k < times.size(); ++k)
                if (!(times[k] > times[k - 1])) return "animation key times not strictly increasing";
            if (times.front() < 0 || in["min"][0].get<double>() != times.front() ||
                in["max"][0].get<double>() != times.back())
                return "animation input min/max wrong or negative";
            const size_t values = out["count"].get<size_t>() * componentCount(out["type"]);
            if (out["componentType"] != 5126 ||
                values != times.size() * width * (interp == "CUBICSPLINE" ? 3 : 1))
                return "animation output is not one value of the path's width per key";
        }
    }
    return "";
}

std::string validateRest(const ParsedGlb& g) {
    const json& j = g.json;
    if (j.contains("materials"))
        for (const json& m : j["materials"]) {
            std::string mode = m.value("alphaMode", "OPAQUE");
            if (mode != "OPAQUE" && mode != "MASK" && mode != "BLEND") return "bad alphaMode";
            if (m.contains("pbrMetallicRoughness") &&
                m["pbrMetallicRoughness"].contains("baseColorTexture") &&
                !validRef(m["pbrMetallicRoughness"]["baseColorTexture"], "index", j, "textures"))
                return "baseColorTexture out of range";
            if (m.contains("normalTexture") &&
                !validRef(m["normalTexture"], "index", j, "textures"))
                return "normalTexture out of range";
        }
    if (j.contains("textures"))
        for (const json& t : j["textures"])
            if (!validRef(t, "source", j, "images") || !validRef(t, "sampler", j, "samplers"))
                return "texture source or sampler out of range";
    if (j.contains("images"))
        for (const json& im : j["images"]) {
            if (!validRef(im, "bufferView", j, "bufferViews") ||
                im.value("mimeType", "") != "image/png")
                return "image needs a bufferView and mimeType image/png";
            const json& v = j["bufferViews"][im["bufferView"].get<size_t>()];
            if (v.contains("target")) return "image bufferView must not have a target";
            const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
            if (std::memcmp(g.bin.data() + v.value("byteOffset", size_t(0)), sig, 8) != 0)
                return "image bytes are not a PNG";
        }
    if (j.contains("cameras"))
        for (const json& c : j["cameras"]) {
            if (c.value("type", "") != "perspective" || !c.contains("perspective"))
                return "camera is not perspective";
            const json& p = c["perspective"];
            double yfov = p.at("yfov"), znear = p.at("znear");
            if (!(yfov > 0 && yfov < std::numbers::pi) || !(znear > 0) ||
                (p.contains("zfar") && !(p["zfar"].get<double>() > znear)))
                return "camera projection invalid";
        }
    const json* lights = nullptr;
    if (j.contains("extensions") && j["extensions"].contains("KHR_lights_punctual"))
        lights = &j["extensions"]["KHR_lights_punctual"]["lights"];
    if (lights) {
        bool declared = false;
        for (const json& e : j.value("extensionsUsed", json::array()))
            declared |= e == "KHR_lights_punctual";
        if (!declared) return "KHR_lights_punctual used but not in extensionsUsed";
        for (const json& l : *lights) {
            std::string type = l.at("type");
            if (type != "directional" && type != "point" && type != "spot") return "bad light type";
        }
    }
    // Nodes: references, one parent each, no cycles; the scene lists exactly the roots.
    const size_t nodeCount = j.contains("nodes") ? j["nodes"].size() : 0;
    std::vector<int> parents(nodeCount, 0);
    for (size_t i = 0; i < nodeCount; ++i) {
        const json& n = j["nodes"][i];
        if (!validRef(n, "mesh", j, "meshes") || !validRef(n, "camera", j, "cameras"))
            return "node mesh or camera out of range";
        if (n.contains("extensions") && n["extensions"].contains("KHR_lights_punctual")) {
            size_t l = n["extensions"]["KHR_lights_punctual"].at("light");
            if (!lights || l >= lights->size()) return "node light out of range";
        }
        if (n.contains("rotation")) {
            double len = 0;
            for (double c : n["rotation"])
                len += c * c;
            if (std::fabs(len - 1) > 1e-5) return "node rotation is not a unit quaternion";
        }
        for (size_t c : n.value("children", std::vector<size_t>{})) {
            if (c >= nodeCount) return "child out of range";
            if (++parents[c] > 1) return "node with two parents";
        }
    }
    if (!j.contains("scenes") || j["scenes"].size() != 1 || j.value("scene", -1) != 0)
        return "need one scene, selected by 'scene'";
    std::vector<size_t> roots = j["scenes"][0].value("nodes", std::vector<size_t>{});
    for (size_t r : roots)
        if (r >= nodeCount || parents[r] != 0) return "scene lists a non-root node";
    size_t reached = 0;
    std::vector<size_t> stack = roots;
    while (!stack.empty() && reached <= nodeCount) {
        size_t n = stack.back();
        stack.pop_back();
        ++reached;
        for (size_t c : j["nodes"][n].value("children", std::vector<size_t>{}))
            stack.push_back(c);
    }
    if (reached != nodeCount) return "nodes unreachable from the scene (a cycle or a lost root)";
    for (auto it = j.begin(); it != j.end(); ++it)
        if (it->is_array() && it->empty()) return "empty top-level array '" + it.key() + "'";
    return "";
}

} // namespace

std::string parseGlb(std::span<const uint8_t> bytes, ParsedGlb& out) {
    if (bytes.size() < 20) return "shorter than a GLB header and one chunk header";
    if (u32(bytes, 0) != 0x46546C67) return "bad magic";
    if (u32(bytes, 4) != 2) return "GLB version is not 2";
    if (u32(bytes, 8) != bytes.size()) return "header length differs from the file size";
    const size_t jsonLength = u32(bytes, 12);
    if (u32(bytes, 16) != 0x4E4F534A) return "first chunk is not JSON";
    if (jsonLength % 4 != 0 || 20 + jsonLength > bytes.size()) return "bad JSON chunk length";
    auto text = bytes.subspan(20, jsonLength);
    out.json = json::parse(text.begin(), text.end(), nullptr, false);
    if (out.json.is_discarded() || !out.json.is_object()) return "JSON chunk does not parse";
    size_t at = 20 + jsonLength;
    out.bin.clear();
    if (at < bytes.size()) {
        if (bytes.size() - at < 8) return "truncated BIN chunk header";
        const size_t binLength = u32(bytes, at);
        if (u32(bytes, at + 4) != 0x004E4942) return "second chunk is not BIN";
        if (binLength % 4 != 0 || at + 8 + binLength != bytes.size())
            return "BIN chunk length does not end the file";
        out.bin.assign(bytes.begin() + ptrdiff_t(at + 8), bytes.end());
    }
    return "";
}

std::string validateGltf(const ParsedGlb& g) {
    try {
        const json& j = g.json;
        if (!j.contains("asset") || j["asset"].value("version", "") != "2.0")
            return "asset.version is not 2.0";
        if (j["asset"].value("generator", "") != "penumbra assets_src")
            return "unexpected asset.generator";
        if (std::string e = validateAccessors(g); !e.empty()) return e;
        if (std::string e = validateMeshes(g); !e.empty()) return e;
        if (std::string e = validateSkinsAndAnimations(g); !e.empty()) return e;
        return validateRest(g);
    } catch (const json::exception& e) {
        return std::string("malformed JSON structure: ") + e.what();
    }
}

std::vector<double> readAccessor(const ParsedGlb& g, size_t accessor) {
    const json& a = g.json["accessors"][accessor];
    const json& v = g.json["bufferViews"][a["bufferView"].get<size_t>()];
    const int ct = a["componentType"];
    const size_t cs = componentSize(ct), cc = componentCount(a["type"]);
    const size_t stride = v.value("byteStride", cs * cc);
    const size_t base = v.value("byteOffset", size_t(0)) + a.value("byteOffset", size_t(0));
    const size_t count = a["count"];
    std::vector<double> out;
    out.reserve(count * cc);
    for (size_t i = 0; i < count; ++i)
        for (size_t c = 0; c < cc; ++c) {
            const uint8_t* p = g.bin.data() + base + i * stride + c * cs;
            if (ct == 5126) {
                float f;
                std::memcpy(&f, p, 4);
                out.push_back(f);
            } else if (ct == 5125) {
                uint32_t u;
                std::memcpy(&u, p, 4);
                out.push_back(u);
            } else if (ct == 5123) {
                uint16_t u;
                std::memcpy(&u, p, 2);
                out.push_back(u);
            } else {
                out.push_back(*p);
            }
        }
    return out;
}

uint64_t renderedTriangles(const ParsedGlb& g) {
    const json& j = g.json;
    uint64_t total = 0;
    std::vector<size_t> stack = j["scenes"][0].value("nodes", std::vector<size_t>{});
    while (!stack.empty()) {
        const json& n = j["nodes"][stack.back()];
        stack.pop_back();
        if (n.contains("mesh"))
            for (const json& p : j["meshes"][n["mesh"].get<size_t>()]["primitives"])
                total += j["accessors"][p["indices"].get<size_t>()]["count"].get<uint64_t>() / 3;
        for (size_t c : n.value("children", std::vector<size_t>{}))
            stack.push_back(c);
    }
    return total;
}

std::vector<Mat4> worldMatrices(const ParsedGlb& g) {
    const json& j = g.json;
    std::vector<Mat4> world(j["nodes"].size(), identity());
    std::vector<std::pair<size_t, Mat4>> stack;
    for (size_t r : j["scenes"][0].value("nodes", std::vector<size_t>{}))
        stack.push_back({r, identity()});
    while (!stack.empty()) {
        auto [n, parent] = stack.back();
        stack.pop_back();
        world[n] = multiply(parent, localMatrix(j["nodes"][n]));
        for (size_t c : j["nodes"][n].value("children", std::vector<size_t>{}))
            stack.push_back({c, world[n]});
    }
    return world;
}

Vec3 transformPoint(const Mat4& m, Vec3 p) {
    return {m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12],
            m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13],
            m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14]};
}

Vec3 transformDirection(const Mat4& m, Vec3 d) {
    return {m[0] * d[0] + m[4] * d[1] + m[8] * d[2], m[1] * d[0] + m[5] * d[1] + m[9] * d[2],
            m[2] * d[0] + m[6] * d[1] + m[10] * d[2]};
}

int findNode(const ParsedGlb& g, const std::string& name) {
    const json& nodes = g.json["nodes"];
    for (size_t i = 0; i < nodes.size(); ++i)
        if (nodes[i].value("name", "") == name) return int(i);
    return -1;
}

void Aabb::grow(Vec3 p) {
    for (int c = 0; c < 3; ++c) {
        min[c] = std::min(min[c], p[c]);
        max[c] = std::max(max[c], p[c]);
    }
}

Aabb worldBounds(const ParsedGlb& g, const std::vector<Mat4>& world, size_t node) {
    const json& j = g.json;
    Aabb box;
    for (const json& p : j["meshes"][j["nodes"][node]["mesh"].get<size_t>()]["primitives"]) {
        const json& a = j["accessors"][p["attributes"]["POSITION"].get<size_t>()];
        for (int k = 0; k < 8; ++k) {
            Vec3 corner;
            for (int c = 0; c < 3; ++c)
                corner[c] = (k >> c & 1) ? a["max"][c] : a["min"][c];
            box.grow(transformPoint(world[node], corner));
        }
    }
    return box;
}

std::array<double, 6> Frustum::planes(Vec3 p) const {
    // Camera-local coordinates: the inverse of a rigid matrix is its transpose on the
    // rotation part.
    Vec3 d{p[0] - world[12], p[1] - world[13], p[2] - world[14]};
    double x = world[0] * d[0] + world[1] * d[1] + world[2] * d[2];
    double y = world[4] * d[0] + world[5] * d[1] + world[6] * d[2];
    double z = world[8] * d[0] + world[9] * d[1] + world[10] * d[2];
    const double ty = std::tan(yfov / 2), tx = ty * aspect, depth = -z;
    return {depth - znear,   zfar - depth,   x + depth * tx,
            -x + depth * tx, y + depth * ty, -y + depth * ty};
}

bool Frustum::contains(Vec3 p) const {
    for (double v : planes(p))
        if (v < 0) return false;
    return true;
}

bool Frustum::boxOutside(const Aabb& box) const {
    std::array<int, 6> outside{};
    for (int k = 0; k < 8; ++k) {
        Vec3 corner;
        for (int c = 0; c < 3; ++c)
            corner[c] = (k >> c & 1) ? box.max[c] : box.min[c];
        std::array<double, 6> d = planes(corner);
        for (int i = 0; i < 6; ++i)
            outside[i] += d[i] < 0;
    }
    return std::any_of(outside.begin(), outside.end(), [](int n) { return n == 8; });
}

bool rayHitsBox(Vec3 o, Vec3 dir, const Aabb& box, double tMin, double tMax) {
    for (int c = 0; c < 3; ++c) {
        if (std::fabs(dir[c]) < 1e-12) {
            if (o[c] < box.min[c] || o[c] > box.max[c]) return false;
            continue;
        }
        double t0 = (box.min[c] - o[c]) / dir[c], t1 = (box.max[c] - o[c]) / dir[c];
        if (t0 > t1) std::swap(t0, t1);
        tMin = std::max(tMin, t0);
        tMax = std::min(tMax, t1);
        if (tMin > tMax) return false;
    }
    return true;
}

} // namespace pnb::test
