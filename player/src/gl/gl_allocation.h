// gl_allocation.h — noticing that the GL could not allocate. A glNamedBufferStorage or
// glTexStorage* that runs out of memory only sets GL_OUT_OF_MEMORY: the object then has no
// storage, and the first write into it is an error or a crash (stream.upload_mib=4096 mapped a
// null pointer). Code that creates storage clears the error flag first and checks it after, and
// returns a Gl error naming what it was making, so the caller falls back or stops with a message.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <string>

#include "pnb_player/play_error.h"

namespace pnb::player {

// Drops the error flags set before (they are not this allocation's).
inline void clearGlErrors() {
    for (int i = 0; i < 64 && glGetError() != GL_NO_ERROR; ++i) {
    }
}

// Ok, or a Gl error naming `what` (and its size) when the GL ran out of memory since
// clearGlErrors() (or since the flags were last read: only GL_OUT_OF_MEMORY counts, so an older
// error of another kind is dropped, not blamed). Call it where storage was just made, not every
// frame: glGetError can stall a threaded driver.
inline PlayResult<Done> checkGlAllocation(const std::string& what, uint64_t bytes) {
    bool outOfMemory = false;
    for (GLenum e; (e = glGetError()) != GL_NO_ERROR;) outOfMemory |= e == GL_OUT_OF_MEMORY;
    if (!outOfMemory) return Done{};
    return PlayError{PlayErrorKind::Gl, "out of GPU memory: the GL could not allocate " + what +
                                            " (" + std::to_string(bytes >> 20) + " MiB)"};
}

} // namespace pnb::player
