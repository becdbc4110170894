// stream_loader.h — the reading side of streaming playback (scene_stream.h): a thread that
// reads the container front to back with streamChunks (a file, a pipe or a socket: one forward
// pass, no seeking), decodes everything before the progressive section into a Scene, then hands
// its chunks — texel levels (TMIP) and meshes' full detail (MDET) — over one at a time through a
// queue bounded in bytes, so it reads ahead only as far as the GL thread keeps up; and, when the
// input is a regular file, a second thread that reads a texel level or a mesh's detail the GL
// thread dropped again on request (pread at the offset the forward pass saw).
//
// Reading, checksums, decompression, decoding and the cross-reference checks all happen on
// these threads; the GL thread only copies texels into staging memory and issues uploads.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pnb/scene.h"
#include "pnb_player/play_error.h"

namespace pnb::player {

struct LoaderShared; // stream_loader.cpp

// A chunk of the progressive section (docs/FORMAT.md §4.1), decoded and checked: a texel level
// (TMIP) or a mesh's full detail (MDET). While it exists its bytes count against the loader's
// read-ahead.
struct Arrival {
    Arrival() = default;
    Arrival(Arrival&&) noexcept;
    Arrival& operator=(Arrival&&) noexcept;
    ~Arrival();

    std::optional<MeshDetail> mesh; // an MDET; else a texel level:
    TextureMip mip;                 // (blobs of either point into `payload`)
    Payload payload;                // owned
    bool refetched = false;

private:
    friend struct LoaderShared;
    std::shared_ptr<LoaderShared> mShared; // returns the bytes to the read-ahead budget
    uint64_t mBytes = 0;
};

class StreamLoader {
public:
    struct Options {
        bool verifyChecksums = true;
        uint64_t readAheadBytes = uint64_t(64) << 20; // decoded levels not yet uploaded, at most
    };
    // Starts reading `path` ("-": standard input). Errors: the file cannot be opened.
    static PlayResult<std::unique_ptr<StreamLoader>> start(const std::string& path, const Options& options);
    ~StreamLoader(); // stops both threads (a pipe whose writer has stalled is left to the exit)

    // Waits until every chunk before the first TMIP or MDET (or the end) is decoded and the scene so far
    // passes validateScene; from then on the scene is read-only on every thread. Errors: the
    // container's (Input, naming the chunk and its byte offset).
    PlayResult<const Scene*> waitForScene();

    // What has arrived, oldest first (does not wait).
    std::vector<Arrival> take();
    // Waits until something has arrived, the forward pass has ended, or an error occurred.
    void waitForLevel();
    // Asks the re-reading thread for (texture, level) again; it arrives through take(). False
    // when impossible: not a regular file, or the forward pass has not passed that level yet.
    bool request(uint32_t texture, uint32_t level);
    // The same for mesh `mesh`'s full detail (MDET).
    bool requestMeshDetail(uint32_t mesh);

    bool seekable() const;
    // Every MDET has arrived: the forward pass ended, or passed a texel level that MDETs may not
    // follow (SceneAssembler::checkProgressive).
    bool meshDetailsDone() const;
    bool forwardDone() const;      // the forward pass reached the end of the file, intact
    PlayResult<Done> status() const; // the first error of either thread, as an Input error
    uint64_t bytesRead() const;    // by the forward pass, through the last chunk handed over
    uint64_t fileBytes() const;    // 0 when unknown (a pipe)
    uint64_t queuedBytes() const;  // decoded levels alive (read ahead, or waiting for upload)

private:
    StreamLoader() = default;
    std::shared_ptr<LoaderShared> mShared;
};

} // namespace pnb::player
