// make_stream_scene_layout.cpp — pnb-make-stream-scene's scene: the street layout (panels,
// ground, rocks, sun, camera and its path), then the writing in FORMAT.md §4.1 order with the
// texel pipeline (a producer thread) and the rocks' details spilled to a temporary file. A part of
// its own: where things go and in which order they are written (make_stream_scene.h).

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <future>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "make_stream_scene.h"
#include "pnb/mesh_levels.h"
#include "pnb/writer.h"
#include "pnb_converter/shader_permutations.h"

namespace stream_scene {

namespace {

// Rocks 0..count-1 through processRock, handed to `use(index, result)` in index order. With two
// threads, rock i + 1 is processed beside rock i (each is independent of the others, so the
// results are the same): two rocks in memory at a time. Stops at use's first exit code.
template <class Use>
std::optional<int> forEachRock(uint32_t count, uint32_t triangles, unsigned threads, Use&& use) {
    for (uint32_t i = 0; i < count; i += threads > 1 ? 2 : 1) {
        std::future<ProcessedRock> next;
        if (threads > 1 && i + 1 < count)
            next = std::async(std::launch::async,
                              [=] { return processRock(i + 1, triangles, i + 1); });
        ProcessedRock rock = processRock(i, triangles, i);
        if (auto e = use(i, rock)) return e; // (the future's destructor waits for its rock)
        if (next.valid()) {
            ProcessedRock second = next.get();
            if (auto e = use(i + 1, second)) return e;
        }
    }
    return std::nullopt;
}

// An unlinked temporary file beside the output, holding the rocks' MDET payloads from their
// making (with the proxies, before the scene is written) until their place in the file (after the
// smallest texel levels): on disk rather than in memory, so RSS does not grow with the rock
// count, and no rock is processed twice. It vanishes when closed, even if the program dies.
class SpillFile {
public:
    SpillFile() = default;
    SpillFile(const SpillFile&) = delete;
    SpillFile& operator=(const SpillFile&) = delete;
    ~SpillFile() {
        if (mFile) std::fclose(mFile);
    }
    // False (errno set) if no file can be made in the directory of `output`.
    bool open(const std::string& output) {
        std::filesystem::path dir = std::filesystem::path(output).parent_path();
        std::string name = (dir.empty() ? std::string(".") : dir.string()) +
                           "/.pnb-make-stream-scene-rocks.XXXXXX";
        int fd = ::mkstemp(name.data());
        if (fd < 0) return false;
        ::unlink(name.c_str());
        mFile = ::fdopen(fd, "w+b");
        if (!mFile) ::close(fd);
        return mFile != nullptr;
    }
    uint64_t size() const { return mSize; }
    bool append(std::span<const std::byte> bytes) {
        if (std::fwrite(bytes.data(), 1, bytes.size(), mFile) != bytes.size()) return false;
        mSize += bytes.size();
        return true;
    }
    bool read(uint64_t offset, uint64_t bytes, std::vector<std::byte>& out) {
        out.resize(bytes);
        return ::fseeko(mFile, off_t(offset), SEEK_SET) == 0 &&
               std::fread(out.data(), 1, out.size(), mFile) == out.size();
    }

private:
    std::FILE* mFile = nullptr;
    uint64_t mSize = 0;
};

// [SECTION] the texel pipeline: one producer thread, the writer on the main thread

// Produces the TMIP payloads in file order. With threads = 2 the next payload is built while the
// current one is written; two buffers circulate, so memory stays at two level-0 payloads.
class MipProducer {
public:
    MipProducer(uint32_t textures, uint32_t textureSize, unsigned threads)
        : mTextures(textures), mTextureSize(textureSize), mLevels(mipCountFor(textureSize)),
          mThreaded(threads > 1) {
        mFree.resize(2);
        if (mThreaded) mThread = std::thread([this] { run(); });
    }
    ~MipProducer() {
        {
            std::lock_guard lock(mMutex);
            mStop = true;
        }
        mCv.notify_all();
        if (mThread.joinable()) mThread.join();
    }
    uint64_t total() const { return uint64_t(mTextures) * mLevels; }

    // The next payload in order (coarsest level of texture 0 first); give it back with recycle().
    MipJob next() {
        if (!mThreaded) {
            MipJob job = std::move(mFree.front());
            mFree.pop_front();
            fill(job, mNext++);
            return job;
        }
        std::unique_lock lock(mMutex);
        mCv.wait(lock, [&] { return !mReady.empty(); });
        MipJob job = std::move(mReady.front());
        mReady.pop_front();
        mCv.notify_all();
        return job;
    }
    void recycle(MipJob job) {
        std::lock_guard lock(mMutex);
        mFree.push_back(std::move(job));
        mCv.notify_all();
    }

private:
    void fill(MipJob& job, uint64_t n) {
        job.level = mLevels - 1 - uint32_t(n / mTextures);
        job.texture = uint32_t(n % mTextures);
        job.size = std::max(1u, mTextureSize >> job.level);
        buildMip(job, mTextureSize, mSrgb);
    }
    void run() {
        for (uint64_t n = 0; n < total(); ++n) {
            MipJob job;
            {
                std::unique_lock lock(mMutex);
                mCv.wait(lock, [&] { return mStop || !mFree.empty(); });
                if (mStop) return;
                job = std::move(mFree.front());
                mFree.pop_front();
            }
            fill(job, n);
            {
                std::lock_guard lock(mMutex);
                mReady.push_back(std::move(job));
            }
            mCv.notify_all();
        }
    }

    uint32_t mTextures, mTextureSize, mLevels;
    bool mThreaded;
    SrgbEncoder mSrgb;
    uint64_t mNext = 0;
    std::mutex mMutex;
    std::condition_variable mCv;
    std::deque<MipJob> mFree, mReady;
    bool mStop = false;
    std::thread mThread;
};

// [SECTION] how a stage says why the run stops

// "internal error: WHAT" on stderr; the exit code that goes with it.
int internalError(const std::string& what) {
    std::fprintf(stderr, "pnb-make-stream-scene: internal error: %s\n", what.c_str());
    return kExitInternal;
}

// "cannot write OUTPUT: WHY" on stderr; the exit code that goes with it.
int writeError(const Options& o, const std::string& why) {
    std::fprintf(stderr, "pnb-make-stream-scene: cannot write %s: %s\n", o.output.c_str(),
                 why.c_str());
    return kExitWrite;
}

// [SECTION] the street: how many panels, where each stands

// --textures, or as many textures as make the file at least --size with the texel chunks alone
// (ceil(size / one texture's chain)). Nullopt, the reason printed, past 100000.
std::optional<uint32_t> textureCount(const Options& o, uint32_t levels) {
    if (o.textures != 0) return o.textures;
    uint64_t perTexture = 0;
    for (uint32_t l = 0; l < levels; ++l) {
        uint32_t s = std::max(1u, o.textureSize >> l);
        perTexture += tmipFileBytes(s, s);
    }
    uint64_t n = (o.sizeBytes + perTexture - 1) / perTexture;
    if (n > 100000) {
        std::fprintf(stderr,
                     "pnb-make-stream-scene: --size needs %llu textures of %u texels, more "
                     "than 100000; use a larger --texture-size\n",
                     (unsigned long long)n, o.textureSize);
        return std::nullopt;
    }
    return uint32_t(std::max<uint64_t>(1, n));
}

// Panel i stands on the left (even i) or right (odd i) of the street, rows `spacing` apart,
// turned 35 degrees towards the oncoming camera (and the sun behind it). Panel i's texture,
// material and mesh are all number i; the ground comes after the panels.
struct StreetLayout {
    uint32_t panels = 0, rows = 0;
    float spacing = 0;
    float streetEnd = 0; // z of the last row and a bit
    float halfStreet = 5.0f;
    Vec3 panelHalf{0.125f, 2.0f, 2.0f};
    float panelY = 2.25f;

    float panelYaw(uint32_t i) const { return (i % 2 == 0 ? -1.0f : 1.0f) * 0.6108652f; }
    Vec3 panelCentre(uint32_t i) const {
        float side = (i % 2 == 0) ? -1.0f : 1.0f;
        return Vec3{side * (halfStreet + panelHalf.x), panelY, -float(i / 2 + 1) * spacing};
    }
};

StreetLayout streetLayout(uint32_t panels, float spacing) {
    StreetLayout street;
    street.panels = panels;
    street.rows = (panels + 1) / 2;
    street.spacing = spacing;
    street.streetEnd = -float(street.rows) * spacing - spacing;
    return street;
}

// [SECTION] the scene's objects, in the order their strings are interned (the file's order)

void describeScene(SceneBuilder& b) {
    Scene& s = b.scene;
    s.info.name = b.intern("stream-street");
    s.info.generator = b.intern("pnb-make-stream-scene");
    s.info.source = b.intern("procedural");
    s.info.metersPerUnit = 1.0f;
}

// A material per panel (its own texture), then the ground's, each with the program the
// converter's planner gives it; the programs' shaders go into the scene first.
std::optional<int> addMaterialsAndPrograms(const Options& o, uint32_t panels, SceneBuilder& b) {
    std::vector<Material> materials;
    std::vector<converter::MaterialFeatures> features;
    for (uint32_t i = 0; i < panels; ++i) {
        Material m;
        m.name = b.intern("panel" + std::to_string(i));
        m.metallicFactor = 0.0f;
        m.roughnessFactor = 0.7f;
        m.castsShadows = o.shadows;
        m.textures[size_t(TextureSlotKind::BaseColor)].texture = i;
        materials.push_back(m);
        converter::MaterialFeatures f;
        f.baseColorMap = true;
        f.uv0 = true;
        features.push_back(f);
    }
    Material ground;
    ground.name = b.intern("ground");
    ground.baseColorFactor = {0.35f, 0.35f, 0.33f, 1.0f};
    ground.metallicFactor = 0.0f;
    ground.roughnessFactor = 0.9f;
    ground.castsShadows = o.shadows;
    materials.push_back(ground);
    features.push_back({});

    converter::SceneShaderNeeds needs;
    needs.shadows = o.shadows;
    converter::ShaderPlan plan = converter::planShaders(materials, features, needs);
    if (auto r = converter::appendShaderPrograms(plan, converter::builtinShaderFiles(), b); !r) {
        std::fprintf(stderr, "pnb-make-stream-scene: %s\n", r.error().message.c_str());
        return kExitInternal;
    }
    for (size_t i = 0; i < materials.size(); ++i) {
        materials[i].program = plan.materialProgram[i];
        b.scene.materials.push_back(materials[i]);
    }
    return std::nullopt;
}

// The panels' textures: RGBA8 sRGB, a full chain of `levels` (their texels are written later).
void addTextures(const Options& o, uint32_t panels, uint32_t levels, SceneBuilder& b) {
    for (uint32_t i = 0; i < panels; ++i) {
        TextureDesc t;
        t.name = b.intern("panel" + std::to_string(i) + ".basecolor");
        t.format = TextureFormat::RGBA8;
        t.colorSpace = ColorSpace::Srgb;
        t.width = t.height = o.textureSize;
        t.mipCount = levels;
        t.wrapU = t.wrapV = Wrap::ClampToEdge;
        b.scene.textures.push_back(t);
    }
}

// One box per panel (its own material), then the ground: 60 m wide, from z = 30 (behind the
// camera's start) to 30 m past the street's end.
void addPanelAndGroundMeshes(const StreetLayout& street, SceneBuilder& b) {
    const MeshData box = makeBox(street.panelHalf);
    for (uint32_t i = 0; i < street.panels; ++i)
        b.scene.meshes.push_back(toMesh(b, "panel" + std::to_string(i), box, i));
    const MeshData groundData = makeGround(-30.0f, 30.0f, 30.0f, street.streetEnd - 30.0f);
    b.scene.meshes.push_back(toMesh(b, "ground", groundData, street.panels));
}

// [SECTION] rocks (--lod-rocks): proxies in the scene, details in the spill file

struct Rock {
    uint32_t mesh = 0;
    bool detailed = false;                    // has levels: MESH is its proxy, MDET its detail
    uint64_t spillOffset = 0, spillBytes = 0; // its MDET payload in the spill file
    Vec3 position{0, 0, 0};
};

// The rocks, where their details wait, and their triangle counts for the summary. Lives until
// the file is written: `undetailed` holds the bytes that a rock without levels' mesh views.
struct Rocks {
    SpillFile spill;
    std::vector<Rock> rocks;
    std::vector<uint64_t> trianglesByLevel; // all rocks (index 0: full detail)
    uint64_t proxyTriangles = 0;
    std::deque<converter::ProcessedMesh> undetailed; // the rare rock without levels, kept whole
};

// On the ground in front of panel i's street face, towards its end nearer the oncoming camera,
// sunk a little (by the rock's own lowest point) so it stands rather than touches.
Vec3 rockPosition(const StreetLayout& street, uint32_t i, const Aabb& rockBounds) {
    const float side = (i % 2 == 0) ? -1.0f : 1.0f;
    const float c = std::cos(street.panelYaw(i)), sn = std::sin(street.panelYaw(i));
    const Vec3 face{-side * c, 0, side * sn}, along{sn, 0, c};
    Vec3 position = add(street.panelCentre(i), add(scale(face, 1.4f), along));
    position.y = -0.85f * rockBounds.min.y;
    return position;
}

// Rock i (processed) into the scene: with levels, its coarse proxy as its mesh and its detail's
// MDET payload appended to the spill file; without, the whole rock as its mesh.
std::optional<int> addRock(const Options& o, const StreetLayout& street, uint32_t i,
                           ProcessedRock& pm, SceneBuilder& b, Rocks& rocks) {
    if (!pm) return internalError("rock " + std::to_string(i) + ": " + pm.error().message);
    Scene& s = b.scene;
    Rock r;
    r.mesh = uint32_t(s.meshes.size());
    Mesh full = converter::toContainerMesh(*pm, b.intern("rock" + std::to_string(i)));
    for (const Submesh& sm : full.submeshes) {
        if (rocks.trianglesByLevel.size() <= sm.lod) rocks.trianglesByLevel.resize(sm.lod + 1u);
        rocks.trianglesByLevel[sm.lod] += sm.indexCount / 3;
    }
    r.detailed = hasLevelChains(full);
    if (r.detailed) {
        s.meshes.push_back(buildCoarseProxy(full, b));
        MeshDetail d{r.mesh, full};
        if (Status st = validateMeshDetail(s, d, i); !isOk(st)) return internalError(st.message);
        std::vector<std::byte> payload = encodeChunk(d);
        r.spillOffset = rocks.spill.size();
        r.spillBytes = payload.size();
        if (!rocks.spill.append(payload)) {
            const int err = errno; // before any allocation below
            return writeError(o, std::string("temporary file: ") + std::strerror(err));
        }
    } else {
        rocks.undetailed.push_back(std::move(*pm)); // moving keeps the bytes `full` views
        s.meshes.push_back(full);
    }
    for (const Submesh& sm : s.meshes.back().submeshes)
        rocks.proxyTriangles += sm.indexCount / 3;
    r.position = rockPosition(street, i, full.bounds);
    rocks.rocks.push_back(r);
    return std::nullopt;
}

// With --lod-rocks, a rock beside every panel, after the ground's mesh: each through the
// converter's mesh pipeline, its coarse proxy kept in the scene, its detail's MDET payload in
// the spill file until its place in the file comes (after every texture's smallest level).
// Memory holds one or two rocks' details at a time, whatever the count. Rock i uses panel i's
// material: no texels of its own.
std::optional<int> addRocks(const Options& o, const StreetLayout& street, SceneBuilder& b,
                            Rocks& rocks) {
    if (!o.lodRocks) return std::nullopt;
    if (!rocks.spill.open(o.output)) {
        const int err = errno; // before any allocation below
        return writeError(o, std::string("no temporary file beside it: ") + std::strerror(err));
    }
    return forEachRock(
        street.panels, o.rockTriangles, o.threads,
        [&](uint32_t i, ProcessedRock& pm) { return addRock(o, street, i, pm, b, rocks); });
}

// [SECTION] the sun, the camera, the nodes and the camera path

// The sun (directional) and the one camera; their nodes come after the objects' nodes.
void addSunAndCamera(const Options& o, SceneBuilder& b) {
    Light sun;
    sun.name = b.intern("sun");
    sun.type = LightType::Directional;
    sun.color = {1.0f, 0.97f, 0.92f};
    sun.intensity = 3.0f;
    sun.castsShadows = o.shadows;
    b.scene.lights.lights.push_back(sun);
    Camera cam;
    cam.name = b.intern("camera");
    cam.yfovRadians = 0.9f;
    cam.znear = 0.1f;
    cam.zfar = 0.0f;
    b.scene.cameras.cameras.push_back(cam);
}

// Adds `n` and grows the scene's bounds by its world box.
void addBoundedNode(Scene& s, const Node& n) {
    s.nodes.nodes.push_back(n);
    s.info.bounds.grow(n.worldBounds.min);
    s.info.bounds.grow(n.worldBounds.max);
}

// A node per panel (mesh i, turned and placed on its side of the street), then the ground's.
void addPanelAndGroundNodes(const StreetLayout& street, SceneBuilder& b) {
    Scene& s = b.scene;
    for (uint32_t i = 0; i < street.panels; ++i) {
        Node n;
        n.name = b.intern("panel" + std::to_string(i));
        n.translation = street.panelCentre(i);
        n.rotation = yawRotation(street.panelYaw(i));
        n.mesh = i;
        n.worldBounds = placed(s.meshes[i].bounds, street.panelYaw(i), n.translation);
        n.worldSphere = {add(s.meshes[i].boundingSphere.center, n.translation),
                         s.meshes[i].boundingSphere.radius};
        addBoundedNode(s, n);
    }
    const uint32_t ground = street.panels;
    Node n;
    n.name = b.intern("ground");
    n.mesh = ground;
    n.worldBounds = s.meshes[ground].bounds;
    n.worldSphere = s.meshes[ground].boundingSphere;
    addBoundedNode(s, n);
}

// A node per rock, named as its mesh, moved (not turned) to its place.
void addRockNodes(const Rocks& rocks, Scene& s) {
    for (const Rock& r : rocks.rocks) {
        const Mesh& m = s.meshes[r.mesh];
        Node n;
        n.name = m.name;
        n.translation = r.position;
        n.mesh = r.mesh;
        n.worldBounds = {add(m.bounds.min, n.translation), add(m.bounds.max, n.translation)};
        n.worldSphere = {add(m.boundingSphere.center, n.translation), m.boundingSphere.radius};
        addBoundedNode(s, n);
    }
}

// The sun's node: 40 degrees up, from behind the camera's start and a little to the right, so
// both rows of panels are lit from the front and cast their shadows down the street.
void addSunNode(SceneBuilder& b) {
    const float elevation = 0.6981317f, azimuth = 0.1745329f;
    const Vec3 toSun{std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                     std::cos(elevation) * std::cos(azimuth)};
    Node n;
    n.name = b.intern("sun");
    n.translation = scale(toSun, 100.0f);
    n.rotation = rotationBetween({0, 0, -1}, scale(toSun, -1));
    n.light = 0;
    b.scene.nodes.nodes.push_back(n);
}

// The path "street": eye height down the middle of the street, a key per row (and one before and
// after), the yaw swaying gently towards one side then the other; then the camera's node, at
// the path's first key.
void addCameraPath(const Options& o, const StreetLayout& street, SceneBuilder& b) {
    Scene& s = b.scene;
    CameraPath path;
    path.name = b.intern("street");
    path.interpolation = Interpolation::CatmullRom;
    const float eye = 1.7f, startZ = 2.0f;
    for (uint32_t k = 0; k <= street.rows + 1; ++k) {
        float z = startZ - float(k) * o.spacing;
        CameraKey key;
        key.timeSeconds = (startZ - z) / o.speed;
        key.position = {0, eye, z};
        key.rotation = yawRotation(0.18f * std::sin(float(k) * 0.45f));
        key.yfovRadians = s.cameras.cameras.front().yfovRadians;
        path.keys.push_back(key);
    }
    s.cameraPaths.push_back(path);
    Node n;
    n.name = b.intern("camera");
    n.translation = path.keys.front().position;
    n.rotation = path.keys.front().rotation;
    n.camera = 0;
    s.nodes.nodes.push_back(n);
}

// [SECTION] writing: the scene, then the texel chunks in streaming order

// What the writing leaves for the summary.
struct Written {
    uint64_t fileBytes = 0;
    uint64_t lastNonZeroEnd = 0; // where the level-0 TMIPs begin
    uint32_t details = 0;        // MDET chunks written
    std::chrono::steady_clock::time_point commitStart, end;
};

// The rocks' details, from the spill file, in rock order.
std::optional<int> writeRockDetails(const Options& o, Rocks& rocks, Writer& writer,
                                    uint32_t& details) {
    std::vector<std::byte> payload;
    for (const Rock& r : rocks.rocks) {
        if (!r.detailed) continue;
        if (!rocks.spill.read(r.spillOffset, r.spillBytes, payload)) {
            const int err = errno; // before any allocation below
            return writeError(o, std::string("cannot read back the temporary file: ") +
                                     std::strerror(err));
        }
        if (Status st = writer.addChunk(tags::kMeshDetail, ChunkTraits<MeshDetail>::version,
                                        payload, ChunkTraits<MeshDetail>::compression);
            !isOk(st))
            return writeError(o, st.message);
        ++details;
    }
    return std::nullopt;
}

// Texels: every texture's coarsest level, then the rocks' details (FORMAT.md §4.1: after every
// smallest level, before any larger one, as writeScene places them), then the next level of
// every texture, ..., every texture's level 0 last.
std::optional<int> writeTexelsAndDetails(const Options& o, uint32_t panels, Rocks& rocks,
                                         Writer& writer, Written& written) {
    MipProducer producer(panels, o.textureSize, o.threads);
    for (uint64_t n = 0; n < producer.total(); ++n) {
        MipJob job = producer.next();
        if (job.payload.size() <= 4096 && !checkPayload(job))
            return internalError("TMIP layout differs from encodeChunk");
        if (Status st =
                writer.addChunk(tags::kTextureMip, ChunkTraits<TextureMip>::version, job.payload);
            !isOk(st))
            return writeError(o, st.message);
        if (job.level > 0) written.lastNonZeroEnd = writer.size();
        producer.recycle(std::move(job));
        if (n + 1 == panels)
            if (auto e = writeRockDetails(o, rocks, writer, written.details)) return e;
    }
    return std::nullopt;
}

// The whole file: the scene's chunks (writeScene), the texels and details, the commit.
std::optional<int> writeContainer(const Options& o, const Scene& s, uint32_t panels, Rocks& rocks,
                                  Written& written) {
    WriteOptions wo;
    wo.checksums = o.checksums;
    auto writer = Writer::create(o.output, wo);
    if (!writer) return writeError(o, writer.error().message);
    if (Status st = writeScene(*writer, s); !isOk(st)) return writeError(o, st.message);
    if (auto e = writeTexelsAndDetails(o, panels, rocks, *writer, written)) return e;
    written.commitStart = std::chrono::steady_clock::now();
    if (Status st = writer->commit(); !isOk(st)) return writeError(o, st.message);
    written.fileBytes = writer->size();
    written.end = std::chrono::steady_clock::now();
    return std::nullopt;
}

// The summary line (and the rocks' line with --lod-rocks); `start` is when run began.
void printSummary(const Options& o, const Scene& s, uint32_t panels, uint32_t levels,
                  const Rocks& rocks, const Written& w,
                  std::chrono::steady_clock::time_point start) {
    double seconds = std::chrono::duration<double>(w.end - start).count();
    double commitSeconds = std::chrono::duration<double>(w.end - w.commitStart).count();
    std::printf("wrote %s: %llu bytes, %u textures of %ux%u (%u levels), %zu chunks; "
                "level-0 TMIPs from byte %llu (%.1f%% of the file); "
                "%.2f s (commit and fsync %.2f s), %.0f MB/s\n",
                o.output.c_str(), (unsigned long long)w.fileBytes, panels, o.textureSize,
                o.textureSize, levels,
                3 + s.shaders.size() + s.programs.size() + s.textures.size() + s.materials.size() +
                    s.meshes.size() + 3 + s.cameraPaths.size() + size_t(panels) * levels +
                    w.details,
                (unsigned long long)w.lastNonZeroEnd,
                100.0 * double(w.fileBytes - w.lastNonZeroEnd) / double(w.fileBytes), seconds,
                commitSeconds, double(w.fileBytes) / 1e6 / seconds);
    if (rocks.rocks.empty()) return;
    std::string perLevel;
    for (uint64_t t : rocks.trianglesByLevel)
        perLevel += (perLevel.empty() ? "" : " / ") + std::to_string(t);
    std::printf("  %zu rocks (%u MDET), triangles by level, all rocks: %s; proxies %llu\n",
                rocks.rocks.size(), w.details, perLevel.c_str(),
                (unsigned long long)rocks.proxyTriangles);
}

} // namespace

// [SECTION] main

// The scene in the order its strings and objects enter it (that order is the file's), then
// its writing. Every stage returns an exit code when it stops the run.
int run(const Options& o) {
    const auto start = std::chrono::steady_clock::now();
    const uint32_t levels = mipCountFor(o.textureSize);
    const std::optional<uint32_t> panels = textureCount(o, levels);
    if (!panels) return kExitUsage;
    const StreetLayout street = streetLayout(*panels, o.spacing);

    SceneBuilder b;
    describeScene(b);
    if (auto e = addMaterialsAndPrograms(o, *panels, b)) return *e;
    addTextures(o, *panels, levels, b);
    addPanelAndGroundMeshes(street, b);
    Rocks rocks; // lives until the file is written: the details wait in its spill file
    if (auto e = addRocks(o, street, b, rocks)) return *e;
    addSunAndCamera(o, b);
    addPanelAndGroundNodes(street, b);
    addRockNodes(rocks, b.scene);
    addSunNode(b);
    addCameraPath(o, street, b);
    if (Status st = validateScene(b.scene); !isOk(st)) return internalError(st.message);

    Written written;
    if (auto e = writeContainer(o, b.scene, *panels, rocks, written)) return *e;
    if (!o.quiet) printSummary(o, b.scene, *panels, levels, rocks, written, start);
    return 0;
}

} // namespace stream_scene
