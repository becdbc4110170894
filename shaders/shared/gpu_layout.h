// gpu_layout.h — one declaration of a GPU block for GLSL and C++ (how: in the C++ part below,
// which the embedded GLSL texts leave out).
#ifndef PNB_GPU_LAYOUT_H
#define PNB_GPU_LAYOUT_H

#ifdef __cplusplus

// One header declares a GPU block (uniform block, storage struct) for GLSL and C++ at once, so
// the player's structs and the shaders' blocks cannot drift apart. The shared
// headers beside this one list each block's members once, as an X-macro
// `PNB_..._MEMBERS(FIELD, ARRAY)` whose rows are FIELD(type, cppName, glslName) and
// ARRAY(type, cppName, glslName, count): GLSL declares `type glslName;`, C++ `cppType cppName{};`
// (the two spellings exist because the shaders' names, uViewProjection, and the player's,
// viewProjection, both predate this file; the order, the types and the counts are written once).
//
// GLSL reads this file through the converter's #include resolution (converter/src/
// shader_sources.cpp: it embeds everything under shaders/) or, for the player's own shaders,
// through the include inlining of cmake/embed_text.cmake. GLSL does not define __cplusplus, so
// it skips the C++ parts (and the embedded texts carry them as empty lines). Comments inside the member lists are /* */: a // comment
// would swallow the line's continuation backslash.

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <type_traits>

#include <glm/glm.hpp>

#define PNB_CPP_TYPE_float float
#define PNB_CPP_TYPE_uint std::uint32_t
#define PNB_CPP_TYPE_vec3 glm::vec3
#define PNB_CPP_TYPE_vec4 glm::vec4
#define PNB_CPP_TYPE_uvec4 glm::uvec4
#define PNB_CPP_TYPE_mat4 glm::mat4

// Members are value-initialised: a block built member by member never uploads stale bytes.
#define PNB_DECLARE_FIELD(type, cppName, glslName) PNB_CPP_TYPE_##type cppName{};
#define PNB_DECLARE_ARRAY(type, cppName, glslName, count) PNB_CPP_TYPE_##type cppName[count]{};
#define PNB_UNIFORM_BLOCK(cppName, glslName, bindingIndex) struct cppName
#define PNB_STRUCT(cppName, glslName) struct cppName
#define PNB_NAMESPACE_BEGIN namespace pnb::player {
#define PNB_NAMESPACE_END }

namespace pnb::gpu {

enum class Rule { Std140, Std430 };

// A GLSL type's base alignment and size in bytes (GL 4.6, 7.6.2.2, rules 1-5; the same under
// std140 and std430 outside arrays and structs). Only the types the blocks use are listed: a new
// one fails to compile here instead of being laid out by guess.
template <class T> struct GlslType;
template <> struct GlslType<float> { static constexpr size_t align = 4, size = 4; };
template <> struct GlslType<std::uint32_t> { static constexpr size_t align = 4, size = 4; };
template <> struct GlslType<glm::vec3> { static constexpr size_t align = 16, size = 12; };
template <> struct GlslType<glm::vec4> { static constexpr size_t align = 16, size = 16; };
template <> struct GlslType<glm::uvec4> { static constexpr size_t align = 16, size = 16; };
// Column-major: four vec4 columns (rule 5).
template <> struct GlslType<glm::mat4> { static constexpr size_t align = 16, size = 64; };

// One member as C++ laid it out: where it is, and what GLSL needs to place it.
struct Member {
    size_t align = 0, size = 0; // of one element
    size_t count = 0;           // 0: not an array
    size_t offset = 0;          // offsetof in the C++ struct
};

template <class T> constexpr Member member(size_t offset) {
    using Element = std::remove_all_extents_t<T>;
    return {GlslType<Element>::align, GlslType<Element>::size,
            std::is_array_v<T> ? std::extent_v<T> : 0, offset};
}

constexpr size_t roundUp(size_t value, size_t to) { return (value + to - 1) / to * to; }

// std140 rounds array elements and structs up to a vec4's alignment (rules 4 and 9); std430 does
// not.
constexpr size_t ruleAlign(Rule rule, size_t align) {
    return rule == Rule::Std140 ? roundUp(align, 16) : align;
}

inline constexpr size_t kLaidOut = ~size_t(0);

// The index of the first member C++ placed elsewhere than `rule` does, the member count if only
// sizeof is wrong (it must be the rule's size of the struct: its array stride), or kLaidOut.
constexpr size_t firstMisplaced(Rule rule, size_t sizeOf, std::initializer_list<Member> members) {
    size_t offset = 0, structAlign = 0, index = 0;
    for (const Member& m : members) {
        size_t align = m.count ? ruleAlign(rule, m.align) : m.align;
        size_t stride = m.count ? roundUp(m.size, align) : m.size;
        offset = roundUp(offset, align);
        if (m.offset != offset) return index;
        offset += m.count ? stride * m.count : m.size;
        structAlign = structAlign > align ? structAlign : align;
        ++index;
    }
    return sizeOf == roundUp(offset, ruleAlign(rule, structAlign)) ? kLaidOut : index;
}

} // namespace pnb::gpu

// The check that the struct above it follows `rule` (pnb::gpu::Rule::Std140 or Std430): a
// failure names the first misplaced member's index ("the comparison reduces to (2 == ...)").
#define PNB_LAYOUT_MEMBER(type, cppName, glslName, ...)                                            \
    ::pnb::gpu::member<decltype(PnbChecked::cppName)>(offsetof(PnbChecked, cppName)),
#define PNB_CHECK_LAYOUT(rule, Struct, MEMBERS)                                                    \
    namespace pnb_layout_##rule##_##Struct {                                                       \
    using PnbChecked = Struct;                                                                     \
    static_assert(::pnb::gpu::firstMisplaced(::pnb::gpu::Rule::rule, sizeof(PnbChecked),          \
                                             {MEMBERS(PNB_LAYOUT_MEMBER, PNB_LAYOUT_MEMBER)}) ==   \
                      ::pnb::gpu::kLaidOut,                                                        \
                  #Struct " does not follow " #rule);                                              \
    }

#else // GLSL

#define PNB_DECLARE_FIELD(type, cppName, glslName) type glslName;
#define PNB_DECLARE_ARRAY(type, cppName, glslName, count) type glslName[count];
#define PNB_UNIFORM_BLOCK(cppName, glslName, bindingIndex)                                         \
    layout(std140, binding = bindingIndex) uniform glslName
#define PNB_STRUCT(cppName, glslName) struct glslName
#define PNB_NAMESPACE_BEGIN
#define PNB_NAMESPACE_END
#define PNB_CHECK_LAYOUT(rule, Struct, MEMBERS)

#endif

#endif
