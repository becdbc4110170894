// converter/src/import_gltf_meshes.cpp — glTF meshes into IR meshes: primitives as triangle
// lists, KHR_draco_mesh_compression decoded with draco (EXT_meshopt_compression is decoded
// earlier, into the buffers: gltf_meshopt.cpp). A stage of the glTF importer, separate from the
// document, materials and nodes stages (import_gltf_internal.h).
//
// Index: [SECTION] draco, [SECTION] meshes
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include "import_gltf_internal.h"

namespace pnb::converter::gltf_internal {

namespace {

// [SECTION] draco

struct DracoMesh {
    std::unique_ptr<draco::Mesh> mesh;
    const tinygltf::Value* attributes = nullptr; // semantic → Draco unique id
};

// Decodes a primitive's KHR_draco_mesh_compression bufferView.
Result<DracoMesh, ConvertError> decodeDraco(const Ctx& ctx, const tinygltf::Value& ext,
                                            const std::string& where) {
    const std::string who = where + " KHR_draco_mesh_compression";
    const std::optional<int> view = intOf(member(&ext, "bufferView"));
    const tinygltf::Value* attributes = member(&ext, "attributes");
    if (!view || !attributes || !attributes->IsObject()) {
        return ctx.fail(who + ": needs an integer bufferView and an attributes object");
    }
    auto bytes = viewBytes(ctx, *view, who);
    if (!bytes) return bytes.error();
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes->data()), bytes->size());
    auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok() || type.value() != draco::TRIANGULAR_MESH) {
        return ctx.fail(who + ": bufferView " + std::to_string(*view) +
                        " is not a Draco triangle mesh");
    }
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) {
        return ctx.fail(who + ": Draco decoding failed: " + decoded.status().error_msg_string());
    }
    DracoMesh out;
    out.mesh = std::move(decoded).value();
    out.attributes = attributes;
    if (!out.mesh) return ctx.fail(who + ": Draco decoding failed");
    return out;
}

// A decoded Draco attribute as floats. The accessor (`index`) describes the decoded data: its
// type, component type and normalized flag. We apply that flag ourselves instead of Draco's
// own, which encoders don't always set.
Result<std::vector<float>, ConvertError> readDracoFloats(Ctx& ctx, const DracoMesh& draco,
                                                         int dracoId, int index,
                                                         const std::string& where,
                                                         const AttributeSpec& spec,
                                                         int& components) {
    const std::string who = accessorWho(index, where);
    if (index < 0 || size_t(index) >= ctx.model.accessors.size()) {
        return ctx.fail(strf("%s: does not exist (%zu accessors)", who.c_str(),
                             ctx.model.accessors.size()));
    }
    const tinygltf::Accessor& a = ctx.model.accessors[size_t(index)];
    const int nc = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    if (auto e = checkComponents(ctx, nc, spec, who)) return *e;
    if (componentSize(a.componentType) == 0 ||
        a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        return ctx.fail(strf("%s: componentType %d is not allowed here", who.c_str(),
                             a.componentType));
    }
    const draco::PointAttribute* att =
        dracoId < 0 ? nullptr : draco.mesh->GetAttributeByUniqueId(uint32_t(dracoId));
    if (!att) return ctx.fail(strf("%s: Draco attribute %d does not exist", who.c_str(), dracoId));
    if (att->num_components() != nc) {
        return ctx.fail(strf("%s: Draco attribute %d has %d components, the accessor is %s",
                             who.c_str(), dracoId, int(att->num_components()), typeName(nc)));
    }
    const size_t n = draco.mesh->num_points();
    if (n == 0) return ctx.fail(who + ": the Draco mesh has no points");
    if (!att->is_mapping_identity() && att->indices_map_size() < n) {
        return ctx.fail(strf("%s: Draco attribute %d maps fewer points than the mesh has",
                             who.c_str(), dracoId));
    }
    if (auto e = ctx.fits(uint64_t(n) * uint64_t(nc) * sizeof(float), who)) return *e;
    const bool isFloat = att->data_type() == draco::DT_FLOAT32 ||
                         att->data_type() == draco::DT_FLOAT64;
    const bool normalized =
        a.normalized || (spec.forceNormalized && a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT);
    std::vector<float> out(n * size_t(nc));
    for (size_t p = 0; p < n; ++p) {
        const draco::AttributeValueIndex value = att->mapped_index(draco::PointIndex(uint32_t(p)));
        bool ok = value.value() < att->size();
        float* dst = out.data() + p * size_t(nc);
        if (ok && isFloat) {
            ok = att->ConvertValue<float>(value, int8_t(nc), dst);
        } else if (ok) {
            int64_t raw[4] = {};
            ok = att->ConvertValue<int64_t>(value, int8_t(nc), raw);
            for (int c = 0; ok && c < nc; ++c) {
                dst[c] = toFloat(double(raw[c]), a.componentType, normalized);
            }
        }
        if (!ok) {
            return ctx.fail(strf("%s: Draco attribute %d: value of point %zu is unreadable",
                                 who.c_str(), dracoId, p));
        }
    }
    if (a.count != n) {
        // The decoded data is the truth; the accessor's count is only a declaration.
        ctx.warn(strf("%s: count %zu, Draco decoded %zu points", who.c_str(), a.count, n));
    }
    components = nc;
    return out;
}

Result<std::vector<uint32_t>, ConvertError> readDracoIndices(const Ctx& ctx, const DracoMesh& draco,
                                                             const std::string& where) {
    const draco::Mesh& mesh = *draco.mesh;
    const size_t faces = mesh.num_faces();
    if (auto e = ctx.fits(uint64_t(faces) * 3 * sizeof(uint32_t), where)) return *e;
    std::vector<uint32_t> out;
    out.reserve(faces * 3);
    for (uint32_t f = 0; f < faces; ++f) {
        for (const draco::PointIndex& p : mesh.face(draco::FaceIndex(f))) out.push_back(p.value());
    }
    return out; // range-checked by the caller, like every other index source
}

// [SECTION] meshes

// glTF 2.0 §3.7.2.1: strips and fans, in the winding the specification gives.
Result<std::vector<uint32_t>, ConvertError> triangulate(Ctx& ctx, std::vector<uint32_t> in,
                                                        int mode, const std::string& where) {
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (size_t extra = in.size() % 3) {
            ctx.warn(strf("%s: %zu indices are not a multiple of 3; the last %zu are dropped",
                          where.c_str(), in.size(), extra));
            in.resize(in.size() - extra);
        }
        return in;
    }
    std::vector<uint32_t> out;
    if (in.size() < 3) return out;
    const size_t triangles = in.size() - 2;
    if (auto e = ctx.fits(uint64_t(triangles) * 3 * sizeof(uint32_t), where)) return *e;
    out.reserve(triangles * 3);
    for (size_t i = 0; i < triangles; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            const bool odd = i % 2 != 0;
            out.insert(out.end(), {in[i], in[i + (odd ? 2 : 1)], in[i + (odd ? 1 : 2)]});
        } else { // TRIANGLE_FAN
            out.insert(out.end(), {in[i + 1], in[i + 2], in[0]});
        }
    }
    return out;
}

// Drops the vertices no triangle uses, keeping the order of the others.
void compactVertices(IrPrimitive& p) {
    const size_t n = p.vertexCount();
    std::vector<uint32_t> remap(n, 0);
    for (uint32_t i : p.indices) remap[i] = 1;
    uint32_t used = 0;
    for (uint32_t& r : remap) r = r ? used++ : std::numeric_limits<uint32_t>::max();
    if (used == n) return;
    auto compact = [&](std::vector<float>& stream, size_t nc) {
        if (stream.empty()) return;
        for (size_t v = 0; v < n; ++v) {
            if (remap[v] != std::numeric_limits<uint32_t>::max()) {
                std::copy_n(stream.begin() + std::ptrdiff_t(v * nc), nc,
                            stream.begin() + std::ptrdiff_t(size_t(remap[v]) * nc));
            }
        }
        stream.resize(size_t(used) * nc);
        stream.shrink_to_fit();
    };
    compact(p.positions, 3);
    compact(p.normals, 3);
    compact(p.tangents, 4);
    compact(p.uv0, 2);
    compact(p.uv1, 2);
    compact(p.colors, 4);
    compact(p.weights, 4);
    for (IrMorphTarget& t : p.targets) {
        compact(t.positions, 3);
        compact(t.normals, 3);
        compact(t.tangents, 3);
    }
    if (!p.joints.empty()) {
        for (size_t v = 0; v < n; ++v)
            if (remap[v] != std::numeric_limits<uint32_t>::max())
                std::copy_n(p.joints.begin() + std::ptrdiff_t(v * 4), 4,
                            p.joints.begin() + std::ptrdiff_t(size_t(remap[v]) * 4));
        p.joints.resize(size_t(used) * 4);
        p.joints.shrink_to_fit();
    }
    for (uint32_t& i : p.indices) i = remap[i];
}

uint64_t sizeBytes(const IrPrimitive& p) {
    const size_t floats = p.positions.size() + p.normals.size() + p.tangents.size() +
                          p.uv0.size() + p.uv1.size() + p.colors.size() + p.weights.size() +
                          p.joints.size();
    size_t deltas = 0;
    for (const IrMorphTarget& t : p.targets)
        deltas += t.positions.size() + t.normals.size() + t.tangents.size();
    return uint64_t(floats + deltas) * sizeof(float) +
           uint64_t(p.indices.size()) * sizeof(uint32_t);
}


// The primitive's morph targets as per-vertex deltas (glTF 2.0 §3.7.2.2: attribute = base + sum
// of weight_i x target_i). Only POSITION, NORMAL and TANGENT (xyz) are morphed, as the
// specification defines; a delta of an attribute the primitive lacks is not read (nothing to
// move). The weights are the mesh's (importMesh).
Check readMorphTargets(Ctx& ctx, const tinygltf::Primitive& src, IrPrimitive& p,
                       const std::string& where) {
    struct Morphed { const char* semantic; const std::vector<float>* base; size_t target; };
    const size_t n = p.vertexCount();
    p.targets.resize(src.targets.size());
    for (size_t t = 0; t < src.targets.size(); ++t) {
        IrMorphTarget& out = p.targets[t];
        const Morphed morphed[] = {{"POSITION", &p.positions, 0}, {"NORMAL", &p.normals, 1},
                                   {"TANGENT", &p.tangents, 2}};
        for (const Morphed& m : morphed) {
            auto it = src.targets[t].find(m.semantic);
            if (it == src.targets[t].end() || m.base->empty()) continue;
            const std::string who = strf("%s morph target %zu %s", where.c_str(), t, m.semantic);
            int components = 0;
            auto delta = readFloats(ctx, it->second, who, {3, 3, false}, components);
            if (!delta) return delta.error();
            if (delta->size() != n * 3) {
                return ctx.fail(strf("%s: count %zu differs from POSITION's %zu",
                                     accessorWho(it->second, who).c_str(), delta->size() / 3, n));
            }
            for (float& d : *delta)
                if (!std::isfinite(d))
                    return ctx.fail(strf("%s: a delta is not finite",
                                         accessorWho(it->second, who).c_str()));
            std::vector<float>& dst = m.target == 0 ? out.positions : m.target == 1 ? out.normals : out.tangents;
            dst = std::move(delta).value();
        }
    }
    return std::nullopt;
}

// JOINTS_0 and WEIGHTS_0 of a primitive a skinned node draws: integer joint indices (checked
// against the skin's joint count by the node, which knows the skin) and the weights as given.
// A primitive without them gets joint 0 at weight 0, which mesh processing turns into weight 1
// on joint 0 (counted in its warning).
Check readSkinAttributes(Ctx& ctx, const tinygltf::Primitive& src, IrPrimitive& p,
                         const std::string& where) {
    const size_t n = p.vertexCount();
    auto joints = src.attributes.find("JOINTS_0");
    auto weights = src.attributes.find("WEIGHTS_0");
    if (joints == src.attributes.end() || weights == src.attributes.end()) {
        p.joints.assign(n * 4, 0);
        p.weights.assign(n * 4, 0.0f);
        return std::nullopt;
    }
    const std::string jointsWhere = where + " JOINTS_0", weightsWhere = where + " WEIGHTS_0";
    const tinygltf::Accessor* ja = joints->second >= 0 && size_t(joints->second) < ctx.model.accessors.size()
                                       ? &ctx.model.accessors[size_t(joints->second)] : nullptr;
    if (ja && (ja->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
               ja->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT))
        return ctx.fail(strf("%s: component type %d, JOINTS_0 must be unsigned byte or short",
                             accessorWho(joints->second, jointsWhere).c_str(), ja->componentType));
    int components = 0;
    auto j = readFloats(ctx, joints->second, jointsWhere, {4, 4, false}, components);
    if (!j) return j.error();
    if (j->size() != n * 4)
        return ctx.fail(strf("%s: count %zu differs from POSITION's %zu",
                             accessorWho(joints->second, jointsWhere).c_str(), j->size() / 4, n));
    auto w = readFloats(ctx, weights->second, weightsWhere, {4, 4, false}, components);
    if (!w) return w.error();
    if (w->size() != n * 4)
        return ctx.fail(strf("%s: count %zu differs from POSITION's %zu",
                             accessorWho(weights->second, weightsWhere).c_str(), w->size() / 4, n));
    p.joints.resize(n * 4);
    for (size_t k = 0; k < j->size(); ++k) p.joints[k] = uint32_t((*j)[k]); // exact: u8/u16
    p.weights = std::move(w).value();
    return std::nullopt;
}

// One primitive as a triangle list, or nullopt when it is dropped (with a warning), with its
// morph targets' deltas, and its joints and weights when a skinned node draws it.
Result<std::optional<IrPrimitive>, ConvertError> importPrimitive(Ctx& ctx, int meshIndex,
                                                                 int primIndex, bool skinned) {
    const tinygltf::Primitive& src =
        ctx.model.meshes[size_t(meshIndex)].primitives[size_t(primIndex)];
    const std::string where =
        strf("%s primitive %d", label("mesh", meshIndex, ctx.model.meshes).c_str(), primIndex);
    const int mode = src.mode;
    if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN) {
        return ctx.fail(strf("%s: mode %d is not a glTF primitive mode", where.c_str(), mode));
    }
    if (mode < TINYGLTF_MODE_TRIANGLES) {
        ctx.scene.noteNotRendered(mode == TINYGLTF_MODE_POINTS ? "points" : "lines", 1,
                                  "primitives", "dropped: only triangles are drawn");
        return std::optional<IrPrimitive>();
    }
    auto position = src.attributes.find("POSITION");
    if (position == src.attributes.end()) {
        ctx.warn(where + ": no POSITION attribute; dropped");
        return std::optional<IrPrimitive>();
    }

    std::optional<DracoMesh> draco;
    if (const tinygltf::Value* ext =
            extensionObject(src.extensions, "KHR_draco_mesh_compression")) {
        auto decoded = decodeDraco(ctx, *ext, where);
        if (!decoded) return decoded.error();
        draco = std::move(decoded).value();
    }

    struct Stream { const char* semantic; std::vector<float>* out; AttributeSpec spec; };
    IrPrimitive p;
    const Stream streams[] = {
        {"POSITION", &p.positions, {3, 3, false}},  {"NORMAL", &p.normals, {3, 3, false}},
        {"TANGENT", &p.tangents, {4, 4, false}},    {"TEXCOORD_0", &p.uv0, {2, 2, false}},
        {"TEXCOORD_1", &p.uv1, {2, 2, false}},      {"COLOR_0", &p.colors, {3, 4, true}},
    };
    for (const auto& attribute : src.attributes) {
        // A named reference, not a structured binding: clang 14 cannot capture bindings.
        const std::string& semantic = attribute.first;
        const bool known = std::any_of(std::begin(streams), std::end(streams),
                                       [&](const Stream& s) { return semantic == s.semantic; });
        // JOINTS_0/WEIGHTS_0 are read when a skinned node draws the mesh (readSkinAttributes),
        // and ignored silently otherwise, as the specification says of an unskinned node.
        const bool skinning = semantic == "JOINTS_0" || semantic == "WEIGHTS_0";
        if (!known && !skinning)
            ctx.warn(where + ": attribute " + semantic + " ignored" +
                     (semantic.rfind("JOINTS_", 0) == 0 || semantic.rfind("WEIGHTS_", 0) == 0
                          ? " (4 joint influences per vertex: JOINTS_0/WEIGHTS_0)"
                          : ""));
    }
    size_t vertexCount = 0;
    for (const Stream& s : streams) { // POSITION first: it sets the vertex count
        auto it = src.attributes.find(s.semantic);
        if (it == src.attributes.end()) continue;
        const std::string attrWhere = where + " " + s.semantic;
        const std::optional<int> dracoId =
            draco ? intOf(member(draco->attributes, s.semantic)) : std::nullopt;
        int components = 0;
        auto data = dracoId
            ? readDracoFloats(ctx, *draco, *dracoId, it->second, attrWhere, s.spec, components)
            : readFloats(ctx, it->second, attrWhere, s.spec, components);
        if (!data) return data.error();
        const size_t count = data->size() / size_t(components);
        if (s.out == &p.positions) {
            vertexCount = count;
        } else if (count != vertexCount) {
            return ctx.fail(strf("%s: count %zu differs from POSITION's %zu",
                                 accessorWho(it->second, attrWhere).c_str(), count,
                                 vertexCount));
        }
        *s.out = std::move(data).value();
        if (s.out == &p.colors && components == 3) { // rgb → rgba, opaque
            std::vector<float> rgba(vertexCount * 4, 1.0f);
            for (size_t v = 0; v < vertexCount; ++v) {
                std::copy_n(p.colors.begin() + std::ptrdiff_t(v * 3), 3,
                            rgba.begin() + std::ptrdiff_t(v * 4));
            }
            p.colors = std::move(rgba);
        }
    }

    // Draco's decoded faces are a triangle list whatever the mode says (the extension allows
    // TRIANGLES and TRIANGLE_STRIP and decodes both to faces).
    std::vector<uint32_t> indices;
    int indexMode = mode;
    if (draco || src.indices >= 0) {
        const std::string indicesWho = draco
            ? where + " KHR_draco_mesh_compression"
            : accessorWho(src.indices, where + " indices");
        auto read = draco ? readDracoIndices(ctx, *draco, indicesWho)
                          : readIndices(ctx, src.indices, where + " indices");
        if (!read) return read.error();
        indices = std::move(read).value();
        for (size_t i = 0; i < indices.size(); ++i) {
            if (indices[i] >= vertexCount) {
                return ctx.fail(strf("%s: index %u (element %zu) is out of range 0..%zu",
                                     indicesWho.c_str(), indices[i], i, vertexCount - 1));
            }
        }
        if (draco) indexMode = TINYGLTF_MODE_TRIANGLES;
    } else {
        if (auto e = ctx.fits(uint64_t(vertexCount) * sizeof(uint32_t), where)) return *e;
        indices.resize(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i) indices[i] = uint32_t(i);
    }
    if (!src.targets.empty()) {
        if (draco) {
            ctx.warn(strf("%s: %zu morph targets of a Draco-compressed primitive ignored",
                          where.c_str(), src.targets.size()));
        } else if (auto e = readMorphTargets(ctx, src, p, where)) {
            return *e;
        }
    }
    if (skinned)
        if (auto e = readSkinAttributes(ctx, src, p, where)) return *e;
    auto triangles = triangulate(ctx, std::move(indices), indexMode, where);
    if (!triangles) return triangles.error();
    p.indices = std::move(triangles).value();
    if (p.indices.empty()) {
        ctx.warn(where + ": no triangles; dropped");
        return std::optional<IrPrimitive>();
    }
    compactVertices(p);

    if (src.material >= 0) {
        auto material = importMaterial(ctx, src.material, where);
        if (!material) return material.error();
        p.material = *material;
    }
    const uint64_t bytes = sizeBytes(p);
    if (auto e = ctx.fits(bytes, where)) return *e;
    ctx.retainedBytes += bytes;
    return std::optional<IrPrimitive>(std::move(p));
}

} // namespace

Result<int, ConvertError> importMesh(Ctx& ctx, int index, const std::vector<double>& nodeWeights,
                                     bool skinned, const std::string& who) {
    if (index < 0 || size_t(index) >= ctx.model.meshes.size()) {
        return ctx.fail(strf("%s: mesh %d does not exist (%zu meshes)", who.c_str(), index,
                             ctx.model.meshes.size()));
    }
    const tinygltf::Mesh& src = ctx.model.meshes[size_t(index)];
    // A node's own morph weights override the mesh's; such a node gets a mesh of its own whose
    // default weights are the node's, every other node shares the mesh at its default weights.
    // A skinned node and an unskinned one drawing the same mesh get a copy each: only the
    // skinned copy carries joints and weights and is deformed (docs/CONVERTER.md).
    const bool ownWeights = !nodeWeights.empty() && nodeWeights != src.weights;
    std::vector<int>& memo = skinned ? ctx.skinnedMeshMap : ctx.meshMap;
    if (!ownWeights && memo[size_t(index)] != -1) return memo[size_t(index)];
    const std::vector<double>& weights = ownWeights ? nodeWeights : src.weights;
    const std::string meshWho = label("mesh", index, ctx.model.meshes);
    IrMesh mesh;
    mesh.name = src.name;
    mesh.skinned = skinned;
    if (src.primitives.empty()) {
        ctx.warn(meshWho + ": no primitives");
    }
    size_t targets = 0;
    for (size_t i = 0; i < src.primitives.size(); ++i) {
        auto p = importPrimitive(ctx, index, int(i), skinned);
        if (!p) return p.error();
        if (p->has_value()) {
            targets = std::max(targets, (**p).targets.size());
            mesh.primitives.push_back(std::move(**p));
        }
    }
    if (targets > kMaxMorphTargets)
        return ctx.fail(strf("%s: %zu morph targets, at most %u are supported", meshWho.c_str(),
                             targets, kMaxMorphTargets));
    if (targets > 0) {
        if (weights.size() != targets)
            ctx.warn(strf("%s: %zu morph weights for %zu targets; the missing weights are 0%s",
                          (ownWeights ? who : meshWho).c_str(), weights.size(), targets,
                          weights.size() > targets ? ", the extra ones ignored" : ""));
        mesh.morphWeights.assign(targets, 0.0f);
        for (size_t t = 0; t < targets && t < weights.size(); ++t)
            mesh.morphWeights[t] = std::isfinite(weights[t]) ? float(weights[t]) : 0.0f;
        for (IrPrimitive& p : mesh.primitives) {
            if (p.targets.size() != targets && !p.targets.empty())
                ctx.warn(strf("%s: a primitive has %zu morph targets, another %zu; the missing "
                              "ones do not move it", meshWho.c_str(), p.targets.size(), targets));
            p.targets.resize(targets);
        }
        // glTF's customary names: mesh.extras.targetNames.
        if (src.extras.IsObject() && src.extras.Has("targetNames")) {
            const tinygltf::Value& names = src.extras.Get("targetNames");
            if (names.IsArray() && names.ArrayLen() == targets)
                for (size_t t = 0; t < targets; ++t)
                    mesh.targetNames.push_back(names.Get(int(t)).IsString()
                                                   ? names.Get(int(t)).Get<std::string>() : "");
        }
    }
    // An IR mesh is kept even when empty, so a node that names it stays valid.
    ctx.scene.meshes.push_back(std::move(mesh));
    const int imported = int(ctx.scene.meshes.size() - 1);
    if (!ownWeights) memo[size_t(index)] = imported;
    return imported;
}

} // namespace pnb::converter::gltf_internal
