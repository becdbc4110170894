// pnb/user_cache_directory.h — where Penumbra's tools keep what they may forget (the converter's
// shader validation cache, the player's program binaries), by the XDG Base Directory rules, with
// one override variable per tool for tests and build machines. Shared so that every tool places
// its cache by the same rules.
#pragma once

#include <string>
#include <string_view>

namespace pnb {

// $<overrideVariable> if set and not empty; else $XDG_CACHE_HOME/penumbra/<subdirectory> if
// XDG_CACHE_HOME is an absolute path (the XDG spec says to ignore a relative one); else
// $HOME/.cache/penumbra/<subdirectory>. "" when HOME is unset or empty too, which callers treat
// as "no on-disk cache" (rather than guessing a home directory a sandboxed or system process may
// not own). An empty subdirectory means penumbra/ itself. The directory is not created here.
std::string userCacheDirectory(const char* overrideVariable, std::string_view subdirectory = {});

} // namespace pnb
