// Reading single values out of a mesh's vertex streams (little-endian, tightly packed; FORMAT.md
// "MESH"), for the animation rules and the CPU deformation. Blobs in a payload are 16-byte
// aligned, but a hand-built Scene's need not be, so values are copied out, never cast.
#pragma once

#include <cstring>

#include "pnb/chunks.h"

namespace pnb::detail {

inline const VertexStream* findStream(const Mesh& m, VertexSemantic s) {
    for (const VertexStream& v : m.streams)
        if (v.semantic == s) return &v;
    return nullptr;
}

// Float `index` of an F32 stream.
inline float streamFloat(const Blob& b, size_t index) {
    float f;
    std::memcpy(&f, b.data() + index * 4, 4);
    return f;
}

// Component `index` of a Joints0 stream (U8 or U16).
inline uint32_t streamJoint(const VertexStream& s, size_t index) {
    if (s.componentType == ComponentType::U8) return uint8_t(s.data[index]);
    return uint32_t(uint8_t(s.data[2 * index])) | uint32_t(uint8_t(s.data[2 * index + 1])) << 8;
}

} // namespace pnb::detail
