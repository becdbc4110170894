#include "load/upload.h"

#include <algorithm>
#include <string>

#include "shared/deform_params.h" // PNB_DEFORM_ABSENT

namespace pnb::player {

namespace {

GLenum glComponent(ComponentType t) {
    constexpr GLenum k[] = {GL_FLOAT, GL_HALF_FLOAT, GL_BYTE, GL_UNSIGNED_BYTE,
                            GL_SHORT, GL_UNSIGNED_SHORT, GL_INT, GL_UNSIGNED_INT};
    return k[size_t(t)];
}

// interface.glsl's attribute locations; -1 for streams no shader reads.
int attributeLocation(VertexSemantic s) {
    switch (s) {
    case VertexSemantic::Position: return 0;
    case VertexSemantic::Normal: return 1;
    case VertexSemantic::Tangent: return 2;
    case VertexSemantic::TexCoord0: return 3;
    case VertexSemantic::TexCoord1: return 4;
    case VertexSemantic::Color0: return 5;
    default: return -1;
    }
}

uint64_t alignUp(uint64_t v, uint64_t a) { return (v + a - 1) / a * a; }

} // namespace

MeshLayout meshLayout(const Mesh& mesh) {
    MeshLayout l;
    for (const VertexStream& s : mesh.streams) {
        l.segments.push_back({l.size, s.data});
        l.size = alignUp(l.size + s.data.size(), 16);
    }
    l.indexOffset = l.size;
    l.segments.push_back({l.indexOffset, mesh.indices});
    l.size += mesh.indices.size();
    return l;
}

PlayResult<GpuMesh> uploadMesh(const Mesh& mesh, uint32_t index, bool withData) {
    GpuMesh m;
    const MeshLayout layout = meshLayout(mesh);
    const uint64_t size = layout.size;
    m.indexOffset = layout.indexOffset;
    m.buffer = createBuffer();
    glNamedBufferStorage(m.buffer.id(), GLsizeiptr(std::max<uint64_t>(size, 16)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    // Straight from the mapping: the driver's copy is the only one.
    if (withData)
        for (const MeshLayout::Segment& seg : layout.segments)
            glNamedBufferSubData(m.buffer.id(), GLintptr(seg.offset), GLsizeiptr(seg.bytes.size()), seg.bytes.data());
    m.bytes = size;

    m.vertexArray = createVertexArray();
    GLuint vao = m.vertexArray.id();
    for (size_t i = 0; i < mesh.streams.size(); ++i) {
        const VertexStream& s = mesh.streams[i];
        int location = attributeLocation(s.semantic);
        if (location < 0) continue;
        auto loc = GLuint(location);
        GLsizei stride = GLsizei(componentSizeBytes(s.componentType) * s.componentCount);
        glEnableVertexArrayAttrib(vao, loc);
        glVertexArrayAttribFormat(vao, loc, s.componentCount, glComponent(s.componentType),
                                  s.normalized ? GL_TRUE : GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, loc, loc);
        glVertexArrayVertexBuffer(vao, loc, m.buffer.id(), GLintptr(layout.segments[i].offset), stride);
        if (s.semantic == VertexSemantic::Position) {
            m.dequantScale = {s.dequantScale.x, s.dequantScale.y, s.dequantScale.z};
            m.dequantOffset = {s.dequantOffset.x, s.dequantOffset.y, s.dequantOffset.z};
        }
        if (s.semantic == VertexSemantic::Normal)
            m.octahedralNormals = s.encoding == VertexEncoding::Octahedral;
    }
    glVertexArrayElementBuffer(vao, m.buffer.id());
    m.indexType = mesh.indexType == IndexType::U16 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    m.indexSize = mesh.indexType == IndexType::U16 ? 2 : 4;
    constexpr GLenum kPrimitive[] = {GL_TRIANGLES, GL_LINES, GL_POINTS};
    m.primitive = kPrimitive[size_t(mesh.primitive)];
    m.submeshes = mesh.submeshes;
    std::string label = "mesh " + std::to_string(index);
    glObjectLabel(GL_BUFFER, m.buffer.id(), GLsizei(label.size()), label.c_str());
    return m;
}

PlayResult<GpuMesh> createPosedMesh(const Mesh& mesh, const GpuMesh& source, DeformedNode& d, uint32_t index) {
    GpuMesh m;
    const MeshLayout layout = meshLayout(mesh);
    auto words = [](uint64_t bytes) { return uint32_t(bytes / 4); };
    // The posed streams: positions, then normals and tangents where the mesh has them, each at a
    // 16-byte boundary.
    uint64_t size = alignUp(uint64_t(mesh.vertexCount) * 12, 16);
    uint64_t posedOffset[3] = {0, 0, 0};
    d.normal = d.tangent = d.joints = d.weights = PNB_DEFORM_ABSENT;
    d.posedNormal = d.posedTangent = PNB_DEFORM_ABSENT;
    for (size_t i = 0; i < mesh.streams.size(); ++i) {
        const VertexStream& s = mesh.streams[i];
        const uint32_t at = words(layout.segments[i].offset);
        switch (s.semantic) {
        case VertexSemantic::Position: d.position = at; break;
        case VertexSemantic::Normal:
            d.normal = at;
            posedOffset[1] = size;
            d.posedNormal = words(size);
            size = alignUp(size + uint64_t(mesh.vertexCount) * 12, 16);
            break;
        case VertexSemantic::Tangent:
            d.tangent = at;
            posedOffset[2] = size;
            d.posedTangent = words(size);
            size = alignUp(size + uint64_t(mesh.vertexCount) * 16, 16);
            break;
        case VertexSemantic::Joints0:
            d.joints = at;
            d.jointsU16 = s.componentType == ComponentType::U16;
            break;
        case VertexSemantic::Weights0: d.weights = at; break;
        default: break;
        }
    }
    d.vertexCount = mesh.vertexCount;
    d.posedBytes = size;
    m.buffer = createBuffer();
    glNamedBufferStorage(m.buffer.id(), GLsizeiptr(std::max<uint64_t>(size, 16)), nullptr, 0);
    // The stored (bind) pose until the deform pass first runs, and while anim.enabled is false.
    for (size_t i = 0; i < mesh.streams.size(); ++i) {
        const VertexStream& s = mesh.streams[i];
        const int moved = s.semantic == VertexSemantic::Position ? 0 : s.semantic == VertexSemantic::Normal ? 1
                          : s.semantic == VertexSemantic::Tangent ? 2 : -1;
        if (moved >= 0)
            glCopyNamedBufferSubData(source.buffer.id(), m.buffer.id(), GLintptr(layout.segments[i].offset),
                                     GLintptr(posedOffset[moved]), GLsizeiptr(s.data.size()));
    }
    m.bytes = size;
    m.vertexArray = createVertexArray();
    const GLuint vao = m.vertexArray.id();
    for (size_t i = 0; i < mesh.streams.size(); ++i) {
        const VertexStream& s = mesh.streams[i];
        const int location = attributeLocation(s.semantic);
        if (location < 0) continue;
        const auto loc = GLuint(location);
        const int moved = s.semantic == VertexSemantic::Position ? 0 : s.semantic == VertexSemantic::Normal ? 1
                          : s.semantic == VertexSemantic::Tangent ? 2 : -1;
        const GLsizei stride = GLsizei(componentSizeBytes(s.componentType) * s.componentCount);
        glEnableVertexArrayAttrib(vao, loc);
        glVertexArrayAttribFormat(vao, loc, s.componentCount, glComponent(s.componentType),
                                  s.normalized ? GL_TRUE : GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, loc, loc);
        if (moved >= 0) glVertexArrayVertexBuffer(vao, loc, m.buffer.id(), GLintptr(posedOffset[moved]), stride);
        else glVertexArrayVertexBuffer(vao, loc, source.buffer.id(), GLintptr(layout.segments[i].offset), stride);
    }
    glVertexArrayElementBuffer(vao, source.buffer.id());
    m.indexType = source.indexType;
    m.indexSize = source.indexSize;
    m.indexOffset = source.indexOffset;
    m.primitive = source.primitive;
    m.submeshes = source.submeshes;
    const std::string label = "posed mesh " + std::to_string(index) + " (node " + std::to_string(d.node) + ")";
    glObjectLabel(GL_BUFFER, m.buffer.id(), GLsizei(label.size()), label.c_str());
    return m;
}

} // namespace pnb::player
