// gltf_internal.h — helpers shared by the glTF importer's files (import_gltf*.cpp,
// gltf_meshopt.cpp). Internal.
//
// The JSON readers read glTF JSON (nlohmann) the way tinygltf reads it: both files inspect or
// patch the JSON before tinygltf parses it, and must agree with tinygltf on which object an index
// names and which values are "absent".
#pragma once

#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace pnb::converter::gltf_internal {

// printf into a std::string, for messages.
inline std::string strf(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
inline std::string strf(const char* fmt, ...) {
    va_list args;
    va_start(args, fmt);
    va_list copy;
    va_copy(copy, args);
    const int n = std::vsnprintf(nullptr, 0, fmt, copy);
    va_end(copy);
    std::string s(n > 0 ? size_t(n) : 0, '\0');
    if (n > 0) std::vsnprintf(s.data(), s.size() + 1, fmt, args);
    va_end(args);
    return s;
}

inline const nlohmann::json* jsonMember(const nlohmann::json& o, const char* key) {
    if (!o.is_object()) return nullptr;
    auto it = o.find(key);
    return it == o.end() ? nullptr : &*it;
}

// Same reading as tinygltf's GetInt (including its truncation to int).
inline std::optional<int> jsonInt(const nlohmann::json* v) {
    if (!v || !(v->is_number_integer() || v->is_number_unsigned())) return std::nullopt;
    return static_cast<int>(v->get<int64_t>());
}

// Same as tinygltf's ParseUnsignedProperty: anything but a non-negative integer is "absent".
inline std::optional<uint64_t> jsonUnsigned(const nlohmann::json* v) {
    if (!v || !v->is_number_unsigned()) return std::nullopt;
    return v->get<uint64_t>();
}

} // namespace pnb::converter::gltf_internal
