// assets_src/src/procedural_light_field.cpp — the light-field scene: a floor with a grid of boxes
// lit by N point lights, the deferred-vs-forward benchmark (procedural_scenes.h). A file of its
// own: only the benchmark scripts make it.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include "procedural_scenes_internal.h"

namespace pnb::assets {

using namespace procedural_detail;

// [SECTION] light-field -------------------------------------------------------------------------

gltf::Document buildLightField(const LightFieldOptions& o) {
    Document doc;
    doc.sceneName = "light-field";
    const float size = o.sizeMeters, half = size / 2;
    const uint32_t boxes = std::max(1u, o.boxesPerSide);
    const float cell = size / float(boxes);

    const uint32_t floorMaterial =
        addMaterial(doc, makeMaterial("floor", {0.6f, 0.6f, 0.6f}, 0.6f));
    constexpr Float3 kBoxColors[] = {
        {0.7f, 0.25f, 0.2f}, {0.25f, 0.55f, 0.3f}, {0.25f, 0.35f, 0.7f}, {0.75f, 0.7f, 0.6f}};
    std::vector<int32_t> boxMeshes;
    for (size_t k = 0; k < std::size(kBoxColors); ++k) {
        const uint32_t mat = addMaterial(
            doc, makeMaterial("box-" + std::to_string(k), kBoxColors[k], 0.4f + 0.1f * float(k)));
        boxMeshes.push_back(
            addMesh(doc, boxesMesh("unit-box-" + std::to_string(k),
                                   {{{-0.5f, 0, -0.5f}, {0.5f, 1, 0.5f}}}, 1.0f, mat, mat)));
    }

    Mesh floorMesh;
    floorMesh.name = "floor";
    floorMesh.primitives.resize(1);
    floorMesh.primitives[0].material = floorMaterial;
    const uint32_t n = std::max(1u, o.floorSubdivisions);
    addGrid(floorMesh.primitives[0], {-half, 0, -half}, {0, 0, size}, {size, 0, 0}, n, n, false);
    addNode(doc, meshNode("floor", addMesh(doc, std::move(floorMesh))));

    Pcg32 boxRng(o.seed, kStreamLightFieldBoxes);
    for (uint32_t j = 0; j < boxes; ++j)
        for (uint32_t i = 0; i < boxes; ++i) {
            const float w = boxRng.uniform(0.3f, 0.6f) * cell,
                        d = boxRng.uniform(0.3f, 0.6f) * cell;
            const float h = boxRng.uniform(1.0f, 4.0f);
            const uint32_t colour = boxRng.below(uint32_t(boxMeshes.size()));
            Node node =
                meshNode("box-" + std::to_string(i) + "-" + std::to_string(j), boxMeshes[colour],
                         {-half + (float(i) + 0.5f) * cell, 0, -half + (float(j) + 0.5f) * cell});
            node.scale = {w, h, d};
            addNode(doc, std::move(node));
        }

    // Point lights on a jittered grid over the floor, above every box.
    constexpr Float3 kLightColors[] = {{1.0f, 0.85f, 0.6f}, {0.6f, 0.75f, 1.0f},
                                       {1.0f, 0.6f, 0.5f},  {0.7f, 1.0f, 0.7f},
                                       {1.0f, 1.0f, 1.0f},  {0.9f, 0.7f, 1.0f}};
    const uint32_t lights = std::min(o.lights, 4096u);
    if (lights > 0) {
        const auto side = uint32_t(std::ceil(std::sqrt(double(lights))));
        const float lightCell = size / float(side);
        const float range = std::max(6.0f, 2.5f * lightCell);
        const float intensity = 120.0f / std::sqrt(float(lights));
        Pcg32 lightRng(o.seed, kStreamLightFieldLights);
        for (uint32_t k = 0; k < lights; ++k) {
            const float x =
                -half + (float(k % side) + 0.5f + lightRng.uniform(-0.35f, 0.35f)) * lightCell;
            const float z =
                -half + (float(k / side) + 0.5f + lightRng.uniform(-0.35f, 0.35f)) * lightCell;
            const float y = lightRng.uniform(4.5f, 6.0f);
            const std::string name = "point-light-" + std::to_string(k);
            doc.lights.push_back({.name = name,
                                  .type = gltf::LightType::Point,
                                  .color = kLightColors[k % std::size(kLightColors)],
                                  .intensity = intensity,
                                  .range = range});
            Node l;
            l.name = name;
            l.translation = {x, y, z};
            l.light = int32_t(doc.lights.size() - 1);
            addNode(doc, std::move(l));
        }
    }

    addCamera(doc, "low-camera", {0, 3.0f, 0.45f * size}, {0, -2.5f, -0.6f * size}, radians(55),
              16.0f / 9.0f, 0.1f, 4.0f * size);
    addSun(doc, sunDirection(radians(40), radians(20)), {0, 0, 0}, size, {0.7f, 0.75f, 1.0f}, 0.3f);
    return doc;
}

} // namespace pnb::assets
