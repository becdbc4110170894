// Streaming playback's GL side (scene_stream.h): the first frame's upload, then per frame the
// residency plan, the staged texel uploads and the publication of complete levels.
#include "pnb_player/scene_stream.h"

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <optional>

#include <epoxy/gl.h>

#include "lod_select.h"
#include "mip_need.h"
#include "pnb_player/settings.h"
#include "load/scene_upload.h"
#include "load/stream_loader.h"
#include "gl/stream_ring.h"
#include "texture_residency.h"
#include "load/upload.h"

namespace pnb::player {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// One surface that samples a texture: its level-0 texels per world unit (mip_need.h).
struct TextureUse {
    uint32_t item = 0;
    double texelsPerUnit = 0;
};

// The level chain each item of a mesh draws (DrawItem::firstLevel ..): kept for the proxy and
// for the detail, so that swapping one for the other again appends no levels.
struct ItemLevels {
    uint32_t item = 0, firstLevel = 0, levelCount = 0;
    uint64_t triangles = 0;
};

std::vector<ItemLevels> itemLevelsOf(const GpuScene& gpu, uint32_t mesh) {
    std::vector<ItemLevels> out;
    for (uint32_t i = 0; i < gpu.items.size(); ++i)
        if (const DrawItem& item = gpu.items[i]; item.mesh == mesh)
            out.push_back({i, item.firstLevel, item.levelCount, item.triangles});
    return out;
}

void setItemLevels(GpuScene& gpu, const std::vector<ItemLevels>& levels) {
    for (const ItemLevels& l : levels) {
        DrawItem& item = gpu.items[l.item];
        gpu.triangles = gpu.triangles - item.triangles + l.triangles;
        item.firstLevel = l.firstLevel;
        item.levelCount = l.levelCount;
        item.triangles = l.triangles;
    }
    ++gpu.materialsVersion; // renderers rebuild their caster lists
}

// Bytes of `rows` rows (block rows for compressed formats: 4 pixels) of one face of a level.
uint64_t rowBytes(const TextureDesc& d, uint32_t level, uint32_t rows) {
    return textureLevelSizeBytes(d.format, std::max(d.width >> level, 1u), rows, 1);
}
// Rows per upload unit: a block row (4) for block-compressed formats, whose 4x1 and 4x4 images
// are the same one block; else 1.
uint32_t rowUnit(const TextureDesc& d) {
    return textureLevelSizeBytes(d.format, 4, 1, 1) == textureLevelSizeBytes(d.format, 4, 4, 1) ? 4 : 1;
}
uint64_t alignUp(uint64_t v, uint64_t a) { return (v + a - 1) / a * a; }
constexpr uint64_t kStagingAlignment = 16;

} // namespace

struct SceneStream::Impl {
    GpuScene* gpu = nullptr;
    std::unique_ptr<StreamLoader> loader;
    const Scene* scene = nullptr; // the loader's, read-only
    // Textures 0..textureCount-1, then the meshes with levels whose detail has been seen, as
    // two-level chains: level 1 the proxy (always resident), level 0 the detail beside it.
    std::vector<TextureResidency> residency;
    uint32_t textureCount = 0;
    uint64_t textureFullBytes = 0; // every texture's whole chain
    struct Pending {
        // Levels valid - 1, valid - 2, ... that have arrived (their bytes hold the loader's
        // read-ahead back until uploaded or dropped); the front is being uploaded.
        std::deque<Arrival> levels;
        uint32_t face = 0, row = 0; // upload progress of the front
        bool requested = false;     // a re-read of valid - 1 was asked for
        bool lost = false;          // needed again, but the input cannot be re-read
        uint32_t nextLevel(uint32_t valid) const { return levels.empty() ? valid : levels.back().mip.level; }
    };
    std::deque<Pending> pending; // deque: Pending holds a deque, which cannot move noexcept
    // Meshes' full detail (MDET) that arrived, in order; the front is being uploaded into its
    // own new buffer, which replaces the proxy's when complete.
    struct PendingMesh {
        Arrival data;
        std::optional<GpuMesh> gpu;
        MeshLayout layout;
        uint64_t done = 0; // bytes copied, over the layout's segments in order
    };
    std::deque<PendingMesh> meshes;
    struct MeshChain {
        uint32_t mesh = 0;
        float coarsestError = 0;       // the proxy's error against the detail, mesh units
        std::optional<GpuMesh> parked; // the proxy, while the detail is drawn
        std::vector<ItemLevels> proxyLevels, detailLevels; // detailLevels: once it was drawn
        std::vector<uint32_t> items;   // the draw items of the mesh
        bool requested = false, lost = false;
    };
    std::vector<MeshChain> meshChains;    // residency[textureCount + i]
    std::vector<int32_t> chainOfMesh;     // per mesh: its index in meshChains, or -1
    // The chain of a mesh whose detail has been seen.
    TextureResidency& meshResidency(uint32_t mesh) { return residency[textureCount + uint32_t(chainOfMesh[mesh])]; }
    // Per mesh chain: whether its detail waits in `meshes` (one pass over the queue, not one
    // per chain).
    std::vector<bool> detailsQueued() const {
        std::vector<bool> queued(meshChains.size());
        for (const PendingMesh& pm : meshes) queued[uint32_t(chainOfMesh[pm.data.mesh->mesh])] = true;
        return queued;
    }
    uint64_t meshChainBytes() const {
        uint64_t sum = 0;
        for (size_t i = 0; i < meshChains.size(); ++i) {
            const TextureResidency& r = residency[textureCount + i];
            sum += r.bytesFrom(r.allocated);
        }
        return sum;
    }
    std::vector<std::vector<TextureUse>> uses; // per texture
    std::vector<bool> everyLevel;              // per texture: the environment's, needed whole
    StreamRing staging;
    uint64_t frame = 0;
    // A budget: storage follows the view's needs, and only levels with storage are kept as they
    // arrive. None: storage follows the texels, a chain growing as its next levels arrive.
    bool budgeted = false;
    GLint unpackAlignment = 1;

    void setBaseLevel(uint32_t t) {
        const GpuTexture& tex = gpu->textures[t];
        const uint32_t valid = std::min(residency[t].valid, tex.mipCount - 1);
        glTextureParameteri(tex.texture.id(), GL_TEXTURE_BASE_LEVEL, GLint(valid - tex.firstLevel));
        ++gpu->texelsVersion; // what a surface's colour samples may have changed (GI probes' cache)
    }

    // New storage for levels `first`.. of texture t; the complete levels both chains have are
    // copied on the GPU. When it shrinks (an eviction), arrived levels finer than `first` are
    // dropped (and their upload, if under way); a growth keeps them for the next frames.
    PlayResult<Done> reallocate(uint32_t t, uint32_t first) {
        const TextureDesc& desc = scene->textures[t];
        GpuTexture& old = gpu->textures[t];
        auto fresh = createTexture(desc, t, first);
        if (!fresh) return fresh.error();
        TextureResidency& r = residency[t];
        const GLenum target = desc.dimension == TextureDimension::Cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D;
        for (uint32_t level = std::max(r.valid, first); level < desc.mipCount; ++level)
            glCopyImageSubData(old.texture.id(), target, GLint(level - old.firstLevel), 0, 0, 0,
                               fresh->texture.id(), target, GLint(level - first), 0, 0, 0,
                               GLsizei(std::max(desc.width >> level, 1u)),
                               GLsizei(std::max(desc.height >> level, 1u)), GLsizei(desc.layers));
        if (epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic")) {
            GLfloat aniso = 1;
            glGetTextureParameterfv(old.texture.id(), GL_TEXTURE_MAX_ANISOTROPY_EXT, &aniso);
            glTextureParameterf(fresh->texture.id(), GL_TEXTURE_MAX_ANISOTROPY_EXT, aniso);
        }
        gpu->memory.textureBytes = gpu->memory.textureBytes - old.bytes + fresh->bytes;
        old = std::move(*fresh);
        const bool shrinks = first > r.allocated;
        r.allocated = first;
        r.valid = std::max(r.valid, first);
        Pending& p = pending[t];
        if (shrinks) // levels without storage now: read again if needed again
            while (!p.levels.empty() && p.levels.back().mip.level < first) p.levels.pop_back();
        if (p.levels.empty()) p.face = p.row = 0;
        setBaseLevel(t);
        return Done{};
    }

    // Takes a level that arrived: kept if it is the next one texture t can use, else dropped
    // (it can be read again from a file when needed).
    void accept(Arrival level) {
        if (level.mesh) {
            // Kept for the next plan if just seen, or if it has storage (then it is the detail
            // to upload); else skipped (read again when needed).
            const bool fresh = chainOfMesh[level.mesh->mesh] < 0;
            const uint32_t c = chainFor(*level.mesh);
            if (level.refetched) meshChains[c].requested = false;
            if (fresh || residency[textureCount + c].allocated == 0) meshes.push_back({std::move(level), std::nullopt, {}, 0});
            return;
        }
        const uint32_t t = level.mip.texture, l = level.mip.level;
        Pending& p = pending[t];
        if (level.refetched) p.requested = false;
        if (l + 1 == p.nextLevel(residency[t].valid) && (!budgeted || l >= residency[t].allocated))
            p.levels.push_back(std::move(level));
    }

    // The chain of the mesh `d` is the detail of, made when its first MDET arrives.
    uint32_t chainFor(const MeshDetail& d) {
        if (chainOfMesh[d.mesh] >= 0) return uint32_t(chainOfMesh[d.mesh]);
        MeshChain c;
        c.mesh = d.mesh;
        for (const Submesh& sm : d.detail.submeshes) c.coarsestError = std::max(c.coarsestError, sm.lodError);
        c.proxyLevels = itemLevelsOf(*gpu, d.mesh);
        for (const ItemLevels& l : c.proxyLevels) c.items.push_back(l.item);
        TextureResidency r;
        r.levelBytes = {meshLayout(d.detail).size, gpu->meshes[d.mesh].bytes};
        r.allocated = r.valid = r.wanted = 1;
        residency.push_back(std::move(r));
        meshChains.push_back(std::move(c));
        chainOfMesh[d.mesh] = int32_t(meshChains.size() - 1);
        return uint32_t(meshChains.size() - 1);
    }

    // Gives up mesh chain c's detail: the proxy is drawn again, an upload under way is dropped.
    void evictDetail(uint32_t c) {
        MeshChain& mc = meshChains[c];
        TextureResidency& r = residency[textureCount + c];
        std::erase_if(meshes, [&](const PendingMesh& pm) { return pm.data.mesh->mesh == mc.mesh; });
        if (r.valid == 0) {
            GpuScene& g = *gpu;
            g.memory.meshBytes -= g.meshes[mc.mesh].bytes;
            g.meshes[mc.mesh] = std::move(*mc.parked);
            mc.parked.reset();
            setItemLevels(g, mc.proxyLevels);
        }
        r.allocated = r.valid = 1;
    }

    // Copies the front mesh detail's bytes until `budget` is spent; when all are in, its buffer
    // replaces the proxy's and its items take its levels. True when it is complete.
    PlayResult<bool> uploadMeshBytes(uint64_t& budget, StreamFrameStats& f) {
        PendingMesh& pm = meshes.front();
        const MeshDetail& d = *pm.data.mesh;
        if (!pm.gpu) {
            auto m = uploadMesh(d.detail, d.mesh, false);
            if (!m) return m.error();
            pm.gpu = std::move(*m);
            pm.layout = meshLayout(d.detail);
        }
        uint64_t start = 0;
        for (const MeshLayout::Segment& seg : pm.layout.segments) {
            const uint64_t end = start + seg.bytes.size();
            while (pm.done < end) {
                // Whole 16-byte units of the budget, so the ring's aligned slices fit the frame's bytes.
                const uint64_t bytes = std::min(end - pm.done, budget / kStagingAlignment * kStagingAlignment);
                if (bytes == 0) return false;
                const uint64_t from = pm.done - start;
                std::byte* dst = nullptr;
                const size_t at = staging.allocate(bytes, dst);
                std::memcpy(dst, seg.bytes.data() + from, bytes);
                glCopyNamedBufferSubData(staging.buffer(), pm.gpu->buffer.id(), GLintptr(at),
                                         GLintptr(seg.offset + from), GLsizeiptr(bytes));
                pm.done += bytes;
                budget -= std::min(budget, alignUp(bytes, kStagingAlignment));
                f.uploadedBytes += bytes;
            }
            start = end;
        }
        // The proxy stays (parked) for when the detail is given up; GL orders the copies before
        // the frame's draws.
        GpuScene& g = *gpu;
        MeshChain& mc = meshChains[uint32_t(chainOfMesh[d.mesh])];
        g.memory.meshBytes += pm.gpu->bytes;
        mc.parked = std::move(g.meshes[d.mesh]);
        g.meshes[d.mesh] = std::move(*pm.gpu);
        if (mc.detailLevels.empty()) {
            replaceMeshLevels(g, d.mesh);
            mc.detailLevels = itemLevelsOf(g, d.mesh);
        } else {
            setItemLevels(g, mc.detailLevels);
        }
        meshResidency(d.mesh).valid = 0;
        meshes.pop_front();
        ++f.meshesCompleted;
        return true;
    }

    // Uploads rows of the front level until `budget` bytes are spent; true when it is complete.
    bool uploadRows(uint32_t t, uint64_t& budget, StreamFrameStats& f) {
        Pending& p = pending[t];
        const TextureDesc& desc = scene->textures[t];
        const TextureMip& mip = p.levels.front().mip;
        const uint32_t unit = rowUnit(desc);
        const uint64_t faceBytes = mip.data.size() / desc.layers;
        while (p.face < desc.layers) {
            const uint32_t left = mip.height - p.row;
            const uint64_t unitBytes = rowBytes(desc, mip.level, std::min(unit, mip.height));
            uint32_t rows = uint32_t(std::min<uint64_t>(left, budget / alignUp(unitBytes, kStagingAlignment) * unit));
            if (rows == 0) {
                if (f.uploadedBytes > 0) return false; // next frame
                rows = std::min(unit, left);           // a unit larger than the frame's bytes
            }
            const uint64_t offset = rowBytes(desc, mip.level, p.row);
            const uint64_t bytes = rowBytes(desc, mip.level, rows);
            std::byte* dst = nullptr;
            const size_t at = staging.allocate(bytes, dst);
            std::memcpy(dst, mip.data.data() + p.face * faceBytes + offset, bytes);
            uploadTextureRows(gpu->textures[t], desc, mip.level, p.face, p.row, rows,
                              reinterpret_cast<const void*>(uintptr_t(at)));
            f.uploadedBytes += bytes;
            budget -= std::min(budget, alignUp(bytes, kStagingAlignment));
            p.row += rows;
            if (p.row >= mip.height) {
                p.row = 0;
                ++p.face;
            }
        }
        residency[t].valid = mip.level;
        p.levels.pop_front();
        p.face = p.row = 0;
        setBaseLevel(t);
        ++f.levelsCompleted;
        return true;
    }
    // SceneStream::update's stages, in order.
    void chooseWantedLevels(const CameraState& camera, uint32_t height, const StreamOptions& options);
    PlayResult<Done> fitStorage(const StreamOptions& options, StreamStatus& st);
    bool takeArrivals(StreamStatus& st);
    PlayResult<Done> uploadWithinBudget(StreamOptions& options, StreamStatus& st);
    void summarise(StreamStatus& st, bool readDone);
};

SceneStream::SceneStream() : mImpl(std::make_unique<Impl>()) {}

SceneStream::~SceneStream() = default;

PlayResult<SceneStream::Opened> SceneStream::open(const std::string& path, const StreamOptions& options,
                                                  LoadStats* statsOut) {
    LoadStats stats;
    const auto start = Clock::now();
    Opened out;
    out.stream.reset(new SceneStream);
    SceneStream& s = *out.stream;
    Impl& im = *s.mImpl;
    s.mOptions = options;
    StreamLoader::Options lo;
    lo.verifyChecksums = options.verifyChecksums;
    lo.readAheadBytes = options.readAheadBytes;
    auto loader = StreamLoader::start(path, lo);
    if (!loader) return loader.error();
    im.loader = std::move(*loader);
    stats.openMs = msSince(start);

    auto phase = Clock::now();
    auto scene = im.loader->waitForScene();
    if (!scene) return scene.error();
    im.scene = *scene;
    stats.decodeMs = msSince(phase);

    // Storage: the smallest level, for the first frame; chains grow from there (update()).
    phase = Clock::now();
    im.budgeted = options.budgetBytes > 0;
    const Scene& sc = *im.scene;
    std::vector<uint32_t> firstLevels;
    for (const TextureDesc& d : sc.textures) {
        TextureResidency r;
        for (uint32_t l = 0; l < d.mipCount; ++l) r.levelBytes.push_back(textureLevelBytes(d, l));
        r.allocated = d.mipCount - 1;
        r.valid = d.mipCount;
        r.wanted = r.allocated;
        firstLevels.push_back(r.allocated);
        s.mStatus.fullBytes += r.bytesFrom(0);
        im.residency.push_back(std::move(r));
    }
    im.textureFullBytes = s.mStatus.fullBytes;
    im.pending.resize(sc.textures.size());
    im.textureCount = uint32_t(sc.textures.size());
    im.chainOfMesh.assign(sc.meshes.size(), -1);
    auto gpu = uploadSceneWithoutTexels(sc, firstLevels, false); // proxies: details stream in
    if (!gpu) return gpu.error();
    im.gpu = gpu->get();
    for (uint32_t t = 0; t < sc.textures.size(); ++t) im.setBaseLevel(t);

    // Which surfaces sample which texture, at how many texels per world unit. The environment's
    // textures are sampled in every direction, whatever the view: they need every level.
    im.uses.resize(sc.textures.size());
    im.everyLevel.assign(sc.textures.size(), false);
    if (sc.environment)
        for (uint32_t t : {sc.environment->radiance, sc.environment->specular, sc.environment->brdfLut})
            if (t != kNone) im.everyLevel[t] = true;
    for (uint32_t i = 0; i < im.gpu->items.size(); ++i) {
        const DrawItem& item = im.gpu->items[i];
        const Mesh& mesh = sc.meshes[item.containerMesh]; // a posed mesh is not the container's
        const Submesh& sm = mesh.submeshes[im.gpu->levels[item.firstLevel].submesh];
        double density = uvDensity(mesh, sm);
        if (!(density > 0)) density = uvDensityFromBounds(sm);
        for (const TextureSlot& slot : im.gpu->materials[item.material].desc.textures) {
            if (slot.texture == kNone) continue;
            const TextureDesc& d = sc.textures[slot.texture];
            const double scale = std::max({std::abs(double(slot.scale.x)), std::abs(double(slot.scale.y)), 1e-6});
            const double tpu = double(std::max(d.width, d.height)) * density * scale / std::max(item.worldScale, 1e-30);
            im.uses[slot.texture].push_back({i, tpu});
        }
    }

    // The first frame's texels: each texture's smallest level, straight from the loader.
    auto missing = [&] {
        for (uint32_t t = 0; t < im.textureCount; ++t)
            if (im.residency[t].valid == im.residency[t].mipCount()) return true;
        return false;
    };
    while (missing()) {
        im.loader->waitForLevel();
        std::vector<Arrival> levels = im.loader->take();
        // Damage after what the first frame needs is reported by update(), like any later.
        if (levels.empty()) {
            if (auto st = im.loader->status(); !st) return st.error();
            if (im.loader->forwardDone()) break; // a texture without texels
        }
        for (Arrival& level : levels) {
            if (level.mesh) {
                im.accept(std::move(level));
                continue;
            }
            const uint32_t t = level.mip.texture;
            TextureResidency& r = im.residency[t];
            if (r.valid < r.mipCount() || level.mip.level + 1 != r.valid) {
                // For the frames to come, if usable — while the read-ahead has room: a container
                // whose smallest levels come late (another writer's order) must still open.
                if (im.loader->queuedBytes() < options.readAheadBytes / 2) im.accept(std::move(level));
                continue;
            }
            uploadTextureMip(im.gpu->textures[t], sc.textures[t], level.mip);
            r.valid = level.mip.level;
            im.setBaseLevel(t);
            s.mStatus.uploadedBytes += level.mip.data.size();
        }
    }
    stats.uploadMs = msSince(phase);
    phase = Clock::now();
    if (auto r = compileNeededPrograms(sc, *im.gpu); !r) return r.error();
    stats.compileMs = msSince(phase);
    glFinish();
    stats.totalMs = msSince(start);
    stats.fileBytes = im.loader->fileBytes();
    stats.chunks = 0;
    s.mStatus.fileBytes = im.loader->fileBytes();
    s.mStatus.bytesRead = im.loader->bytesRead();
    s.mStatus.residentBytes = residentBytes(im.residency);
    s.mStatus.peakBytes = s.mStatus.residentBytes;
    s.mStatus.neededBytes = im.budgeted ? neededBytes(im.residency) : s.mStatus.fullBytes;
    if (statsOut) *statsOut = stats;
    out.scene = std::move(*gpu);
    return out;
}

void SceneStream::markFirstFrame() { mStatus.firstFrameBytesRead = mImpl->loader->bytesRead(); }

void StreamOptions::applySettings(const RenderSettings& settings) {
    budgetBytes = uint64_t(settings.streamBudgetMib) << 20;
    uploadBytesPerFrame = std::max<uint64_t>(uint64_t(double(settings.streamUploadMib) * 1048576.0), 1);
    lodThresholdPx = settings.lodThresholdPx;
    lodBias = settings.lodBias;
    lodForce = settings.lodForce;
}

void SceneStream::setLimits(const RenderSettings& settings) { mOptions.applySettings(settings); }

// The levels this view needs; without a budget, storage for the levels that have arrived.
void SceneStream::Impl::chooseWantedLevels(const CameraState& camera, uint32_t height, const StreamOptions& options) {
    budgeted = options.budgetBytes > 0;
    // Pixels per unit at distance 1 (perspective) or at any distance (orthographic: d = 1 below).
    const bool ortho = camera.projection == Projection::Orthographic;
    const double pixelScale = ortho ? lodPixelScaleOrthographic(std::abs(double(camera.ymag)), height)
                                    : lodPixelScale(camera.yfovRadians, height);
    for (uint32_t t = 0; t < textureCount; ++t) {
        TextureResidency& r = residency[t];
        if (!budgeted) {
            r.wanted = std::min(r.allocated, pending[t].nextLevel(r.valid));
            continue;
        }
        uint32_t want = everyLevel[t] ? 0 : r.mipCount() - 1;
        for (const TextureUse& u : uses[t]) {
            const DrawItem& item = gpu->items[u.item];
            const double d = lodDistance(ortho, camera.position, item.boundsMin, item.boundsMax);
            want = std::min(want, neededMipLevel(u.texelsPerUnit, d, pixelScale, r.mipCount()));
        }
        r.wanted = want;
    }
    // Meshes: the detail while the LOD rule would draw an item finer than the proxy (without a
    // budget: once it has arrived).
    const bool allDetail = options.lodForce >= 0 || options.lodBias < 0;
    std::vector<bool> queued = detailsQueued();
    for (uint32_t c = 0; c < meshChains.size(); ++c) {
        const MeshChain& mc = meshChains[c];
        TextureResidency& r = residency[textureCount + c];
        bool need = r.valid == 0 || queued[c];
        if (budgeted) {
            need = allDetail;
            for (uint32_t i = 0; i < mc.items.size() && !need; ++i) {
                const DrawItem& item = gpu->items[mc.items[i]];
                const double d = lodDistance(ortho, camera.position, item.boundsMin, item.boundsMax);
                const double px = double(mc.coarsestError) * item.worldScale * pixelScale / d;
                need = !(px <= double(options.lodThresholdPx)); // NaN (d = 0): needed
            }
        }
        r.wanted = need ? 0 : 1;
    }

}

// Storage: cut back and grow chains within the budget.
PlayResult<Done> SceneStream::Impl::fitStorage(const StreamOptions& options, StreamStatus& st) {
    // New storage per frame: what two frames of uploads fill (creating it costs frame time).
    const ResidencyPlan plan = planResidency(residency, options.budgetBytes, frame,
                                             2 * options.uploadBytesPerFrame);
    for (const ResidencyChange& c : plan.evictions) {
        const uint64_t before = residency[c.texture].bytesFrom(residency[c.texture].allocated);
        if (c.texture >= textureCount) evictDetail(c.texture - textureCount);
        else if (auto r = reallocate(c.texture, c.allocated); !r) return r.error();
        st.frame.evictedBytes += before - residency[c.texture].bytesFrom(c.allocated);
        ++st.frame.evictions;
    }
    for (const ResidencyChange& c : plan.growths) {
        if (c.texture >= textureCount) residency[c.texture].allocated = 0; // buffer made at upload
        else if (auto r = reallocate(c.texture, c.allocated); !r) return r.error();
        ++st.frame.growths;
    }
    st.peakBytes = std::max(st.peakBytes, plan.peakBytes);
    // Mesh details that arrived but were given no storage: skipped (read again when needed).
    std::erase_if(meshes, [&](const PendingMesh& pm) {
        return meshResidency(pm.data.mesh->mesh).allocated != 0;
    });

    return Done{};
}

// Levels read since the last frame; re-reads of levels the chains now have room for. Returns
// whether the loader has read the whole file.
bool SceneStream::Impl::takeArrivals(StreamStatus& st) {
    for (Arrival& level : loader->take()) accept(std::move(level));
    const bool readDone = loader->forwardDone();
    for (uint32_t t = 0; t < textureCount; ++t) {
        const TextureResidency& r = residency[t];
        Pending& p = pending[t];
        // The next level is wanted: storage waits for it (budget), or every level is (none).
        const bool wantsNext = budgeted ? r.allocated < r.valid : r.valid > 0;
        if (!wantsNext || !p.levels.empty() || p.requested || p.lost) continue;
        if (loader->request(t, r.valid - 1)) {
            p.requested = true;
            ++st.frame.refetches;
        } else if (readDone) {
            p.lost = true; // passed on a pipe: it will not come again
            ++st.lostLevels;
        }
    }
    const std::vector<bool> queued = detailsQueued(); // after the drops and arrivals above (new chains too)
    for (uint32_t c = 0; c < meshChains.size(); ++c) {
        MeshChain& mc = meshChains[c];
        const TextureResidency& r = residency[textureCount + c];
        if (r.allocated != 0 || r.valid == 0 || queued[c] || mc.requested || mc.lost) continue;
        if (loader->requestMeshDetail(mc.mesh)) {
            mc.requested = true;
            ++st.frame.refetches;
        } else if (readDone) {
            mc.lost = true;
            ++st.lostLevels;
        }
    }

    return readDone;
}

// Uploads, the textures furthest from what they need first, within the frame's upload bytes.
PlayResult<Done> SceneStream::Impl::uploadWithinBudget(StreamOptions& options, StreamStatus& st) {
    const Scene& sc = *scene;
    std::vector<uint32_t> order;
    for (uint32_t t = 0; t < pending.size(); ++t)
        if (!pending[t].levels.empty()) order.push_back(t);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return int64_t(residency[a].valid) - residency[a].wanted >
               int64_t(residency[b].valid) - residency[b].wanted;
    });
    if (!order.empty() || !meshes.empty()) {
        uint64_t largestUnit = 0;
        for (uint32_t t : order) {
            const TextureDesc& d = sc.textures[t];
            largestUnit = std::max(largestUnit, rowBytes(d, pending[t].levels.front().mip.level, rowUnit(d)));
        }
        // The frame's bytes, and one unit more: a unit larger than them still goes alone. A
        // stream.upload_mib the GPU cannot hold three frames of (4096 MiB: GL_OUT_OF_MEMORY,
        // then a crash) is halved until it fits, once, with a message.
        const uint64_t asked = options.uploadBytesPerFrame;
        while (!staging.reserve(options.uploadBytesPerFrame + alignUp(largestUnit, kStagingAlignment),
                                   kStagingAlignment)) {
            if (options.uploadBytesPerFrame <= (uint64_t(1) << 20))
                return PlayError{PlayErrorKind::Gl, "the GL cannot allocate even 1 MiB per frame of "
                                                    "texture upload staging: out of GPU memory"};
            options.uploadBytesPerFrame /= 2;
        }
        if (options.uploadBytesPerFrame != asked)
            std::fprintf(stderr, "pnb-play: stream.upload_mib=%.0f: the GPU cannot hold %d frames of "
                                 "upload staging that large; uploading %.0f MiB per frame instead\n",
                         double(asked) / 1048576.0, StreamRing::kSections,
                         double(options.uploadBytesPerFrame) / 1048576.0);
        staging.beginFrame();
        glGetIntegerv(GL_UNPACK_ALIGNMENT, &unpackAlignment);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, staging.buffer());
        uint64_t budget = options.uploadBytesPerFrame;
        // Meshes first: until its detail is in, a mesh is drawn as its coarse proxy.
        // (A detail that arrived after this frame's plan waits for the next one's.)
        while (budget >= kStagingAlignment && !meshes.empty() &&
               meshResidency(meshes.front().data.mesh->mesh).allocated == 0) {
            auto done = uploadMeshBytes(budget, st.frame);
            if (!done) return done.error();
            if (!*done) break;
        }
        // (A level that arrived after this frame's plan has storage from the next frame on.)
        auto hasStorage = [&](uint32_t t) {
            return pending[t].levels.front().mip.level >= residency[t].allocated;
        };
        for (uint32_t t : order)
            while (budget > 0 && !pending[t].levels.empty() && hasStorage(t))
                if (!uploadRows(t, budget, st.frame)) break;
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        glPixelStorei(GL_UNPACK_ALIGNMENT, unpackAlignment);
        staging.endFrame();
    }

    return Done{};
}

// The frame's figures into the totals, and whether the view (or the file) is complete.
void SceneStream::Impl::summarise(StreamStatus& st, bool readDone) {
    st.uploadedBytes += st.frame.uploadedBytes;
    st.evictedBytes += st.frame.evictedBytes;
    st.evictions += st.frame.evictions;
    st.refetches += st.frame.refetches;
    st.bytesRead = loader->bytesRead();
    st.readDone = readDone;
    st.residentBytes = residentBytes(residency);
    st.residentMeshBytes = meshChainBytes();
    st.fullBytes = textureFullBytes;
    for (uint32_t c = 0; c < meshChains.size(); ++c) st.fullBytes += residency[textureCount + c].bytesFrom(0);
    st.neededBytes = budgeted ? neededBytes(residency) : st.fullBytes;
    // Complete: with a budget, every level and detail the view needs is in (the rest of the file
    // may still be read); without one, every level of every texture and every detail, so the
    // whole file.
    st.meshesReplaced += st.frame.meshesCompleted;
    bool complete = (budgeted || readDone) && meshes.empty() && loader->meshDetailsDone();
    for (uint32_t t = 0; t < textureCount && complete; ++t)
        complete = pending[t].lost || residency[t].valid <= (budgeted ? residency[t].wanted : 0);
    for (uint32_t c = 0; c < meshChains.size() && complete; ++c)
        complete = meshChains[c].lost || residency[textureCount + c].valid <= residency[textureCount + c].wanted;
    st.complete = complete;
}

PlayResult<Done> SceneStream::update(const CameraState& camera, uint32_t width, uint32_t height) {
    (void)width;
    Impl& im = *mImpl;
    StreamStatus& st = mStatus;
    st.frame = {};
    if (auto r = im.loader->status(); !r) return r.error();
    ++im.frame;
    im.chooseWantedLevels(camera, height, mOptions);
    if (auto r = im.fitStorage(mOptions, st); !r) return r.error();
    const bool readDone = im.takeArrivals(st);
    if (auto r = im.uploadWithinBudget(mOptions, st); !r) return r.error();
    im.summarise(st, readDone);
    return Done{};
}

} // namespace pnb::player
