// converter/src/convert_scene_graph.cpp — convertScene's scene stage (convert_internal.h): where
// the nodes are in the world, and the sun, camera and camera path a source lacks.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "convert_internal.h"
#include "pnb/path_json.h"

namespace pnb::converter::convert_detail {

namespace {

// Default sun when a scene has no directional light: 50° elevation, from 30° azimuth. Its
// intensity matches the player's default exposure (1.0) for mid-grey surfaces.
constexpr float kSunElevationRadians = 0.8726646f;
constexpr float kSunAzimuthRadians = 0.5235988f;
constexpr float kSunIntensityLux = 3.0f;

Mat4d trs(const Vec3& t, const Vec4& q, const Vec3& s) {
    double x = q.x, y = q.y, z = q.z, w = q.w;
    double n = std::sqrt(x * x + y * y + z * z + w * w);
    if (n > 0)
        x /= n, y /= n, z /= n, w /= n;
    else
        x = y = z = 0, w = 1;
    Mat4d r{};
    r.m[0] = (1 - 2 * (y * y + z * z)) * s.x;
    r.m[1] = (2 * (x * y + z * w)) * s.x;
    r.m[2] = (2 * (x * z - y * w)) * s.x;
    r.m[4] = (2 * (x * y - z * w)) * s.y;
    r.m[5] = (1 - 2 * (x * x + z * z)) * s.y;
    r.m[6] = (2 * (y * z + x * w)) * s.y;
    r.m[8] = (2 * (x * z + y * w)) * s.z;
    r.m[9] = (2 * (y * z - x * w)) * s.z;
    r.m[10] = (1 - 2 * (x * x + y * y)) * s.z;
    r.m[12] = t.x;
    r.m[13] = t.y;
    r.m[14] = t.z;
    r.m[15] = 1;
    return r;
}

Mat4d multiply(const Mat4d& a, const Mat4d& b) {
    Mat4d r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row)
            for (int k = 0; k < 4; ++k)
                r.m[c * 4 + row] += a.m[k * 4 + row] * b.m[c * 4 + k];
    return r;
}

Aabb transformBounds(const Mat4d& m, const Aabb& b) {
    Aabb out;
    if (b.min.x > b.max.x) return out;
    for (int i = 0; i < 8; ++i) {
        double p[3] = {(i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                       (i & 4) ? b.max.z : b.min.z};
        double r[3];
        for (int k = 0; k < 3; ++k)
            r[k] = m.m[k] * p[0] + m.m[4 + k] * p[1] + m.m[8 + k] * p[2] + m.m[12 + k];
        out.grow({float(r[0]), float(r[1]), float(r[2])});
    }
    return out;
}

// A sphere through a transform: the centre moves, the radius grows by the largest axis scale,
// so the result still contains everything the original did.
Sphere transformSphere(const Mat4d& m, const Sphere& s) {
    if (!(s.radius > 0)) return {};
    double c[3];
    for (int k = 0; k < 3; ++k)
        c[k] =
            m.m[k] * s.center.x + m.m[4 + k] * s.center.y + m.m[8 + k] * s.center.z + m.m[12 + k];
    double maxScale = 0;
    for (int col = 0; col < 3; ++col)
        maxScale = std::max(maxScale, std::sqrt(m.m[col * 4] * m.m[col * 4] +
                                                m.m[col * 4 + 1] * m.m[col * 4 + 1] +
                                                m.m[col * 4 + 2] * m.m[col * 4 + 2]));
    return {{float(c[0]), float(c[1]), float(c[2])}, float(s.radius * maxScale)};
}

// The world bounds of a node's mesh: of every EXT_mesh_gpu_instancing copy when it has them.
Aabb instancedBounds(const Mat4d& node, const std::vector<InstanceTransform>& instances,
                     const Aabb& mesh) {
    if (instances.empty()) return transformBounds(node, mesh);
    Aabb out;
    for (const InstanceTransform& t : instances) {
        const Aabb b =
            transformBounds(multiply(node, trs(t.translation, t.rotation, t.scale)), mesh);
        if (b.min.x > b.max.x) continue;
        out.grow(b.min);
        out.grow(b.max);
    }
    return out;
}

// A sphere holding every copy's sphere: centred on their centres' box, as large as the farthest.
Sphere instancedSphere(const Mat4d& node, const std::vector<InstanceTransform>& instances,
                       const Sphere& mesh) {
    if (instances.empty()) return transformSphere(node, mesh);
    std::vector<Sphere> copies;
    Aabb centres;
    for (const InstanceTransform& t : instances) {
        const Sphere s =
            transformSphere(multiply(node, trs(t.translation, t.rotation, t.scale)), mesh);
        if (!(s.radius > 0)) continue;
        copies.push_back(s);
        centres.grow(s.center);
    }
    if (copies.empty()) return {};
    const Vec3 c{(centres.min.x + centres.max.x) / 2, (centres.min.y + centres.max.y) / 2,
                 (centres.min.z + centres.max.z) / 2};
    double radius = 0;
    for (const Sphere& s : copies) {
        const double dx = s.center.x - c.x, dy = s.center.y - c.y, dz = s.center.z - c.z;
        radius = std::max(radius, std::sqrt(dx * dx + dy * dy + dz * dz) + s.radius);
    }
    return {c, float(radius)};
}

// The floats of stream `semantic` of a processed mesh (F32 streams only; empty otherwise).
std::vector<float> floatsOf(const std::vector<OwnedStream>& streams, VertexSemantic semantic) {
    for (const OwnedStream& st : streams)
        if (st.desc.semantic == semantic && st.desc.componentType == ComponentType::F32) {
            std::vector<float> out(st.bytes.size() / 4);
            if (!out.empty()) std::memcpy(out.data(), st.bytes.data(), out.size() * 4);
            return out;
        }
    return {};
}

// The joint indices of a processed skinned mesh (U8 or U16 x 4).
std::vector<uint32_t> jointsOf(const ProcessedMesh& mesh) {
    for (const OwnedStream& st : mesh.streams)
        if (st.desc.semantic == VertexSemantic::Joints0) {
            const bool u8 = st.desc.componentType == ComponentType::U8;
            std::vector<uint32_t> out(size_t(mesh.vertexCount) * 4);
            for (size_t k = 0; k < out.size(); ++k)
                out[k] = u8 ? uint32_t(st.bytes[k])
                            : uint32_t(st.bytes[2 * k]) | uint32_t(st.bytes[2 * k + 1]) << 8;
            return out;
        }
    return {};
}

// A deformed node's world bounds in the rest pose (docs/CONVERTER.md): its mesh at the default
// morph weights, skinned by its joints at rest (world(joint) x inverse bind matrix) or placed by
// its own world matrix when it has no skin. The player computes per-frame bounds.
Aabb restPoseBounds(const ProcessedMesh& mesh, const IrSkin* skin, const std::vector<Mat4d>& world,
                    const Mat4d& nodeWorld) {
    std::vector<float> positions = floatsOf(mesh.streams, VertexSemantic::Position);
    const size_t n = positions.size() / 3;
    for (size_t t = 0; t < mesh.morphTargets.size(); ++t) {
        const float w = mesh.morphWeights[t];
        if (w == 0) continue;
        const std::vector<float> delta = floatsOf(mesh.morphTargets[t].deltas, VertexSemantic::Position);
        for (size_t i = 0; i < delta.size() && i < positions.size(); ++i) positions[i] += w * delta[i];
    }
    Aabb out;
    if (!skin) {
        Aabb local;
        for (size_t i = 0; i < n; ++i) local.grow({positions[i * 3], positions[i * 3 + 1], positions[i * 3 + 2]});
        return transformBounds(nodeWorld, local);
    }
    std::vector<Mat4d> joint(skin->joints.size());
    for (size_t j = 0; j < joint.size(); ++j) {
        Mat4d ibm;
        for (int k = 0; k < 16; ++k) ibm.m[k] = skin->inverseBindMatrices[j][size_t(k)];
        joint[j] = multiply(world[size_t(skin->joints[j])], ibm);
    }
    const std::vector<uint32_t> joints = jointsOf(mesh);
    const std::vector<float> weights = floatsOf(mesh.streams, VertexSemantic::Weights0);
    if (joints.size() != n * 4 || weights.size() != n * 4) return out;
    for (size_t i = 0; i < n; ++i) {
        double r[3] = {0, 0, 0};
        const double p[3] = {positions[i * 3], positions[i * 3 + 1], positions[i * 3 + 2]};
        for (int k = 0; k < 4; ++k) {
            const double w = weights[i * 4 + size_t(k)];
            const uint32_t j = joints[i * 4 + size_t(k)];
            if (w == 0 || j >= joint.size()) continue;
            const Mat4d& m = joint[j];
            for (int c = 0; c < 3; ++c)
                r[c] += w * (m.m[c] * p[0] + m.m[4 + c] * p[1] + m.m[8 + c] * p[2] + m.m[12 + c]);
        }
        out.grow({float(r[0]), float(r[1]), float(r[2])});
    }
    return out;
}

Sphere sphereOfBox(const Aabb& b) {
    if (b.min.x > b.max.x) return {};
    const Vec3 c{(b.min.x + b.max.x) / 2, (b.min.y + b.max.y) / 2, (b.min.z + b.max.z) / 2};
    const double dx = b.max.x - c.x, dy = b.max.y - c.y, dz = b.max.z - c.z;
    return {c, std::nextafter(float(std::sqrt(dx * dx + dy * dy + dz * dz)), 3.4e38f)};
}

// A root node the converter adds (default sun or camera): placed, without bounds of its own.
void appendRootNode(IrScene& scene, NodePlacement& placement, IrNode node) {
    placement.world.push_back(trs(node.translation, node.rotation, node.scale));
    placement.nodeBounds.emplace_back();
    placement.nodeSpheres.emplace_back();
    scene.nodes.push_back(std::move(node));
}

// World transforms and bounds of the source's nodes, from the processed meshes' bounds.
NodePlacement placeNodes(const IrScene& scene, const std::vector<ProcessedMesh>& meshes) {
    NodePlacement p;
    p.world.resize(scene.nodes.size());
    p.nodeBounds.resize(scene.nodes.size());
    p.nodeSpheres.resize(scene.nodes.size());
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const IrNode& n = scene.nodes[i];
        Mat4d local = trs(n.translation, n.rotation, n.scale);
        p.world[i] = n.parent >= 0 ? multiply(p.world[size_t(n.parent)], local) : local;
    }
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const IrNode& n = scene.nodes[i];
        if (n.mesh >= 0 && size_t(n.mesh) < meshes.size()) {
            const ProcessedMesh& mesh = meshes[size_t(n.mesh)];
            // Joints may come after the node in the list: every world matrix is known here.
            const IrSkin* skin = n.skin >= 0 ? &scene.skins[size_t(n.skin)] : nullptr;
            if (mesh.deformed) {
                p.nodeBounds[i] = restPoseBounds(mesh, skin, p.world, p.world[i]);
                p.nodeSpheres[i] = sphereOfBox(p.nodeBounds[i]);
            } else {
                p.nodeBounds[i] = instancedBounds(p.world[i], n.instances, mesh.bounds);
                p.nodeSpheres[i] = instancedSphere(p.world[i], n.instances, mesh.boundingSphere);
            }
            if (p.nodeBounds[i].min.x <= p.nodeBounds[i].max.x) {
                p.sceneBounds.grow(p.nodeBounds[i].min);
                p.sceneBounds.grow(p.nodeBounds[i].max);
            }
        }
    }
    return p;
}

// A directional light and its node when the source has no directional light; returns whether
// it added one. The node stands outside the scene's bounds, shining at their centre.
bool addDefaultSunIfMissing(IrScene& scene, NodePlacement& placement) {
    const bool hasSun = std::any_of(scene.lights.begin(), scene.lights.end(), [](const IrLight& l) {
        return l.type == LightType::Directional;
    });
    if (hasSun) return false;
    const Aabb& bounds = placement.sceneBounds;
    Vec3 center{0, 0, 0};
    float radius = 1;
    if (bounds.min.x <= bounds.max.x) {
        center = {(bounds.min.x + bounds.max.x) / 2, (bounds.min.y + bounds.max.y) / 2,
                  (bounds.min.z + bounds.max.z) / 2};
        Vec3 e{bounds.max.x - center.x, bounds.max.y - center.y, bounds.max.z - center.z};
        radius = std::max(std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z), 1e-3f);
    }
    IrLight sun;
    sun.name = "default-sun";
    sun.type = LightType::Directional;
    sun.color = {1.0f, 0.97f, 0.92f};
    sun.intensity = kSunIntensityLux;
    scene.lights.push_back(sun);
    Vec3 toSun{std::cos(kSunElevationRadians) * std::sin(kSunAzimuthRadians),
               std::sin(kSunElevationRadians),
               std::cos(kSunElevationRadians) * std::cos(kSunAzimuthRadians)};
    IrNode node;
    node.name = "default-sun";
    node.translation = {center.x + toSun.x * 2 * radius, center.y + toSun.y * 2 * radius,
                        center.z + toSun.z * 2 * radius};
    node.rotation = lookAtRotation(node.translation, center); // shines down its -Z
    node.light = int(scene.lights.size() - 1);
    appendRootNode(scene, placement, std::move(node));
    return true;
}

// A camera framing the scene's bounds when the source has none; returns whether it added one.
bool addDefaultCameraIfMissing(IrScene& scene, NodePlacement& placement) {
    if (!scene.cameras.empty()) return false;
    // Where the default orbit starts (camera_path.h "framing"): the bounding sphere inside
    // the frustum with a 10 % margin, near and far planes from the sphere.
    const Framing framing = frameBounds(placement.sceneBounds);
    IrCamera cam;
    cam.name = "default-camera";
    cam.yfovRadians = kDefaultYfovRadians;
    cam.znear = framing.znear;
    cam.zfar = framing.zfar;
    scene.cameras.push_back(cam);
    IrNode node;
    node.name = "default-camera";
    node.translation = framingPosition(framing, 0.0f);
    node.rotation = lookAtRotation(node.translation, framing.center);
    node.camera = 0;
    appendRootNode(scene, placement, std::move(node));
    return true;
}

// The camera path of --path, else the default orbit around the scene's bounds.
Result<std::vector<PathSpec>, ConvertError>
loadOrDefaultCameraPaths(const ConvertSettings& s, const Aabb& sceneBounds, ConvertSummary& sum) {
    std::vector<PathSpec> paths;
    if (!s.cameraPath.empty()) {
        auto p = loadCameraPath(s.cameraPath);
        if (!p) return p.error();
        paths.push_back(std::move(*p));
        sum.dependencies.push_back(s.cameraPath);
    } else {
        paths.push_back(defaultCameraPath(sceneBounds));
        sum.defaultPath = true;
    }
    return paths;
}

} // namespace

Result<SceneGraph, ConvertError> completeSceneGraph(const ConvertSettings& s, IrScene& scene,
                                                    const std::vector<ProcessedMesh>& meshes,
                                                    ConvertSummary& sum) {
    SceneGraph graph;
    // The default environment goes with a source that has no light of its own (before the
    // default sun): a scene that lights itself (a lamp in a closed room) keeps its look.
    graph.sourceHasLights = !scene.lights.empty();
    graph.generatedLight.assign(scene.lights.size(), false);
    // World bounds first: the default sun, camera and path frame them.
    graph.placement = placeNodes(scene, meshes);
    sum.defaultSun = addDefaultSunIfMissing(scene, graph.placement);
    if (sum.defaultSun) graph.generatedLight.push_back(true);
    sum.defaultCamera = addDefaultCameraIfMissing(scene, graph.placement);
    // After the default sun, before anything reads the lights: ranges, shadow flags and the
    // kMaxLights cap (which remaps node.light) are decided here, once.
    processLights(scene, graph.generatedLight, s.lights, sum.warnings);
    auto paths = loadOrDefaultCameraPaths(s, graph.placement.sceneBounds, sum);
    if (!paths) return paths.error();
    graph.paths = std::move(*paths);
    return graph;
}

} // namespace pnb::converter::convert_detail
