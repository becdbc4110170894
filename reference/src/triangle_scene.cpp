// The Embree scene of the Monte-Carlo tracers (triangle_scene.h).
#include "triangle_scene.h"

#include <algorithm>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "embree_geometry.h"
#include "mesh_decode.h"
#include "pnb/node_transform.h"
#include "self_intersection.h"
#include "translucency.h"

namespace pnb::reference::detail {

TriangleScene::~TriangleScene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
}

TracerResult<std::unique_ptr<TriangleScene>> buildTriangleScene(const Scene& scene, PosedScene& posed, glm::dvec3 origin,
                                                                const TriangleInstanceCallback& onInstance,
                                                                BlendSurfaces blend) {
    auto inputError = [](std::string message) { return TracerError{TracerErrorKind::Input, std::move(message)}; };
    auto out = std::make_unique<TriangleScene>();
    out->device = rtcNewDevice(nullptr);
    if (!out->device) return TracerError{TracerErrorKind::Embree, "Embree could not create a device"};
    out->scene = rtcNewScene(out->device);
    if (!out->scene) return TracerError{TracerErrorKind::Embree, "Embree: rtcNewScene failed"};
    // Robust: no traversal shortcuts that trade accuracy for speed; this is the reference.
    rtcSetSceneFlags(out->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(out->scene, RTC_BUILD_QUALITY_HIGH);

    // Every drawn copy of a mesh, as the player places them (EXT_mesh_gpu_instancing included),
    // in the pose traced.
    for (const MeshInstance& copy : posed.instances()) {
        const size_t i = copy.node;
        const Node& n = scene.nodes.nodes[i];
        if (n.mesh >= scene.meshes.size())
            return inputError(nodeName(scene, uint32_t(i)) + " refers to mesh " + std::to_string(n.mesh) + " of " +
                              std::to_string(scene.meshes.size()));
        const glm::dmat4 world = glm::make_mat4(copy.world.data());
        const Mesh& mesh = fullDetailMesh(scene, n.mesh); // the MDET detail, not a proxy
        if (mesh.primitive != Primitive::Triangles) continue;
        const uint64_t indexCount = mesh.indices.size() / (mesh.indexType == IndexType::U16 ? 2 : 4);
        for (const Submesh& sm : mesh.submeshes) {
            if (sm.lod != 0 || sm.material == kNone) continue;
            if (sm.material >= scene.materials.size())
                return inputError(meshName(scene, n.mesh) + " refers to material " + std::to_string(sm.material) +
                                  " of " + std::to_string(scene.materials.size()));
            // Blend surfaces reflect nothing here; those that cast shadows attenuate what
            // crosses them (translucency.h), the others let everything through.
            const Material& material = scene.materials[sm.material];
            const bool translucent = blend == BlendSurfaces::Translucent && isTranslucentCaster(material);
            if (material.alphaMode == AlphaMode::Blend && !translucent && blend == BlendSurfaces::Translucent) continue;
            if (uint64_t(sm.firstIndex) + sm.indexCount > indexCount)
                return inputError(meshName(scene, n.mesh) + ": submesh indices " + std::to_string(sm.firstIndex) +
                                  "+" + std::to_string(sm.indexCount) + " run past its " +
                                  std::to_string(indexCount) + " indices");
            std::vector<uint32_t> indices;
            const uint64_t end = uint64_t(sm.firstIndex) + sm.indexCount / 3 * 3;
            for (uint64_t k = sm.firstIndex; k < end; ++k) {
                const uint32_t index = readIndex(mesh, k);
                if (index >= mesh.vertexCount)
                    return inputError(meshName(scene, n.mesh) + ": index " + std::to_string(index) + " at position " +
                                      std::to_string(k) + " is not below vertexCount " +
                                      std::to_string(mesh.vertexCount));
                indices.push_back(index);
            }
            if (indices.empty()) continue;
            auto pos = posed.positions(copy.node);
            if (!pos) return pos.error();

            // Both queries: IndirectTracer intersects (it needs the hit), SkyTracer only asks
            // whether anything is in the way.
            const RTCFilterFunctionN filter = translucent ? passTranslucent : rejectOwnSurface;
            const auto id = attachTriangles(out->device, out->scene, {*pos, world, origin, indices, filter, true},
                                            out->tolerances, out->worldBand);
            if (!id) return TracerError{TracerErrorKind::Embree, "Embree: attaching a geometry failed"};
            out->triangles += indices.size() / 3;
            ++out->instances;
            if (out->worldOfGeometry.size() <= *id) out->worldOfGeometry.resize(*id + 1, glm::dmat4(1.0));
            out->worldOfGeometry[*id] = world;
            if (translucent) {
                ++out->translucentInstances;
                if (auto e = out->translucent.add(scene, *id, n.mesh, sm, std::move(indices))) return *e;
            } else if (onInstance)
                if (auto e = onInstance(*id, uint32_t(i), n.mesh, sm, std::move(indices))) return *e;
        }
    }
    rtcCommitScene(out->scene);
    if (rtcGetDeviceError(out->device) != RTC_ERROR_NONE)
        return TracerError{TracerErrorKind::Embree, "Embree: building the triangle scene failed"};
    return out;
}

} // namespace pnb::reference::detail
