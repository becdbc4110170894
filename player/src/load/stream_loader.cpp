#include "load/stream_loader.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <thread>
#include <unordered_map>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace pnb::player {

// Everything both threads and the GL thread touch; shared so that a thread left running at exit
// (a stalled pipe) never sees it destroyed.
struct LoaderShared {
    std::mutex mutex;
    std::condition_variable changed; // any of the below
    StreamLoader::Options options;
    int fd = -1;
    bool ownsFd = false, seekable = false;
    uint64_t fileBytes = 0;

    SceneAssembler assembler; // the forward thread's until sceneReady, then read-only
    bool sceneReady = false, forwardDone = false, forwardExited = false, fetchExited = false;
    bool stop = false;
    Error error{FormatError::None, 0, {}};
    uint64_t bytesRead = 0, queued = 0;
    std::deque<Arrival> arrived;
    // Where the forward pass saw each chunk of the progressive section, for re-reads.
    std::unordered_map<uint64_t, ChunkInfo> levels;  // (texture << 32 | level) -> TMIP
    std::unordered_map<uint32_t, ChunkInfo> details; // mesh -> MDET
    struct Request {
        std::optional<uint32_t> mesh; // an MDET; else the TMIP at `level` in `levels`
        uint64_t level = 0;
    };
    std::deque<Request> requests;
    uint32_t tmipCount = 0, mdetCount = 0;

    ~LoaderShared() {
        if (ownsFd && fd >= 0) ::close(fd);
    }
    // Counts `level`'s bytes against the read-ahead until it is destroyed (under the lock).
    static void track(Arrival& level, const std::shared_ptr<LoaderShared>& sh, uint64_t bytes) {
        level.mShared = sh;
        level.mBytes = bytes;
        sh->queued += bytes;
    }
    void fail(const Error& e) { // under the lock
        if (error.code == FormatError::None) error = e;
        changed.notify_all();
    }
};

namespace {

uint64_t levelKey(uint32_t texture, uint32_t level) { return uint64_t(texture) << 32 | level; }

// Decodes a TMIP payload and checks it against the scene's descriptors.
Result<TextureMip> decodeLevel(const Scene& scene, const ChunkInfo& info, const Payload& payload, uint32_t index) {
    auto mip = decodeChunk<TextureMip>(payload.bytes(), info.header, info.payloadOffset);
    if (!mip) return mip.error();
    if (Status s = validateTextureMip(scene, *mip, index); !isOk(s)) {
        Error e = s;
        e.offset = info.headerOffset;
        return e;
    }
    return mip;
}

// Decodes an MDET payload and checks it against the scene (its proxy).
Result<MeshDetail> decodeMeshDetail(const Scene& scene, const ChunkInfo& info, const Payload& payload, uint32_t index) {
    auto d = decodeChunk<MeshDetail>(payload.bytes(), info.header, info.payloadOffset);
    if (!d) return d.error();
    if (Status s = validateMeshDetail(scene, *d, index); !isOk(s)) {
        Error e = s;
        e.offset = info.headerOffset;
        e.message = "chunk " + std::to_string(info.header.sequence) + " 'MDET': " + e.message;
        return e;
    }
    return d;
}

void forwardPass(const std::shared_ptr<LoaderShared>& sh) {
    ReadOptions ro;
    ro.verifyChecksums = sh->options.verifyChecksums;
    Status st = streamChunks(sh->fd, ro, [&](const StreamedChunk& chunk) {
        const ChunkInfo& info = chunk.info;
        const uint64_t end = info.payloadOffset + info.header.storedSize;
        std::unique_lock lock(sh->mutex);
        if (sh->stop) return false;
        if (!sh->sceneReady) {
            lock.unlock(); // the assembler is this thread's alone until sceneReady
            if (Status s = sh->assembler.checkOrder(info); !isOk(s)) {
                lock.lock();
                sh->fail(s);
                return false;
            }
            if (streamOrderRank(info.header.tag) == streamOrderRank(tags::kTextureMip)) { // progressive
                Status s = sh->assembler.finish();
                if (isOk(s)) s = validateScene(sh->assembler.scene);
                lock.lock();
                if (!isOk(s)) {
                    sh->fail(s);
                    return false;
                }
                sh->sceneReady = true;
                sh->changed.notify_all();
            } else {
                Status s = streamOrderRank(info.header.tag) < 0
                               ? Status{}
                               : sh->assembler.decode(info, Payload::own({chunk.payload.begin(), chunk.payload.end()}));
                lock.lock();
                sh->bytesRead = end;
                if (!isOk(s)) {
                    sh->fail(s);
                    return false;
                }
                return true;
            }
        } else if (Status s = sh->assembler.checkOrder(info); !isOk(s)) {
            sh->fail(s);
            return false;
        }
        const bool mesh = info.header.tag == tags::kMeshDetail;
        if (info.header.tag != tags::kTextureMip && !mesh) { // an unknown chunk among the texels
            sh->bytesRead = end;
            return true;
        }
        // Read ahead only as far as the budget allows (one level always, or nothing moves).
        const uint64_t bytes = info.header.rawSize;
        sh->changed.wait(lock, [&] { return sh->stop || sh->queued == 0 || sh->queued + bytes <= sh->options.readAheadBytes; });
        if (sh->stop) return false;
        const uint32_t index = mesh ? sh->mdetCount++ : sh->tmipCount++;
        lock.unlock();
        Arrival level;
        level.payload = Payload::own({chunk.payload.begin(), chunk.payload.end()});
        Status decoded;
        if (mesh) {
            auto d = decodeMeshDetail(sh->assembler.scene, info, level.payload, index);
            if (d) level.mesh = std::move(*d);
            else decoded = d.error();
        } else {
            auto mip = decodeLevel(sh->assembler.scene, info, level.payload, index);
            if (mip) level.mip = *mip;
            else decoded = mip.error();
        }
        lock.lock();
        // Stopped meanwhile: nothing more goes into `arrived` (an Arrival there keeps the shared
        // state alive, and the state keeps it: after the stop nobody would take it).
        if (sh->stop) return false;
        if (isOk(decoded)) decoded = sh->assembler.checkProgressive(info, mesh ? nullptr : &level.mip);
        if (!isOk(decoded)) {
            sh->fail(decoded);
            return false;
        }
        LoaderShared::track(level, sh, bytes);
        if (mesh) sh->details[level.mesh->mesh] = info;
        else sh->levels[levelKey(level.mip.texture, level.mip.level)] = info;
        sh->arrived.push_back(std::move(level));
        sh->bytesRead = end;
        sh->changed.notify_all();
        return true;
    });
    std::deque<Arrival> orphans; // destroyed after the lock below is released (they take it)
    std::lock_guard lock(sh->mutex);
    if (sh->stop) orphans.swap(sh->arrived);
    if (!isOk(st)) sh->fail(st);
    else if (!sh->stop && sh->error.code == FormatError::None) {
        if (!sh->sceneReady) { // no texels at all
            Status s = sh->assembler.finish();
            if (isOk(s)) s = validateScene(sh->assembler.scene);
            if (!isOk(s)) sh->fail(s);
            else sh->sceneReady = true;
        }
        sh->forwardDone = sh->error.code == FormatError::None;
        sh->bytesRead = sh->fileBytes ? sh->fileBytes : sh->bytesRead;
    }
    sh->forwardExited = true;
    sh->changed.notify_all();
}

void fetchLoop(const std::shared_ptr<LoaderShared>& sh) {
    ReadOptions ro;
    ro.verifyChecksums = sh->options.verifyChecksums;
    std::unique_lock lock(sh->mutex);
    while (true) {
        sh->changed.wait(lock, [&] { return sh->stop || !sh->requests.empty(); });
        if (sh->stop) break;
        const LoaderShared::Request request = sh->requests.front();
        sh->requests.pop_front();
        const ChunkInfo info = request.mesh ? sh->details.at(*request.mesh) : sh->levels.at(request.level);
        lock.unlock();
        Arrival level;
        Status decoded;
        if (auto payload = readChunkAt(sh->fd, info, ro); !payload) {
            decoded = payload.error();
        } else {
            level.payload = std::move(*payload);
            if (request.mesh) {
                auto d = decodeMeshDetail(sh->assembler.scene, info, level.payload, 0);
                if (d) level.mesh = std::move(*d);
                else decoded = d.error();
            } else {
                auto mip = decodeLevel(sh->assembler.scene, info, level.payload, 0);
                if (mip) level.mip = *mip;
                else decoded = mip.error();
            }
        }
        lock.lock();
        if (sh->stop) break;
        if (!isOk(decoded)) {
            sh->fail(decoded);
            break;
        }
        level.refetched = true;
        LoaderShared::track(level, sh, info.header.rawSize);
        sh->arrived.push_back(std::move(level));
        sh->changed.notify_all();
    }
    std::deque<Arrival> orphans; // destroyed after the lock is released (they take it)
    if (sh->stop) orphans.swap(sh->arrived);
    sh->fetchExited = true;
    sh->changed.notify_all();
    lock.unlock();
}

} // namespace

Arrival::Arrival(Arrival&& o) noexcept
    : mesh(std::move(o.mesh)), mip(o.mip), payload(std::move(o.payload)), refetched(o.refetched),
      mShared(std::move(o.mShared)), mBytes(std::exchange(o.mBytes, 0)) {}
Arrival& Arrival::operator=(Arrival&& o) noexcept {
    if (this != &o) {
        Arrival gone(std::move(*this));
        mesh = std::move(o.mesh);
        mip = o.mip;
        payload = std::move(o.payload);
        refetched = o.refetched;
        mShared = std::move(o.mShared);
        mBytes = std::exchange(o.mBytes, 0);
    }
    return *this;
}
Arrival::~Arrival() {
    if (!mShared || !mBytes) return;
    std::lock_guard lock(mShared->mutex);
    mShared->queued -= mBytes;
    mShared->changed.notify_all();
}

PlayResult<std::unique_ptr<StreamLoader>> StreamLoader::start(const std::string& path, const Options& options) {
    auto sh = std::make_shared<LoaderShared>();
    sh->options = options;
    if (path == "-") {
        sh->fd = STDIN_FILENO;
    } else {
        sh->fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (sh->fd < 0) return PlayError{PlayErrorKind::Input, "cannot open '" + path + "': " + std::strerror(errno)};
        sh->ownsFd = true;
    }
    struct stat st {};
    if (::fstat(sh->fd, &st) == 0 && S_ISREG(st.st_mode)) {
        sh->seekable = true;
        sh->fileBytes = uint64_t(st.st_size);
    }
    std::unique_ptr<StreamLoader> loader(new StreamLoader);
    loader->mShared = sh;
    std::thread(forwardPass, sh).detach();
    if (sh->seekable) std::thread(fetchLoop, sh).detach();
    else sh->fetchExited = true;
    return loader;
}

StreamLoader::~StreamLoader() {
    std::deque<Arrival> dropped;
    std::unique_lock lock(mShared->mutex);
    mShared->stop = true;
    dropped.swap(mShared->arrived); // their destructors take the lock: freed after it
    mShared->changed.notify_all();
    // The threads are detached and hold the shared state; wait for them briefly so that a
    // normal exit leaves nothing running. A forward pass blocked in read(2) on a stalled pipe
    // is left to end with the process.
    mShared->changed.wait_for(lock, std::chrono::seconds(2),
                              [&] { return mShared->forwardExited && mShared->fetchExited; });
    lock.unlock();
}

PlayResult<const Scene*> StreamLoader::waitForScene() {
    std::unique_lock lock(mShared->mutex);
    mShared->changed.wait(lock, [&] {
        return mShared->sceneReady || mShared->error.code != FormatError::None || mShared->forwardExited;
    });
    // Ready: damage further on is status()'s to report, after the first frame.
    if (mShared->sceneReady) return &mShared->assembler.scene;
    if (mShared->error.code != FormatError::None) return inputError(mShared->error);
    return PlayError{PlayErrorKind::Input, "the stream ended before the scene"};
}

std::vector<Arrival> StreamLoader::take() {
    std::lock_guard lock(mShared->mutex);
    std::vector<Arrival> out;
    out.reserve(mShared->arrived.size());
    for (Arrival& l : mShared->arrived) out.push_back(std::move(l));
    mShared->arrived.clear();
    return out;
}

void StreamLoader::waitForLevel() {
    std::unique_lock lock(mShared->mutex);
    mShared->changed.wait(lock, [&] {
        return !mShared->arrived.empty() || mShared->forwardExited || mShared->error.code != FormatError::None;
    });
}

bool StreamLoader::request(uint32_t texture, uint32_t level) {
    std::lock_guard lock(mShared->mutex);
    if (!mShared->seekable || !mShared->levels.count(levelKey(texture, level))) return false;
    mShared->requests.push_back({std::nullopt, levelKey(texture, level)});
    mShared->changed.notify_all();
    return true;
}

bool StreamLoader::requestMeshDetail(uint32_t mesh) {
    std::lock_guard lock(mShared->mutex);
    if (!mShared->seekable || !mShared->details.count(mesh)) return false;
    mShared->requests.push_back({mesh, 0});
    mShared->changed.notify_all();
    return true;
}

bool StreamLoader::seekable() const { return mShared->seekable; }
bool StreamLoader::meshDetailsDone() const {
    std::lock_guard lock(mShared->mutex);
    return mShared->forwardDone || mShared->assembler.largerTexelsSeen();
}
bool StreamLoader::forwardDone() const {
    std::lock_guard lock(mShared->mutex);
    return mShared->forwardDone;
}
PlayResult<Done> StreamLoader::status() const {
    std::lock_guard lock(mShared->mutex);
    if (mShared->error.code != FormatError::None) return inputError(mShared->error);
    return Done{};
}
uint64_t StreamLoader::bytesRead() const {
    std::lock_guard lock(mShared->mutex);
    return mShared->bytesRead;
}
uint64_t StreamLoader::fileBytes() const { return mShared->fileBytes; }
uint64_t StreamLoader::queuedBytes() const {
    std::lock_guard lock(mShared->mutex);
    return mShared->queued;
}

} // namespace pnb::player
