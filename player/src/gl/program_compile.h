// program_compile.h — GLSL programs from a container's PROG/SHDR chunks (and the player's own
// embedded passes). Compile and link errors name the program, its permutation and the source
// file and line, using the `// pnb-files:` table and `#line` directives the converter writes.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "pnb/scene.h"
#include "pnb_player/gl_handles.h"
#include "pnb_player/play_error.h"

namespace pnb::player {

struct StageSource {
    GLenum stage = GL_VERTEX_SHADER;
    std::string_view source; // starts with #version
};

// `label` names the program in errors; `defines` are inserted after the #version line.
PlayResult<GlHandle> compileProgram(std::string_view label, std::span<const StageSource> stages,
                                    std::span<const std::string_view> defines);

// PROG chunk `index` of `scene`, e.g. label "gbuffer[HAS_UV0] (PROG 2)".
PlayResult<GlHandle> compileSceneProgram(const Scene& scene, uint32_t index);

// "name[DEF1 DEF2]"
std::string programLabel(const Scene& scene, uint32_t index);

// One of the player's embedded programs (player/shaders), by file names.
PlayResult<GlHandle> compileEmbeddedProgram(std::string_view vertexFile,
                                            std::string_view fragmentFile,
                                            std::span<const std::string_view> defines = {});

// The text of one of the player's embedded shader files ("" if there is none).
std::string_view embeddedSource(std::string_view name);

// An embedded compute shader; `defines` select its stage where one file holds several.
PlayResult<GlHandle> compileEmbeddedCompute(std::string_view file,
                                            std::span<const std::string_view> defines = {});

} // namespace pnb::player
