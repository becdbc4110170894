// converter/src/import_gltf_accessors.cpp — the glTF importer's accessor reader: every byte
// taken from a buffer goes through here, bounds-checked (a file of its own so the meshes stage
// reads as geometry, not as byte arithmetic; import_gltf_internal.h has the interface).
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "import_gltf_internal.h"

namespace pnb::converter::gltf_internal {

namespace {

// What an accessor's data is and where, after validation: element i's bytes are
// base[i * stride, i * stride + elementSize), all inside a loaded buffer.
struct AccessorLayout {
    const tinygltf::Accessor* accessor = nullptr;
    size_t count = 0, componentSize = 0, elementSize = 0, stride = 0;
    int componentType = 0, components = 0;
    bool normalized = false;
    const uint8_t* base = nullptr; // null: no bufferView, so all zeros (plus sparse values)
};

} // namespace

std::string accessorWho(int index, const std::string& where) {
    return strf("accessor %d (%s)", index, where.c_str());
}

// The bytes of a bufferView, checked against the size of the buffer that was actually loaded.
Result<std::span<const uint8_t>, ConvertError> viewBytes(const Ctx& ctx, int view,
                                                         const std::string& who) {
    const tinygltf::Model& m = ctx.model;
    if (view < 0 || size_t(view) >= m.bufferViews.size()) {
        return ctx.fail(strf("%s: bufferView %d does not exist (%zu bufferViews)", who.c_str(),
                             view, m.bufferViews.size()));
    }
    const tinygltf::BufferView& bv = m.bufferViews[size_t(view)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= m.buffers.size()) {
        return ctx.fail(strf("%s: bufferView %d refers to buffer %d, which does not exist (%zu "
                             "buffers)",
                             who.c_str(), view, bv.buffer, m.buffers.size()));
    }
    const std::vector<unsigned char>& data = m.buffers[size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset) {
        return ctx.fail(strf("%s: bufferView %d (byteOffset %zu, byteLength %zu) exceeds buffer "
                             "%d (%zu bytes)",
                             who.c_str(), view, bv.byteOffset, bv.byteLength, bv.buffer,
                             data.size()));
    }
    return std::span<const uint8_t>(data.data() + bv.byteOffset, bv.byteLength);
}

namespace {

// Validates accessor `index` for one use (`where` names it: "mesh 'Cube' primitive 0 POSITION").
// `mat4`: a MAT4 accessor is allowed (inverse bind matrices: 16 components, which need no
// column padding whatever their component type, since each column is 4 components).
Result<AccessorLayout, ConvertError> layoutOf(const Ctx& ctx, int index, const std::string& where,
                                              bool forIndices, bool mat4 = false) {
    const tinygltf::Model& m = ctx.model;
    const std::string who = accessorWho(index, where);
    if (index < 0 || size_t(index) >= m.accessors.size()) {
        return ctx.fail(strf("%s: does not exist (%zu accessors)", who.c_str(),
                             m.accessors.size()));
    }
    const tinygltf::Accessor& a = m.accessors[size_t(index)];
    AccessorLayout l;
    l.accessor = &a;
    l.componentType = a.componentType;
    l.componentSize = componentSize(a.componentType);
    const bool allowed = forIndices
        ? (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
           a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        : (l.componentSize != 0 && a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    if (!allowed) {
        return ctx.fail(strf("%s: componentType %d is not allowed here", who.c_str(),
                             a.componentType));
    }
    l.components = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    if ((l.components < 1 || l.components > 4) && !(mat4 && l.components == 16)) {
        return ctx.fail(strf("%s: matrix types are not allowed here", who.c_str()));
    }
    if (a.count == 0) return ctx.fail(who + ": count is 0");
    if (a.count > std::numeric_limits<uint32_t>::max()) {
        return ctx.fail(strf("%s: count %zu does not fit 32-bit indices", who.c_str(), a.count));
    }
    l.count = a.count;
    l.normalized = a.normalized && !forIndices;
    l.elementSize = l.componentSize * size_t(l.components);
    l.stride = l.elementSize;
    if (a.bufferView < 0) return l; // all zeros unless sparse (glTF 2.0 §3.6.2.3)

    auto view = viewBytes(ctx, a.bufferView, who);
    if (!view) return view.error();
    const size_t declaredStride = m.bufferViews[size_t(a.bufferView)].byteStride;
    if (declaredStride != 0) {
        if (declaredStride < l.elementSize) {
            return ctx.fail(strf("%s: bufferView %d byteStride %zu is smaller than the element "
                                 "(%zu bytes)",
                                 who.c_str(), a.bufferView, declaredStride, l.elementSize));
        }
        l.stride = declaredStride;
    }
    // The last element ends at byteOffset + (count - 1) * stride + elementSize; checked without
    // overflow.
    const size_t size = view->size();
    const bool fits = a.byteOffset <= size && size - a.byteOffset >= l.elementSize &&
                      (l.count - 1) <= (size - a.byteOffset - l.elementSize) / l.stride;
    if (!fits) {
        return ctx.fail(strf("%s: byteOffset %zu + count %zu x stride %zu exceeds bufferView %d "
                             "(%zu bytes)",
                             who.c_str(), a.byteOffset, l.count, l.stride, a.bufferView, size));
    }
    l.base = view->data() + a.byteOffset;
    return l;
}

// Validates the accessor's sparse substitution and calls apply(element, valueBytes) for each
// entry. Sparse index and value arrays are tightly packed (glTF 2.0 §3.6.2.3).
template <class Apply>
Check applySparse(const Ctx& ctx, const AccessorLayout& l, const std::string& who, Apply apply) {
    const auto& s = l.accessor->sparse;
    if (!s.isSparse) return std::nullopt;
    if (s.count < 1 || size_t(s.count) > l.count) {
        return ctx.fail(strf("%s: sparse count %d is outside 1..%zu", who.c_str(), s.count,
                             l.count));
    }
    const int indexType = s.indices.componentType;
    const size_t indexSize = componentSize(indexType);
    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        return ctx.fail(strf("%s: sparse indices componentType %d is not allowed", who.c_str(),
                             indexType));
    }
    const size_t n = size_t(s.count);
    struct Part { const char* name; int view; int offset; size_t elementSize; };
    const Part parts[2] = {{"indices", s.indices.bufferView, s.indices.byteOffset, indexSize},
                           {"values", s.values.bufferView, s.values.byteOffset, l.elementSize}};
    const uint8_t* starts[2] = {};
    for (int i = 0; i < 2; ++i) {
        const Part& p = parts[i];
        const std::string partWho = who + " sparse " + p.name;
        auto view = viewBytes(ctx, p.view, partWho);
        if (!view) return view.error();
        // n <= accessor count <= 2^32 and elementSize <= 64, so n * elementSize cannot overflow.
        const size_t bytes = n * p.elementSize;
        if (p.offset < 0 || size_t(p.offset) > view->size() ||
            bytes > view->size() - size_t(p.offset)) {
            return ctx.fail(strf("%s: byteOffset %d + %zu x %zu bytes exceeds bufferView %d "
                                 "(%zu bytes)",
                                 partWho.c_str(), p.offset, n, p.elementSize, p.view,
                                 view->size()));
        }
        starts[i] = view->data() + p.offset;
    }
    for (size_t k = 0; k < n; ++k) {
        const double index = readComponent(starts[0] + k * indexSize, indexType);
        if (index >= double(l.count)) {
            return ctx.fail(strf("%s: sparse index %.0f (entry %zu) is out of range 0..%zu",
                                 who.c_str(), index, k, l.count - 1));
        }
        apply(size_t(index), starts[1] + k * l.elementSize);
    }
    return std::nullopt;
}

} // namespace

Check checkComponents(const Ctx& ctx, int components, const AttributeSpec& spec,
                      const std::string& who) {
    if (components >= spec.minComponents && components <= spec.maxComponents) return {};
    const std::string expected = spec.minComponents == spec.maxComponents
        ? typeName(spec.minComponents)
        : strf("%s..%s", typeName(spec.minComponents), typeName(spec.maxComponents));
    return ctx.fail(strf("%s: type %s, expected %s", who.c_str(), typeName(components),
                         expected.c_str()));
}

// The single entry point for attribute data: returns count x components floats.
Result<std::vector<float>, ConvertError> readFloats(const Ctx& ctx, int index,
                                                    const std::string& where,
                                                    const AttributeSpec& spec, int& components) {
    auto layout = layoutOf(ctx, index, where, false, spec.maxComponents == 16);
    if (!layout) return layout.error();
    const AccessorLayout& l = *layout;
    const std::string who = accessorWho(index, where);
    if (auto e = checkComponents(ctx, l.components, spec, who)) return *e;
    if (auto e = ctx.fits(uint64_t(l.count) * uint64_t(l.components) * sizeof(float), who)) {
        return *e;
    }
    const bool normalized =
        l.normalized || (spec.forceNormalized && l.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT);
    const size_t nc = size_t(l.components);
    std::vector<float> out(l.count * nc, 0.0f);
    auto decode = [&](size_t element, const uint8_t* src) {
        for (size_t c = 0; c < nc; ++c) {
            out[element * nc + c] = toFloat(readComponent(src + c * l.componentSize,
                                                          l.componentType),
                                            l.componentType, normalized);
        }
    };
    if (l.base) {
        for (size_t i = 0; i < l.count; ++i) decode(i, l.base + i * l.stride);
    }
    if (auto e = applySparse(ctx, l, who, decode)) return *e;
    components = l.components;
    return out;
}

Result<std::vector<uint32_t>, ConvertError> readIndices(const Ctx& ctx, int index,
                                                        const std::string& where) {
    auto layout = layoutOf(ctx, index, where, true);
    if (!layout) return layout.error();
    const AccessorLayout& l = *layout;
    const std::string who = accessorWho(index, where);
    if (l.components != 1) {
        return ctx.fail(strf("%s: type %s, expected SCALAR", who.c_str(), typeName(l.components)));
    }
    if (auto e = ctx.fits(uint64_t(l.count) * sizeof(uint32_t), who)) return *e;
    std::vector<uint32_t> out(l.count, 0);
    auto decode = [&](size_t element, const uint8_t* src) {
        out[element] = uint32_t(readComponent(src, l.componentType));
    };
    if (l.base) {
        for (size_t i = 0; i < l.count; ++i) decode(i, l.base + i * l.stride);
    }
    if (auto e = applySparse(ctx, l, who, decode)) return *e;
    return out;
}

} // namespace pnb::converter::gltf_internal
