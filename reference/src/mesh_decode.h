// mesh_decode.h — reading a container's meshes as the GPU's vertex fetch does, for the Embree
// tracers (shadow_tracer.cpp, indirect_tracer.cpp). Internal to pnb_reference.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "pnb/scene.h"
#include "pnb_reference/shadow_tracer.h"

namespace pnb::reference::detail {

// "mesh 3 'floor'", "node 7 'lamp'", "light 1 'bulb'": names for error messages ("" names are
// left out).
std::string meshName(const Scene& scene, uint32_t mesh);
std::string nodeName(const Scene& scene, uint32_t node);
std::string lightName(const Scene& scene, uint32_t light);

// The stream `semantic` of `mesh` as values the vertex shader sees: stored (normalised if so
// flagged) * dequantScale + dequantOffset (x, y, z; w as stored), missing components 0 (w 1).
// Plain encoding only. Errors: Input (no such stream when `required`, a size that disagrees
// with vertexCount, an invalid layout), Unsupported (an octahedral stream). An absent optional
// stream gives an empty vector.
TracerResult<std::vector<glm::dvec4>> decodeStream(const Scene& scene, uint32_t mesh,
                                                   VertexSemantic semantic, bool required);

// Index k of the mesh's index buffer (U16 or U32).
uint32_t readIndex(const Mesh& mesh, uint64_t k);

} // namespace pnb::reference::detail
