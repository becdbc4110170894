// child_convert.h — opening a dropped glTF/OBJ in pnb-play without linking an importer: the
// player runs the converter as a child process (posix_spawn with an argv, no shell) into a
// temporary .pnb. The layering rule stands: pnb-play never links pnb_converter or an importer.
#pragma once

#include <string>

#include "pnb_player/play_error.h"

namespace pnb::player {

// True for the extensions the converter imports (.gltf, .glb, .obj; case-insensitive).
bool isConvertibleSource(const std::string& path);

// The pnb-convert to run: $PNB_CONVERT if set, else the one beside this executable, else the
// first on PATH; "" when there is none.
std::string findConverter();

// A converted container in a fresh temporary directory; the destructor removes both.
class TempContainer {
public:
    TempContainer() = default;
    explicit TempContainer(std::string dir, std::string file) : mDir(std::move(dir)), mFile(std::move(file)) {}
    TempContainer(TempContainer&& o) noexcept : mDir(std::move(o.mDir)), mFile(std::move(o.mFile)) { o.mDir.clear(); }
    TempContainer& operator=(TempContainer&& o) noexcept;
    TempContainer(const TempContainer&) = delete;
    TempContainer& operator=(const TempContainer&) = delete;
    ~TempContainer();
    const std::string& file() const { return mFile; }

private:
    std::string mDir, mFile;
};

// Runs `converter SOURCE -o TMP/<stem>.pnb -q` and waits for it. Errors (Input) say whether the
// converter is missing, could not start, or failed (with its exit code; its own message went to
// stderr).
PlayResult<TempContainer> convertInChild(const std::string& source, const std::string& converter);

} // namespace pnb::player
