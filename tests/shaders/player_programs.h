// player_programs.h — the programs pnb-play builds from its embedded shaders (player/shaders), as
// its call sites build them, for tests/shaders' validation of every real shader.
//
// The player names its programs and their defines at each call site (renderer.cpp's built-ins,
// gi_resources.cpp, shadow_resources.cpp, pass_light_clusters.cpp, pass_shadow.cpp), so this
// table repeats them. A new file in player/shaders/ that no entry uses fails the test
// (expand_shaders.cpp's coverage check); a new define set at a call site needs a line here.
#pragma once

#include <string>
#include <vector>

namespace pnb::test {

// Where a stage's text comes from: the player's embedded files, or the scene library (shaders/)
// resolved as the converter packs it.
enum class ShaderOrigin { Player, Scene };

struct PlayerStage {
    std::string file;
    ShaderOrigin origin = ShaderOrigin::Player;
};

struct PlayerProgram {
    std::string label;                // as the player labels it in errors
    std::vector<PlayerStage> stages;  // in link order
    std::vector<std::string> defines; // in the order the call site passes them
};

// Every program built from player/shaders alone: full-screen and flat passes, the compute passes
// with each define set their call sites pass (LPV stages with and without FLOAT_ATOMICS).
std::vector<PlayerProgram> playerPrograms();

// pass_shadow.cpp's geometry-shader variant of a container's shadow program: its stages with
// shadow_layers.geom after the vertex stage, its defines plus LAYER_FROM_GEOMETRY.
PlayerProgram geometryLayerProgram(const std::string& shadowLabel,
                                   const std::vector<std::string>& shadowDefines);

} // namespace pnb::test
