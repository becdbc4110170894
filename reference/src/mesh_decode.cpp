// Container meshes as the GPU reads them (mesh_decode.h).
#include "mesh_decode.h"

#include <algorithm>
#include <cstring>

#include <glm/gtc/packing.hpp>

namespace pnb::reference::detail {

namespace {

TracerError inputError(std::string message) { return {TracerErrorKind::Input, std::move(message)}; }

// The string `ref` names, or "" (also for a reference past the table: names are only decoration).
std::string nameOf(const Scene& scene, StringRef ref) {
    return ref < scene.strings.strings.size() ? std::string(scene.strings.strings[ref]) : "";
}

template <class T> T load(const std::byte* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

// One stored component as the GPU's vertex fetch reads it (OpenGL 4.5 §10.3.7 / §2.3.5.1):
// normalised unsigned c / (2^b - 1), normalised signed max(c / (2^(b-1) - 1), -1).
double readComponent(const std::byte* p, ComponentType type, bool normalized) {
    switch (type) {
    case ComponentType::F32: return load<float>(p);
    case ComponentType::F16: return glm::unpackHalf1x16(load<uint16_t>(p));
    case ComponentType::I8: {
        double c = load<int8_t>(p);
        return normalized ? std::max(c / 127.0, -1.0) : c;
    }
    case ComponentType::U8: {
        double c = load<uint8_t>(p);
        return normalized ? c / 255.0 : c;
    }
    case ComponentType::I16: {
        double c = load<int16_t>(p);
        return normalized ? std::max(c / 32767.0, -1.0) : c;
    }
    case ComponentType::U16: {
        double c = load<uint16_t>(p);
        return normalized ? c / 65535.0 : c;
    }
    case ComponentType::I32: {
        double c = load<int32_t>(p);
        return normalized ? std::max(c / 2147483647.0, -1.0) : c;
    }
    case ComponentType::U32: {
        double c = load<uint32_t>(p);
        return normalized ? c / 4294967295.0 : c;
    }
    case ComponentType::Count: break;
    }
    return 0.0;
}

const char* semanticName(VertexSemantic s) {
    switch (s) {
    case VertexSemantic::Position: return "position";
    case VertexSemantic::Normal: return "normal";
    case VertexSemantic::TexCoord0: return "texcoord 0";
    case VertexSemantic::TexCoord1: return "texcoord 1";
    case VertexSemantic::Color0: return "colour";
    default: return "vertex";
    }
}

} // namespace

std::string meshName(const Scene& scene, uint32_t mesh) {
    std::string name = nameOf(scene, scene.meshes[mesh].name);
    return "mesh " + std::to_string(mesh) + (name.empty() ? "" : " '" + name + "'");
}

std::string nodeName(const Scene& scene, uint32_t node) {
    std::string name = nameOf(scene, scene.nodes.nodes[node].name);
    return "node " + std::to_string(node) + (name.empty() ? "" : " '" + name + "'");
}

std::string lightName(const Scene& scene, uint32_t light) {
    std::string name = nameOf(scene, scene.lights.lights[light].name);
    return "light " + std::to_string(light) + (name.empty() ? "" : " '" + name + "'");
}

// As FORMAT.md §4.3 specifies and the player's vertex shader applies (F32 Plain streams have
// scale 1, offset 0). Missing components read as 0 (w as 1), as GL's vertex fetch does.
TracerResult<std::vector<glm::dvec4>> decodeStream(const Scene& scene, uint32_t meshIndex,
                                                   VertexSemantic semantic, bool required) {
    const Mesh& mesh = fullDetailMesh(scene, meshIndex); // the MDET detail, not a proxy
    const VertexStream* stream = nullptr;
    for (const VertexStream& s : mesh.streams)
        if (s.semantic == semantic) {
            stream = &s;
            break;
        }
    const std::string what = meshName(scene, meshIndex) + ": the " + semanticName(semantic) + " stream";
    if (!stream) {
        if (!required) return std::vector<glm::dvec4>{};
        return inputError(meshName(scene, meshIndex) + " has triangles but no " + semanticName(semantic) + " stream");
    }
    const VertexStream& s = *stream;
    if (s.encoding != VertexEncoding::Plain)
        return TracerError{TracerErrorKind::Unsupported,
                           what + " is octahedral-encoded (a unit-vector encoding); it must be Plain"};
    if (s.componentType >= ComponentType::Count || s.componentCount < 1 || s.componentCount > 4)
        return inputError(what + " has an invalid layout");
    const uint64_t elementBytes = uint64_t(componentSizeBytes(s.componentType)) * s.componentCount;
    if (s.data.size() != elementBytes * mesh.vertexCount)
        return inputError(what + " holds " + std::to_string(s.data.size()) + " bytes, expected " +
                          std::to_string(elementBytes * mesh.vertexCount) + " (vertexCount " +
                          std::to_string(mesh.vertexCount) + ")");
    const double scale[3] = {s.dequantScale.x, s.dequantScale.y, s.dequantScale.z};
    const double offset[3] = {s.dequantOffset.x, s.dequantOffset.y, s.dequantOffset.z};
    const uint32_t componentBytes = componentSizeBytes(s.componentType);
    std::vector<glm::dvec4> out(mesh.vertexCount);
    for (uint32_t v = 0; v < mesh.vertexCount; ++v) {
        const std::byte* element = s.data.data() + uint64_t(v) * elementBytes;
        for (uint32_t c = 0; c < 4; ++c) {
            double stored = c < s.componentCount
                                ? readComponent(element + c * componentBytes, s.componentType, s.normalized)
                                : (c == 3 ? 1.0 : 0.0);
            out[v][int(c)] = c < 3 ? stored * scale[c] + offset[c] : stored;
        }
    }
    return out;
}

uint32_t readIndex(const Mesh& mesh, uint64_t k) {
    if (mesh.indexType == IndexType::U16) return load<uint16_t>(mesh.indices.data() + k * 2);
    return load<uint32_t>(mesh.indices.data() + k * 4);
}

} // namespace pnb::reference::detail
