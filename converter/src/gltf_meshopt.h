// gltf_meshopt.h — EXT_meshopt_compression for the glTF importer (import_gltf.cpp). Internal.
//
// The extension stores a bufferView's bytes compressed in another buffer; the view itself lives
// in a "fallback" buffer that usually has no data at all (no uri, not the GLB BIN chunk).
// tinygltf 2.7 knows nothing of this: it would fail on such a buffer ("Invalid byteLength" in a
// GLB, a missing file in a .gltf). So the work is split around tinygltf's load:
//   1. planMeshopt(), on the JSON before tinygltf sees it: records every compressed bufferView
//      and replaces each fallback buffer by a 1-byte data-URI stub that tinygltf loads happily.
//   2. decodeMeshopt(), on the loaded buffers: gives each fallback buffer its declared size and
//      decodes every compressed bufferView into place with meshoptimizer's decoders. After that
//      the importer reads accessors exactly as for an uncompressed file.
// Decoded views that sit in a buffer with real data (gltfpack -cf) are decoded over it, as the
// extension asks of loaders that support it.
//
// Errors are sentences without the file name (the caller prefixes it); they name the bufferView
// or buffer at fault. Nothing is trusted: every range is checked against the bytes actually
// loaded before a decoder runs, and the strides and counts the decoders assert on are validated.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pnb::converter::gltf_meshopt {

enum class Mode : uint8_t { Attributes, Triangles, Indices };
enum class Filter : uint8_t { None, Octahedral, Quaternion, Exponential };

// One bufferView's EXT_meshopt_compression object, and where its decoded bytes go.
struct CompressedView {
    size_t view = 0;                             // the bufferView the decoded bytes fill
    size_t targetBuffer = 0;                     // bufferView.buffer
    uint64_t targetOffset = 0, targetLength = 0; // bufferView.byteOffset/byteLength
    size_t sourceBuffer = 0;                     // the extension's buffer ...
    uint64_t sourceOffset = 0, sourceLength = 0; // ... byteOffset and byteLength
    uint64_t byteStride = 0, count = 0;          // decoded element size and count
    Mode mode = Mode::Attributes;
    Filter filter = Filter::None;
};

struct MeshoptPlan {
    std::vector<CompressedView> views;
    std::vector<std::pair<size_t, uint64_t>> fallbackBuffers; // buffer index, declared byteLength

    bool empty() const { return views.empty() && fallbackBuffers.empty(); }
};

// Reads every bufferView's and buffer's EXT_meshopt_compression object from the parsed glTF
// JSON `doc` into `plan`, and rewrites each fallback buffer in `doc` as a 1-byte stub
// (`changed` is set when it does). Malformed extension objects are errors naming the bufferView
// or buffer. Objects the rest of the file does not describe well enough to check (a bufferView
// without an integer buffer, say) are left for tinygltf to reject.
std::optional<std::string> planMeshopt(nlohmann::json& doc, MeshoptPlan& plan, bool& changed);

// Resizes each fallback buffer in `buffers` (buffer i's loaded bytes) to its declared byteLength
// (zero-filled; their total must not exceed `maxFallbackBytes`) and decodes every compressed view
// into its target range. Fails on the first view whose ranges do not fit the loaded buffers or
// whose data does not decode (truncated or corrupt), naming it.
std::optional<std::string> decodeMeshopt(const MeshoptPlan& plan,
                                         const std::vector<std::vector<unsigned char>*>& buffers,
                                         uint64_t maxFallbackBytes);

} // namespace pnb::converter::gltf_meshopt
