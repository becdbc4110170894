// pnb_player/path_json.h — camera paths as the keyframe JSON that `pnb-convert --path FILE` reads,
// in the player's types, so `pnb-play --path FILE` can replay a file without converting, and a
// path recorded in the window can be packed into a container unchanged. The schema, its rules,
// the reader and the writer are pnb/path_json.h (pnb_path_json, shared with the converter).
//
// Does NOT do: reading or writing containers; any schema field beyond pnb/path_json.h's.
#pragma once

#include <string>

#include "pnb_player/gpu_scene.h"
#include "pnb_player/play_error.h"

namespace pnb::player {

// Reads a keyframe file. Errors (Input) name the file and the key at fault.
PlayResult<ScenePath> readPathJson(const std::string& file);

// The JSON text of `path` (name, interpolation, loop, keys with time, position, rotation,
// yfov_degrees), newline-terminated.
std::string pathJsonText(const ScenePath& path);

// Writes pathJsonText atomically (pnb/atomic_file.h). Errors are Io.
PlayResult<Done> writePathJson(const std::string& file, const ScenePath& path);

} // namespace pnb::player
