// converter/src/import_gltf_nodes.cpp — the glTF node trees into IR nodes (TRS, matrices
// decomposed), with the cameras and KHR_lights_punctual lights they carry. The last stage of the
// glTF importer: it pulls in meshes and materials through the other stages
// (import_gltf_internal.h).
//
// Index: [SECTION] lights and cameras, [SECTION] nodes
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "import_gltf_internal.h"

namespace pnb::converter::gltf_internal {

namespace {

// [SECTION] lights and cameras

// The IR index of KHR_lights_punctual light `index`, or -1 when it is dropped (warned).
Result<int, ConvertError> importLight(Ctx& ctx, int index, const std::string& who) {
    const tinygltf::Model& m = ctx.model;
    if (index < 0 || size_t(index) >= m.lights.size()) {
        return ctx.fail(strf("%s: light %d does not exist (%zu lights)", who.c_str(), index,
                             m.lights.size()));
    }
    int& mapped = ctx.lightMap[size_t(index)];
    if (mapped != -1) return mapped == -2 ? -1 : mapped;
    const tinygltf::Light& src = m.lights[size_t(index)];
    const std::string lightWho = label("light", index, m.lights);
    IrLight light;
    light.name = src.name;
    if (src.type == "directional") {
        light.type = LightType::Directional;
    } else if (src.type == "point") {
        light.type = LightType::Point;
    } else if (src.type == "spot") {
        light.type = LightType::Spot;
    } else {
        ctx.warn(lightWho + ": type '" + src.type + "' is unknown; dropped");
        mapped = -2;
        return -1;
    }
    if (src.color.size() == 3 && finiteAll(src.color)) {
        light.color = {clampOr(src.color[0], 0, 1, 1), clampOr(src.color[1], 0, 1, 1),
                       clampOr(src.color[2], 0, 1, 1)};
    } else if (!src.color.empty()) {
        ctx.warn(lightWho + ": color is not 3 numbers; using white");
    }
    light.intensity = clampOr(src.intensity, 0, std::numeric_limits<float>::max(), 1);
    if (!(src.intensity >= 0) || !std::isfinite(src.intensity))
        ctx.warn(lightWho + strf(": intensity %g is not a finite number >= 0; %g", src.intensity,
                                 double(light.intensity)));
    // range: absent (tinygltf: 0) stays 0, an invalid one (negative, or too large for a float)
    // is passed on as it is: processLights (light_processing.h) replaces both with the computed
    // range and warns, naming the light, whichever importer it came from.
    if (std::isnan(src.range)) light.range = std::numeric_limits<float>::quiet_NaN();
    else if (std::fabs(src.range) > double(std::numeric_limits<float>::max()))
        light.range = (src.range > 0 ? 1 : -1) * std::numeric_limits<float>::infinity();
    else light.range = float(src.range);
    if (light.type == LightType::Spot) {
        const double inner = src.spot.innerConeAngle, outer = src.spot.outerConeAngle;
        light.outerConeRadians = clampOr(outer, 0, kMaxSpotConeRadians, 0.7853982f);
        light.innerConeRadians = clampOr(inner, 0, light.outerConeRadians, 0.0f);
        // In double, so that pi/2 written as 1.5707963267948966 is inside.
        if (!(inner >= 0 && inner <= outer && outer <= double(kMaxSpotConeRadians))) {
            ctx.warn(lightWho + strf(": spot cone angles (inner %g, outer %g) outside 0 <= inner "
                                     "<= outer <= pi/2; clamped to inner %g, outer %g",
                                     inner, outer, double(light.innerConeRadians),
                                     double(light.outerConeRadians)));
        }
    }
    ctx.scene.lights.push_back(std::move(light));
    return mapped = int(ctx.scene.lights.size() - 1);
}

Result<int, ConvertError> importCamera(Ctx& ctx, int index, const std::string& who) {
    const tinygltf::Model& m = ctx.model;
    if (index < 0 || size_t(index) >= m.cameras.size()) {
        return ctx.fail(strf("%s: camera %d does not exist (%zu cameras)", who.c_str(), index,
                             m.cameras.size()));
    }
    if (ctx.cameraMap[size_t(index)] != -1) return ctx.cameraMap[size_t(index)];
    const tinygltf::Camera& src = m.cameras[size_t(index)];
    const float kMax = std::numeric_limits<float>::max();
    IrCamera cam;
    cam.name = src.name;
    if (src.type == "orthographic") { // tinygltf accepts only the two types
        const tinygltf::OrthographicCamera& o = src.orthographic;
        cam.projection = Projection::Orthographic;
        cam.xmag = clampOr(o.xmag, -kMax, kMax, 1);
        cam.ymag = clampOr(o.ymag, -kMax, kMax, 1);
        cam.znear = clampOr(o.znear, 0, kMax, 0);
        cam.zfar = clampOr(o.zfar, 0, kMax, 0);
    } else {
        const tinygltf::PerspectiveCamera& p = src.perspective;
        cam.projection = Projection::Perspective;
        cam.yfovRadians = p.yfov > 0 ? clampOr(p.yfov, 0, 3.1415926f, 0.8f) : 0.8f;
        cam.aspectRatio = clampOr(p.aspectRatio, 0, kMax, 0); // absent: tinygltf gives 0
        cam.znear = p.znear > 0 ? clampOr(p.znear, 0, kMax, 0.1f) : 0.1f;
        cam.zfar = clampOr(p.zfar, 0, kMax, 0); // absent (infinite): tinygltf gives 0
        if (p.yfov <= 0 || p.znear <= 0) {
            ctx.warn(label("camera", index, m.cameras) + ": yfov and znear must be > 0; "
                                                          "defaults used");
        }
    }
    ctx.scene.cameras.push_back(std::move(cam));
    return ctx.cameraMap[size_t(index)] = int(ctx.scene.cameras.size() - 1);
}

// [SECTION] nodes

struct Dvec3 { double x, y, z; };
double dot(const Dvec3& a, const Dvec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Dvec3 cross(const Dvec3& a, const Dvec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Dvec3 scaled(const Dvec3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
Dvec3 minus(const Dvec3& a, const Dvec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }

// Rotation matrix (columns c0 c1 c2, orthonormal, det +1) to a unit quaternion xyzw (Shepperd).
Vec4 quaternionFromColumns(const Dvec3& c0, const Dvec3& c1, const Dvec3& c2) {
    const double m00 = c0.x, m10 = c0.y, m20 = c0.z;
    const double m01 = c1.x, m11 = c1.y, m21 = c1.z;
    const double m02 = c2.x, m12 = c2.y, m22 = c2.z;
    double x, y, z, w;
    const double trace = m00 + m11 + m22;
    if (trace > 0) {
        const double s = std::sqrt(trace + 1.0) * 2;
        w = 0.25 * s; x = (m21 - m12) / s; y = (m02 - m20) / s; z = (m10 - m01) / s;
    } else if (m00 > m11 && m00 > m22) {
        const double s = std::sqrt(1.0 + m00 - m11 - m22) * 2;
        w = (m21 - m12) / s; x = 0.25 * s; y = (m01 + m10) / s; z = (m02 + m20) / s;
    } else if (m11 > m22) {
        const double s = std::sqrt(1.0 + m11 - m00 - m22) * 2;
        w = (m02 - m20) / s; x = (m01 + m10) / s; y = 0.25 * s; z = (m12 + m21) / s;
    } else {
        const double s = std::sqrt(1.0 + m22 - m00 - m11) * 2;
        w = (m10 - m01) / s; x = (m02 + m20) / s; y = (m12 + m21) / s; z = 0.25 * s;
    }
    const double len = std::sqrt(x * x + y * y + z * z + w * w);
    if (!(len > 0) || !std::isfinite(len)) return {0, 0, 0, 1};
    return {float(x / len), float(y / len), float(z / len), float(w / len)};
}

// Column-major 4x4 into TRS. A negative determinant becomes a negative x scale. Shear (columns
// not orthogonal) and a projective last row cannot be represented: we warn and take the
// Gram-Schmidt rotation, which keeps the x axis exact.
void decomposeMatrix(Ctx& ctx, const std::vector<double>& m, IrNode& node, const std::string& who) {
    if (!finiteAll(m)) {
        ctx.warn(who + ": matrix has non-finite values; using identity");
        return;
    }
    node.translation = {float(m[12]), float(m[13]), float(m[14])};
    Dvec3 c[3] = {{m[0], m[1], m[2]}, {m[4], m[5], m[6]}, {m[8], m[9], m[10]}};
    double s[3] = {std::sqrt(dot(c[0], c[0])), std::sqrt(dot(c[1], c[1])),
                   std::sqrt(dot(c[2], c[2]))};
    if (m[3] != 0 || m[7] != 0 || m[11] != 0 || m[15] != 1) {
        ctx.warn(who + ": matrix is projective (last row not 0 0 0 1); the row is ignored");
    }
    const double kTiny = 1e-12;
    if (s[0] < kTiny || s[1] < kTiny || s[2] < kTiny) {
        ctx.warn(who + ": matrix has a zero scale axis; rotation set to identity");
        node.scale = {float(s[0]), float(s[1]), float(s[2])};
        return;
    }
    if (dot(c[0], cross(c[1], c[2])) < 0) s[0] = -s[0]; // a mirror: flip x
    for (int i = 0; i < 3; ++i) c[i] = scaled(c[i], 1.0 / s[i]);
    const double kShear = 1e-4;
    if (std::abs(dot(c[0], c[1])) > kShear || std::abs(dot(c[0], c[2])) > kShear ||
        std::abs(dot(c[1], c[2])) > kShear) {
        ctx.warn(who + ": matrix has shear, which TRS cannot express; decomposed approximately");
    }
    const Dvec3 r0 = c[0];
    Dvec3 r1 = minus(c[1], scaled(r0, dot(c[1], r0)));
    const double len1 = std::sqrt(dot(r1, r1));
    r1 = len1 > kTiny ? scaled(r1, 1.0 / len1) : (std::abs(r0.x) < 0.9 ? Dvec3{1, 0, 0}
                                                                          : Dvec3{0, 1, 0});
    if (len1 <= kTiny) { // c1 parallel to c0: any perpendicular axis
        r1 = minus(r1, scaled(r0, dot(r1, r0)));
        r1 = scaled(r1, 1.0 / std::sqrt(dot(r1, r1)));
    }
    const Dvec3 r2 = cross(r0, r1);
    node.rotation = quaternionFromColumns(r0, r1, r2);
    node.scale = {float(s[0]), float(s[1]), float(s[2])};
}

void applyTrs(Ctx& ctx, const tinygltf::Node& src, IrNode& node, const std::string& who) {
    if (!src.matrix.empty()) {
        if (src.matrix.size() == 16) {
            decomposeMatrix(ctx, src.matrix, node, who);
        } else {
            ctx.warn(strf("%s: matrix has %zu values, not 16; using identity", who.c_str(),
                          src.matrix.size()));
        }
        return;
    }
    auto vec = [&](const std::vector<double>& v, size_t n, const char* name) {
        if (v.empty()) return false;
        if (v.size() == n && finiteAll(v)) return true;
        ctx.warn(strf("%s: %s is not %zu finite numbers; using the default", who.c_str(), name,
                      n));
        return false;
    };
    if (vec(src.translation, 3, "translation")) {
        node.translation = {float(src.translation[0]), float(src.translation[1]),
                            float(src.translation[2])};
    }
    if (vec(src.scale, 3, "scale")) {
        node.scale = {float(src.scale[0]), float(src.scale[1]), float(src.scale[2])};
    }
    if (vec(src.rotation, 4, "rotation")) {
        const auto& q = src.rotation;
        const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (len > 1e-12 && std::isfinite(len)) {
            node.rotation = {float(q[0] / len), float(q[1] / len), float(q[2] / len),
                             float(q[3] / len)};
            if (std::abs(len - 1.0) > 1e-3) ctx.warn(who + ": rotation was not unit; normalized");
        } else {
            ctx.warn(who + ": rotation is a zero quaternion; using identity");
        }
    }
}

// EXT_mesh_gpu_instancing: the node's per-copy TRANSLATION, ROTATION and SCALE accessors (any
// may be absent: identity), all with one count.
Check importInstances(Ctx& ctx, const tinygltf::Value& ext, IrNode& node, const std::string& who) {
    const tinygltf::Value* attributes = member(&ext, "attributes");
    if (!attributes || !attributes->IsObject())
        return ctx.fail(who + ": EXT_mesh_gpu_instancing has no 'attributes' object");
    struct Channel { const char* name; int components; std::vector<float> data; };
    Channel channels[] = {{"TRANSLATION", 3, {}}, {"ROTATION", 4, {}}, {"SCALE", 3, {}}};
    size_t count = 0;
    bool any = false;
    for (Channel& c : channels) {
        const std::optional<int> accessor = intOf(member(attributes, c.name));
        if (!accessor) continue;
        const std::string where = who + " EXT_mesh_gpu_instancing " + c.name;
        int components = 0;
        auto data = readFloats(ctx, *accessor, where, {c.components, c.components, false}, components);
        if (!data) return data.error();
        const size_t n = data->size() / size_t(c.components);
        if (any && n != count)
            return ctx.fail(strf("%s: count %zu differs from the other attributes' %zu",
                                 where.c_str(), n, count));
        count = n;
        any = true;
        c.data = std::move(data).value();
    }
    if (!any || count == 0) {
        ctx.warn(who + ": EXT_mesh_gpu_instancing has no instances; the mesh is drawn once");
        return std::nullopt;
    }
    if (auto e = ctx.fits(uint64_t(count) * sizeof(InstanceTransform), who)) return e;
    node.instances.resize(count);
    size_t repaired = 0;
    for (size_t i = 0; i < count; ++i) {
        InstanceTransform& t = node.instances[i];
        if (!channels[0].data.empty()) t.translation = {channels[0].data[i * 3], channels[0].data[i * 3 + 1], channels[0].data[i * 3 + 2]};
        if (!channels[1].data.empty()) {
            const float* q = &channels[1].data[i * 4];
            const double len = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
            if (len > 1e-12 && std::isfinite(len)) t.rotation = {float(q[0] / len), float(q[1] / len), float(q[2] / len), float(q[3] / len)};
            else ++repaired;
        }
        if (!channels[2].data.empty()) t.scale = {channels[2].data[i * 3], channels[2].data[i * 3 + 1], channels[2].data[i * 3 + 2]};
        const float values[] = {t.translation.x, t.translation.y, t.translation.z, t.scale.x, t.scale.y, t.scale.z};
        if (!std::all_of(std::begin(values), std::end(values), [](float v) { return std::isfinite(v); })) {
            t = InstanceTransform{};
            ++repaired;
        }
    }
    if (repaired)
        ctx.warn(strf("%s: EXT_mesh_gpu_instancing: %zu instances with a non-finite or zero "
                      "transform reset to identity", who.c_str(), repaired));
    return std::nullopt;
}

// Fills in one IR node from glTF node `index`; imports what it references.
Check importNodeContent(Ctx& ctx, int index, IrNode& node) {
    const tinygltf::Node& src = ctx.model.nodes[size_t(index)];
    const std::string who = label("node", index, ctx.model.nodes);
    node.name = src.name;
    applyTrs(ctx, src, node, who);
    if (src.skin >= 0 && size_t(src.skin) >= ctx.model.skins.size())
        return ctx.fail(strf("%s: skin %d does not exist (%zu skins)", who.c_str(), src.skin,
                             ctx.model.skins.size()));
    if (src.mesh >= 0) {
        const bool skinned = src.skin >= 0;
        auto mesh = importMesh(ctx, src.mesh, src.weights, skinned, who);
        if (!mesh) return mesh.error();
        node.mesh = *mesh;
        // The glTF skin index until importSkins turns it into the IR skin's.
        node.skin = src.skin;
        const tinygltf::Value* ext = extensionObject(src.extensions, "EXT_mesh_gpu_instancing");
        if (ext && skinned)
            ctx.warn(who + ": EXT_mesh_gpu_instancing on a skinned node ignored (a skin deforms "
                           "one copy); the mesh is drawn once");
        else if (ext)
            if (auto e = importInstances(ctx, *ext, node, who)) return e;
    }
    if (src.camera >= 0) {
        auto camera = importCamera(ctx, src.camera, who);
        if (!camera) return camera.error();
        node.camera = *camera;
    }
    if (const tinygltf::Value* ext = extensionObject(src.extensions, "KHR_lights_punctual")) {
        const std::optional<int> light = intOf(member(ext, "light"));
        if (!light) return ctx.fail(who + ": KHR_lights_punctual has no integer 'light'");
        auto imported = importLight(ctx, *light, who);
        if (!imported) return imported.error();
        node.light = *imported;
    }
    return std::nullopt;
}

} // namespace

// Flattens the trees under `roots` into ctx.scene.nodes, parents first (depth-first pre-order,
// with an explicit stack because a chain of nodes can be as long as the file allows).
Check flattenNodes(Ctx& ctx, const std::vector<int>& roots, const std::string& rootsWho) {
    const tinygltf::Model& m = ctx.model;
    std::vector<int> irIndexOf(m.nodes.size(), -1);
    struct Pending { int node, irParent, parent; }; // parent: glTF index, -1 for a root
    std::vector<Pending> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, -1, -1});
    while (!stack.empty()) {
        const Pending cur = stack.back();
        stack.pop_back();
        const std::string referrer =
            cur.parent < 0 ? rootsWho : label("node", cur.parent, m.nodes);
        if (cur.node < 0 || size_t(cur.node) >= m.nodes.size()) {
            return ctx.fail(strf("%s refers to node %d, which does not exist (%zu nodes)",
                                 referrer.c_str(), cur.node, m.nodes.size()));
        }
        const std::string who = label("node", cur.node, m.nodes);
        if (const int placed = irIndexOf[size_t(cur.node)]; placed >= 0) {
            for (int a = cur.irParent; a >= 0; a = ctx.scene.nodes[size_t(a)].parent) {
                if (a == placed) {
                    return ctx.fail(who + ": the node graph has a cycle (" + who +
                                    " is its own ancestor)");
                }
            }
            return ctx.fail(who + " is referenced more than once (again by " + referrer +
                            "); glTF nodes must form strict trees");
        }
        IrNode node;
        node.parent = cur.irParent;
        if (auto e = importNodeContent(ctx, cur.node, node)) return e;
        irIndexOf[size_t(cur.node)] = int(ctx.scene.nodes.size());
        ctx.nodeMap[size_t(cur.node)] = int(ctx.scene.nodes.size());
        ctx.scene.nodes.push_back(std::move(node));
        const int irIndex = int(ctx.scene.nodes.size() - 1);
        const std::vector<int>& children = m.nodes[size_t(cur.node)].children;
        for (auto it = children.rbegin(); it != children.rend(); ++it) {
            stack.push_back({*it, irIndex, cur.node});
        }
    }
    return std::nullopt;
}

// The roots to import: the default scene's (or scene 0's) nodes. A file without scenes gets
// every node that is nobody's child, since there is nothing else to convert.
Result<std::vector<int>, ConvertError> chooseRoots(Ctx& ctx, std::string& rootsWho) {
    const tinygltf::Model& m = ctx.model;
    if (m.scenes.empty()) {
        if (m.defaultScene >= 0) {
            return ctx.fail(strf("scene %d does not exist (the file has no scenes)",
                                 m.defaultScene));
        }
        std::vector<bool> isChild(m.nodes.size(), false);
        for (const tinygltf::Node& n : m.nodes) {
            for (int c : n.children) {
                if (c >= 0 && size_t(c) < m.nodes.size()) isChild[size_t(c)] = true;
            }
        }
        std::vector<int> roots;
        for (size_t i = 0; i < m.nodes.size(); ++i) {
            if (!isChild[i]) roots.push_back(int(i));
        }
        if (!m.nodes.empty()) ctx.warn("no scenes; importing every root node");
        rootsWho = "the root node list";
        return roots;
    }
    const int scene = m.defaultScene >= 0 ? m.defaultScene : 0;
    if (size_t(scene) >= m.scenes.size()) {
        return ctx.fail(strf("scene %d does not exist (%zu scenes)", scene, m.scenes.size()));
    }
    rootsWho = label("scene", scene, m.scenes);
    if (m.scenes.size() > 1) {
        ctx.warn(strf("%zu scenes; importing %s, the others are ignored", m.scenes.size(),
                      rootsWho.c_str()));
    }
    return m.scenes[size_t(scene)].nodes;
}

} // namespace pnb::converter::gltf_internal
