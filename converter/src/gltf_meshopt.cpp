// gltf_meshopt.cpp — EXT_meshopt_compression: planning on the JSON, decoding into the loaded
// buffers (gltf_meshopt.h explains the split around tinygltf).
//
// Based on: the EXT_meshopt_compression specification (KhronosGroup/glTF, extensions/2.0/Vendor),
// whose constraints on byteStride, count and filter are the ones the meshoptimizer decoders
// assert on; they are checked here so that no file can reach those assertions.
#include "gltf_meshopt.h"

#include <cinttypes>

#include <meshoptimizer.h>

#include "gltf_internal.h"

namespace pnb::converter::gltf_meshopt {

namespace {

using namespace gltf_internal;

constexpr const char* kExtension = "EXT_meshopt_compression";
// The smallest buffer tinygltf accepts: its data-URI decoder refuses empty data.
constexpr const char* kStubUri = "data:application/octet-stream;base64,AA==";

const nlohmann::json* extensionOf(const nlohmann::json& o) {
    const nlohmann::json* ext = jsonMember(o, "extensions");
    const nlohmann::json* e = ext ? jsonMember(*ext, kExtension) : nullptr;
    return e && e->is_object() ? e : nullptr;
}

const char* modeName(Mode m) {
    switch (m) {
    case Mode::Attributes:
        return "ATTRIBUTES";
    case Mode::Triangles:
        return "TRIANGLES";
    case Mode::Indices:
        return "INDICES";
    }
    return "?";
}

std::optional<Mode> parseMode(const nlohmann::json* v) {
    if (!v || !v->is_string()) return std::nullopt;
    const std::string& s = v->get_ref<const std::string&>();
    if (s == "ATTRIBUTES") return Mode::Attributes;
    if (s == "TRIANGLES") return Mode::Triangles;
    if (s == "INDICES") return Mode::Indices;
    return std::nullopt;
}

std::optional<Filter> parseFilter(const nlohmann::json* v) {
    if (!v) return Filter::None; // the default
    if (!v->is_string()) return std::nullopt;
    const std::string& s = v->get_ref<const std::string&>();
    if (s == "NONE") return Filter::None;
    if (s == "OCTAHEDRAL") return Filter::Octahedral;
    if (s == "QUATERNION") return Filter::Quaternion;
    if (s == "EXPONENTIAL") return Filter::Exponential;
    return std::nullopt;
}

// The extension's rules for byteStride, count and filter; they are also the preconditions of
// meshopt_decodeVertexBuffer/IndexBuffer/IndexSequence and meshopt_decodeFilter*.
std::optional<std::string> checkShape(const CompressedView& c) {
    const uint64_t s = c.byteStride;
    switch (c.mode) {
    case Mode::Attributes:
        if (s == 0 || s > 256 || s % 4 != 0) {
            return strf("ATTRIBUTES byteStride %" PRIu64 " is not a multiple of 4 in 4..256", s);
        }
        break;
    case Mode::Triangles:
        if (c.count % 3 != 0) {
            return strf("TRIANGLES count %" PRIu64 " is not a multiple of 3", c.count);
        }
        [[fallthrough]];
    case Mode::Indices:
        if (s != 2 && s != 4) {
            return strf("%s byteStride %" PRIu64 " is not 2 or 4", modeName(c.mode), s);
        }
        break;
    }
    if (c.filter != Filter::None && c.mode != Mode::Attributes) {
        return strf("filters apply to ATTRIBUTES only, not %s", modeName(c.mode));
    }
    if (c.filter == Filter::Octahedral && s != 4 && s != 8) {
        return strf("OCTAHEDRAL needs byteStride 4 or 8, not %" PRIu64, s);
    }
    if (c.filter == Filter::Quaternion && s != 8) {
        return strf("QUATERNION needs byteStride 8, not %" PRIu64, s);
    }
    return std::nullopt; // EXPONENTIAL: any ATTRIBUTES stride (a multiple of 4) is valid
}

// Reads one bufferView's extension object. nullopt with an empty `error`: the bufferView itself
// is malformed, which tinygltf reports.
std::optional<CompressedView> parseView(size_t index, const nlohmann::json& bv,
                                        const nlohmann::json& ext, std::string& error) {
    const std::string who = strf("bufferView %zu: %s", index, kExtension);
    const std::optional<int> target = jsonInt(jsonMember(bv, "buffer"));
    const std::optional<uint64_t> targetLength = jsonUnsigned(jsonMember(bv, "byteLength"));
    if (!target || !targetLength) return std::nullopt;

    CompressedView c;
    c.view = index;
    c.targetOffset = jsonUnsigned(jsonMember(bv, "byteOffset")).value_or(0);
    c.targetLength = *targetLength;
    const std::optional<int> source = jsonInt(jsonMember(ext, "buffer"));
    const std::optional<uint64_t> sourceLength = jsonUnsigned(jsonMember(ext, "byteLength"));
    const std::optional<uint64_t> stride = jsonUnsigned(jsonMember(ext, "byteStride"));
    const std::optional<uint64_t> count = jsonUnsigned(jsonMember(ext, "count"));
    const std::optional<Mode> mode = parseMode(jsonMember(ext, "mode"));
    const std::optional<Filter> filter = parseFilter(jsonMember(ext, "filter"));
    if (!source || !sourceLength || !stride || !count || !mode) {
        error = who + ": needs integer buffer, byteLength, byteStride and count, and a mode of "
                      "ATTRIBUTES, TRIANGLES or INDICES";
        return std::nullopt;
    }
    if (!filter) {
        error = who + ": filter is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL";
        return std::nullopt;
    }
    if (*target < 0 || *source < 0) {
        error =
            strf("%s: buffer index %d is negative", who.c_str(), *target < 0 ? *target : *source);
        return std::nullopt;
    }
    c.targetBuffer = size_t(*target);
    c.sourceBuffer = size_t(*source);
    c.sourceOffset = jsonUnsigned(jsonMember(ext, "byteOffset")).value_or(0);
    c.sourceLength = *sourceLength;
    c.byteStride = *stride;
    c.count = *count;
    c.mode = *mode;
    c.filter = *filter;
    if (auto e = checkShape(c)) {
        error = who + ": " + *e;
        return std::nullopt;
    }
    return c;
}

// Whether [offset, offset + length) lies inside `size` bytes, without overflow.
bool inside(uint64_t offset, uint64_t length, uint64_t size) {
    return offset <= size && length <= size - offset;
}

std::optional<std::string> decodeView(const CompressedView& c,
                                      const std::vector<std::vector<unsigned char>*>& buffers) {
    const std::string who = strf("bufferView %zu: %s", c.view, kExtension);
    if (c.targetBuffer >= buffers.size() || c.sourceBuffer >= buffers.size()) {
        return strf("%s: buffer %zu does not exist (%zu buffers)", who.c_str(),
                    c.targetBuffer >= buffers.size() ? c.targetBuffer : c.sourceBuffer,
                    buffers.size());
    }
    std::vector<unsigned char>& target = *buffers[c.targetBuffer];
    const std::vector<unsigned char>& source = *buffers[c.sourceBuffer];
    if (!inside(c.targetOffset, c.targetLength, target.size())) {
        return strf("%s: the bufferView (byteOffset %" PRIu64 ", byteLength %" PRIu64
                    ") exceeds buffer %zu (%zu bytes)",
                    who.c_str(), c.targetOffset, c.targetLength, c.targetBuffer, target.size());
    }
    if (c.count > c.targetLength / c.byteStride) {
        return strf("%s: count %" PRIu64 " x byteStride %" PRIu64
                    " exceeds the bufferView's byteLength %" PRIu64,
                    who.c_str(), c.count, c.byteStride, c.targetLength);
    }
    if (!inside(c.sourceOffset, c.sourceLength, source.size())) {
        return strf("%s: compressed data (byteOffset %" PRIu64 ", byteLength %" PRIu64
                    ") exceeds buffer %zu (%zu bytes)",
                    who.c_str(), c.sourceOffset, c.sourceLength, c.sourceBuffer, source.size());
    }
    const uint64_t decodedBytes = c.count * c.byteStride;
    if (c.sourceBuffer == c.targetBuffer && c.sourceOffset < c.targetOffset + decodedBytes &&
        c.targetOffset < c.sourceOffset + c.sourceLength) {
        return who + ": the compressed data overlaps the bytes it decodes to";
    }

    unsigned char* dst = target.data() + c.targetOffset;
    const unsigned char* src = source.data() + c.sourceOffset;
    const size_t n = size_t(c.count), stride = size_t(c.byteStride),
                 srcSize = size_t(c.sourceLength);
    int rc = 0;
    switch (c.mode) {
    case Mode::Attributes:
        rc = meshopt_decodeVertexBuffer(dst, n, stride, src, srcSize);
        break;
    case Mode::Triangles:
        rc = meshopt_decodeIndexBuffer(dst, n, stride, src, srcSize);
        break;
    case Mode::Indices:
        rc = meshopt_decodeIndexSequence(dst, n, stride, src, srcSize);
        break;
    }
    if (rc != 0) {
        return strf("%s: %s data (buffer %zu, byteOffset %" PRIu64 ", byteLength %" PRIu64
                    ") is truncated or corrupt (meshoptimizer error %d)",
                    who.c_str(), modeName(c.mode), c.sourceBuffer, c.sourceOffset, c.sourceLength,
                    rc);
    }
    switch (c.filter) {
    case Filter::None:
        break;
    case Filter::Octahedral:
        meshopt_decodeFilterOct(dst, n, stride);
        break;
    case Filter::Quaternion:
        meshopt_decodeFilterQuat(dst, n, stride);
        break;
    case Filter::Exponential:
        meshopt_decodeFilterExp(dst, n, stride);
        break;
    }
    return std::nullopt;
}

} // namespace

std::optional<std::string> planMeshopt(nlohmann::json& doc, MeshoptPlan& plan, bool& changed) {
    if (!doc.is_object()) return std::nullopt;
    if (auto buffers = doc.find("buffers"); buffers != doc.end() && buffers->is_array()) {
        for (size_t i = 0; i < buffers->size(); ++i) {
            nlohmann::json& buffer = (*buffers)[i];
            const nlohmann::json* ext = extensionOf(buffer);
            const nlohmann::json* fallback = ext ? jsonMember(*ext, "fallback") : nullptr;
            if (!fallback || !fallback->is_boolean() || !fallback->get<bool>()) continue;
            const std::optional<uint64_t> length = jsonUnsigned(jsonMember(buffer, "byteLength"));
            if (!length) continue; // tinygltf rejects the buffer
            plan.fallbackBuffers.emplace_back(i, *length);
            // Its data, if any, is never read: the decoded views replace it.
            buffer["uri"] = kStubUri;
            buffer["byteLength"] = 1;
            changed = true;
        }
    }
    if (auto views = doc.find("bufferViews"); views != doc.end() && views->is_array()) {
        for (size_t i = 0; i < views->size(); ++i) {
            const nlohmann::json* ext = extensionOf((*views)[i]);
            if (!ext) continue;
            std::string error;
            std::optional<CompressedView> view = parseView(i, (*views)[i], *ext, error);
            if (!error.empty()) return error;
            if (view) plan.views.push_back(*view);
        }
    }
    return std::nullopt;
}

std::optional<std::string> decodeMeshopt(const MeshoptPlan& plan,
                                         const std::vector<std::vector<unsigned char>*>& buffers,
                                         uint64_t maxFallbackBytes) {
    uint64_t total = 0;
    for (const auto& [index, length] : plan.fallbackBuffers) {
        if (length > maxFallbackBytes - total) {
            return strf("buffer %zu: %s fallback buffers declare more than the importer's limit "
                        "of %" PRIu64 " bytes (this one: %" PRIu64 " bytes)",
                        index, kExtension, maxFallbackBytes, length);
        }
        total += length;
    }
    for (const auto& [index, length] : plan.fallbackBuffers) {
        if (index >= buffers.size()) continue; // planned from JSON tinygltf did not load
        buffers[index]->assign(size_t(length), 0);
    }
    for (const CompressedView& view : plan.views) {
        if (auto e = decodeView(view, buffers)) return e;
    }
    return std::nullopt;
}

} // namespace pnb::converter::gltf_meshopt
