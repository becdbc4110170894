// pnb_converter/shader_permutations.h — which shader programs, with which permutation defines,
// a scene needs; their sources with #include resolved; and their validation with glslang.
//
// "Model only what the scene requires": a program variant exists only for a feature combination
// some material uses (no normal-map variant without a normal-mapped material), scene-level
// programs only when something uses them (no shadow program without a shadow-casting light and
// caster, no deferred lighting without a deferred material), GI programs only with GI on, and
// the IBL define only with an environment.
//
// Does NOT do: compile for a GPU (the player does), write the container.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/error.h"
#include "pnb/scene_builder.h"
#include "pnb_converter/scene_ir.h"

namespace pnb::converter {

// A GLSL file of the shader library: a path relative to shaders/ and its text.
struct ShaderFile {
    std::string_view name, text;
};

// The renderer's shaders embedded at build time (shaders/, without sample/).
std::span<const ShaderFile> builtinShaderFiles();

// One stage's source with every #include "x" replaced by the file's text (once per file: include
// guards are honoured, and a file included twice is inlined once). The result starts with the
// stage's #version line and a `#line 2 0`; each inlined file is bracketed by #line directives
// whose source-string numbers index `files` (file 0 is the stage itself), so compiler messages
// can name the file. Errors (Input): a missing file, an include cycle, a missing #version.
struct ResolvedSource {
    std::string text;
    std::vector<std::string> files;
};
Result<ResolvedSource, ConvertError> resolveShaderSource(std::string_view name,
                                                         std::span<const ShaderFile> library);

// What one material needs from its surface shader.
struct MaterialFeatures {
    bool baseColorMap = false, metallicRoughnessMap = false, normalMap = false,
         occlusionMap = false, emissiveMap = false;
    bool vertexColor = false; // the mesh drawn with it has COLOR_0
    bool uv0 = false, uv1 = false;
    bool alphaMask = false;
};

// Scene-wide facts that decide the scene-level programs.
struct SceneShaderNeeds {
    bool shadows = false;       // a light casts shadows and some material casts them
    bool maskedCasters = false; // some shadow caster is alpha-masked
    // Some shadow caster is blended (BLEND, castsShadows): light passes through it tinted
    // (issue 43): a `shadow[TRANSLUCENT]` program draws its transmittance, and the lighting
    // programs read it (TRANSLUCENT_SHADOWS).
    bool translucentCasters = false;
    bool gi = false;            // GI: lighting with GI, G-buffer variants for forward materials
    bool ibl = false;           // an environment (ENVM) is written: lighting with IBL
    bool skins = false;         // a skinned node (SKIN): `deform[SKIN]`
    bool morphs = false;        // morph targets (MRPH): `deform[MORPH]`
};

// A program with its stage files and the sorted defines of this permutation.
struct ProgramVariant {
    std::string name;                     // "gbuffer", "forward", "shadow", ...
    std::vector<std::string> stageFiles;  // e.g. {"surface.vert", "gbuffer.frag"}
    std::vector<ShaderStage> stages;
    std::vector<std::string> defines;     // "HAS_NORMAL_MAP", sorted
};

struct ShaderPlan {
    std::vector<ProgramVariant> programs; // deduplicated, deterministic order
    std::vector<uint32_t> materialProgram; // per material: index into programs
};

// Chooses the programs: each material gets the surface program of its shading path with the
// defines of its features; identical variants are shared.
ShaderPlan planShaders(std::span<const Material> materials,
                       std::span<const MaterialFeatures> features, const SceneShaderNeeds& needs);

// Appends the plan's shader stages (each file resolved once and shared by every program that
// uses it) and programs to builder.scene, in plan order: program i of the plan is PROG chunk i.
// Errors: resolveShaderSource's.
Result<bool, ConvertError> appendShaderPrograms(const ShaderPlan& plan, std::span<const ShaderFile> library,
                                                SceneBuilder& builder);

class ShaderValidationCache; // shader_validation_cache.h

// How validateShaders reached its verdicts.
struct ShaderValidationStats {
    size_t compiled = 0;  // variants compiled and linked by glslang
    size_t fromCache = 0; // variants the cache already knew to be valid
};

// Compiles and links every variant of `plan` with glslang (GLSL 4.50 core, OpenGL rules) and
// returns how many variants passed. With a `cache`, a variant whose exact texts, stages and
// glslang version passed before is not compiled again, and each one that passes is remembered.
// Errors (Input): the program, its defines, and the compiler's message with file:line.
Result<size_t, ConvertError> validateShaders(const ShaderPlan& plan,
                                             std::span<const ShaderFile> library,
                                             ShaderValidationCache* cache = nullptr,
                                             ShaderValidationStats* stats = nullptr);

// Text form of a define list for messages and summaries: "gbuffer[HAS_UV0 HAS_NORMAL_MAP]".
std::string describeVariant(const ProgramVariant& v);

} // namespace pnb::converter
