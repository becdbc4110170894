// Camera-path keyframe files for the player: pnb/path_json.h's reader and writer (shared with the
// converter) in the player's types.
#include "pnb_player/path_json.h"

#include "pnb/atomic_file.h"
#include "pnb/path_json.h"

namespace pnb::player {

PlayResult<ScenePath> readPathJson(const std::string& file) {
    auto p = readCameraPathJson(file);
    if (!p) return PlayError{PlayErrorKind::Input, p.error().message};
    ScenePath sp;
    sp.name = p->name;
    sp.path.interpolation = p->interpolation;
    sp.path.loop = p->loop;
    sp.path.keys = std::move(p->keys);
    return sp;
}

std::string pathJsonText(const ScenePath& sp) {
    return cameraPathJsonText({sp.name, sp.path.interpolation, sp.path.loop, sp.path.keys});
}

PlayResult<Done> writePathJson(const std::string& file, const ScenePath& path) {
    std::string text = pathJsonText(path);
    Status s = writeFileAtomic(file, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    if (!isOk(s)) return PlayError{PlayErrorKind::Io, s.describe()};
    return Done{};
}

} // namespace pnb::player
