// pnb_player/play_error.h — the player's error value: what failed, in a sentence a user can act
// on. Bad input (a damaged container, a setting that does not parse, a shader that does not
// compile) is returned as a PlayError, never thrown or asserted.
#pragma once

#include <string>

#include "pnb/error.h"

namespace pnb::player {

enum class PlayErrorKind {
    Input,   // the container is damaged or inconsistent
    Usage,   // a command-line option or setting is invalid
    Gl,      // no suitable context, or the driver refused (shader compile, framebuffer)
    Io,      // an output file could not be written
};

struct PlayError {
    PlayErrorKind kind = PlayErrorKind::Input;
    std::string message;
};

template <class T> using PlayResult = Result<T, PlayError>;
struct Done {}; // the value of a PlayResult that only reports success

inline PlayError inputError(const Error& e) { return {PlayErrorKind::Input, e.describe()}; }

} // namespace pnb::player
