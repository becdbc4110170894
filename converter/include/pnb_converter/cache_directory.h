// pnb_converter/cache_directory.h — where the converter keeps what it may forget: the user's
// cache directory (XDG Base Directory rules, with an override for tests and build machines).
#pragma once

#include <string>

namespace pnb::converter {

// $PNB_CACHE_DIR if set and not empty; else $XDG_CACHE_HOME/penumbra if XDG_CACHE_HOME is an
// absolute path (the XDG spec says to ignore a relative one); else $HOME/.cache/penumbra (HOME
// from the environment, else the password database). "" when none of these exists, which
// callers treat as "no on-disk cache". The directory is not created here.
std::string userCacheDirectory();

} // namespace pnb::converter
