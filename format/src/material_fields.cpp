#include "pnb/material_fields.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <vector>

namespace pnb {

namespace {

// Accessors of the rows below: where a field of each kind lives in a Material.
template <auto member> MaterialFieldSlot number(Material& m) { return {.floats = &(m.*member)}; }
template <auto member> MaterialFieldSlot color(Material& m) { return {.floats = &(m.*member).x}; }
template <auto member> MaterialFieldSlot flag(Material& m) { return {.flag = &(m.*member)}; }
template <auto member> MaterialFieldSlot choice(Material& m) {
    static_assert(sizeof(m.*member) == 1, "a Choice field is a one-byte enum");
    return {.choice = reinterpret_cast<uint8_t*>(&(m.*member))};
}
template <auto member> MaterialFieldSlot integer(Material& m) { return {.integer = &(m.*member)}; }
template <TextureSlotKind kind> MaterialFieldSlot texture(Material& m) {
    return {.texture = &m.textures[size_t(kind)].texture};
}

using M = Material;
using T = TextureSlotKind;
constexpr MaterialField kFields[] = {
    {"base_color", FieldType::Color4, 0, 1, nullptr, "linear RGBA multiplier of the base colour",
     color<&M::baseColorFactor>},
    {"emissive", FieldType::Color3, 0, 1, nullptr, "linear RGB emitted colour", color<&M::emissiveFactor>},
    {"emissive_strength", FieldType::Float, 0, 10000, nullptr, "scale of the emissive colour",
     number<&M::emissiveStrength>},
    {"metallic", FieldType::Float, 0, 1, nullptr, "0 = dielectric, 1 = metal", number<&M::metallicFactor>},
    {"roughness", FieldType::Float, 0, 1, nullptr, "perceptual roughness", number<&M::roughnessFactor>},
    {"normal_scale", FieldType::Float, 0, 10, nullptr, "strength of the normal map", number<&M::normalScale>},
    {"occlusion_strength", FieldType::Float, 0, 1, nullptr, "strength of the occlusion map",
     number<&M::occlusionStrength>},
    {"alpha_mode", FieldType::Choice, 0, 0, "opaque|mask|blend", "how alpha is used", choice<&M::alphaMode>},
    {"alpha_cutoff", FieldType::Float, 0, 1, nullptr, "mask threshold (alpha_mode = mask)",
     number<&M::alphaCutoff>},
    {"shading_path", FieldType::Choice, 0, 0, "deferred|forward", "pipeline placement",
     choice<&M::shadingPath>},
    {"layer_priority", FieldType::Integer, 0, 65535, nullptr, "deferred layer order, ascending",
     integer<&M::layerPriority>},
    {"double_sided", FieldType::Bool, 0, 0, nullptr, "render back faces", flag<&M::doubleSided>},
    {"casts_shadows", FieldType::Bool, 0, 0, nullptr, "drawn into shadow maps", flag<&M::castsShadows>},
    {"receives_shadows", FieldType::Bool, 0, 0, nullptr, "shadowed when lit", flag<&M::receivesShadows>},
    {"unlit", FieldType::Bool, 0, 0, nullptr, "base colour as is, no lighting (KHR_materials_unlit)",
     flag<&M::unlit>},
    {"base_color_texture", FieldType::TextureRef, 0, 0, nullptr, "texture index or none",
     texture<T::BaseColor>},
    {"metallic_roughness_texture", FieldType::TextureRef, 0, 0, nullptr, "texture index or none",
     texture<T::MetallicRoughness>},
    {"normal_texture", FieldType::TextureRef, 0, 0, nullptr, "texture index or none", texture<T::Normal>},
    {"occlusion_texture", FieldType::TextureRef, 0, 0, nullptr, "texture index or none",
     texture<T::Occlusion>},
    {"emissive_texture", FieldType::TextureRef, 0, 0, nullptr, "texture index or none",
     texture<T::Emissive>},
};

std::vector<std::string_view> split(std::string_view s, char sep) {
    std::vector<std::string_view> parts;
    size_t start = 0;
    while (true) {
        size_t at = s.find(sep, start);
        parts.push_back(s.substr(start, at == std::string_view::npos ? at : at - start));
        if (at == std::string_view::npos) return parts;
        start = at + 1;
    }
}

bool parseFloat(std::string_view s, float& out) {
    auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(out);
}

Error invalid(const MaterialField& f, std::string_view value, const std::string& expected) {
    return makeError(FormatError::BadReference, 0, "%s = '%.*s' is invalid: expected %s",
                     f.name, int(value.size()), value.data(), expected.c_str());
}

std::string rangeText(const MaterialField& f, const char* what) {
    char buf[96];
    std::snprintf(buf, sizeof(buf), "%s in [%g, %g]", what, f.min, f.max);
    return buf;
}

} // namespace

std::span<const MaterialField> materialFields() { return kFields; }

Status setMaterialField(Material& material, std::string_view field, std::string_view value) {
    size_t index = 0;
    while (index < std::size(kFields) && field != kFields[index].name) ++index;
    if (index == std::size(kFields)) {
        std::string names;
        for (const MaterialField& f : kFields) names += std::string(names.empty() ? "" : ", ") + f.name;
        return makeError(FormatError::BadReference, 0, "unknown material field '%.*s'; fields: %s",
                         int(field.size()), field.data(), names.c_str());
    }
    const MaterialField& f = kFields[index];
    Material edited = material;
    MaterialFieldSlot slot = f.slot(edited);
    switch (f.type) {
    case FieldType::Float:
    case FieldType::Color3:
    case FieldType::Color4: {
        size_t n = f.type == FieldType::Float ? 1 : f.type == FieldType::Color3 ? 3 : 4;
        auto parts = split(value, ',');
        if (parts.size() != n)
            return invalid(f, value, rangeText(f, n == 1 ? "a number" : n == 3 ? "r,g,b" : "r,g,b,a"));
        for (size_t i = 0; i < n; ++i) {
            float v = 0;
            if (!parseFloat(parts[i], v) || v < f.min || v > f.max)
                return invalid(f, value, rangeText(f, n == 1 ? "a number" : "components"));
            slot.floats[i] = v; // Vec3/Vec4 components are consecutive floats
        }
        break;
    }
    case FieldType::Bool:
        if (value == "true") *slot.flag = true;
        else if (value == "false") *slot.flag = false;
        else return invalid(f, value, "true or false");
        break;
    case FieldType::Choice: {
        auto choices = split(f.choices, '|');
        size_t c = 0;
        while (c < choices.size() && choices[c] != value) ++c;
        if (c == choices.size()) return invalid(f, value, std::string("one of ") + f.choices);
        *slot.choice = uint8_t(c);
        break;
    }
    case FieldType::Integer: {
        unsigned v = 0;
        auto r = std::from_chars(value.data(), value.data() + value.size(), v);
        if (r.ec != std::errc() || r.ptr != value.data() + value.size() || v < f.min || v > f.max)
            return invalid(f, value, rangeText(f, "a whole number"));
        *slot.integer = uint16_t(v);
        break;
    }
    case FieldType::TextureRef: {
        if (value == "none") {
            *slot.texture = kNone;
            break;
        }
        unsigned v = 0;
        auto r = std::from_chars(value.data(), value.data() + value.size(), v);
        if (r.ec != std::errc() || r.ptr != value.data() + value.size() || v == kNone)
            return invalid(f, value, "a texture index or none");
        *slot.texture = v;
        break;
    }
    }
    material = edited;
    return {};
}

std::string getMaterialField(const Material& material, std::string_view field) {
    size_t index = 0;
    while (index < std::size(kFields) && field != kFields[index].name) ++index;
    if (index == std::size(kFields)) return {};
    const MaterialField& f = kFields[index];
    MaterialFieldSlot slot = f.slot(const_cast<Material&>(material));
    char buf[128];
    switch (f.type) {
    case FieldType::Float: std::snprintf(buf, sizeof(buf), "%.9g", slot.floats[0]); return buf;
    case FieldType::Color3:
        std::snprintf(buf, sizeof(buf), "%.9g,%.9g,%.9g", slot.floats[0], slot.floats[1],
                      slot.floats[2]);
        return buf;
    case FieldType::Color4:
        std::snprintf(buf, sizeof(buf), "%.9g,%.9g,%.9g,%.9g", slot.floats[0], slot.floats[1],
                      slot.floats[2], slot.floats[3]);
        return buf;
    case FieldType::Bool: return *slot.flag ? "true" : "false";
    case FieldType::Choice: return std::string(split(f.choices, '|')[*slot.choice]);
    case FieldType::Integer: return std::to_string(*slot.integer);
    case FieldType::TextureRef:
        return *slot.texture == kNone ? "none" : std::to_string(*slot.texture);
    }
    return {};
}

bool globMatch(std::string_view pattern, std::string_view text) {
    // Iterative matcher with one backtrack point: linear in practice, no recursion depth to blow.
    size_t p = 0, t = 0, starP = std::string_view::npos, starT = 0;
    while (t < text.size()) {
        if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == text[t])) {
            ++p;
            ++t;
        } else if (p < pattern.size() && pattern[p] == '*') {
            starP = p++;
            starT = t;
        } else if (starP != std::string_view::npos) {
            p = starP + 1;
            t = ++starT;
        } else {
            return false;
        }
    }
    while (p < pattern.size() && pattern[p] == '*') ++p;
    return p == pattern.size();
}

} // namespace pnb
