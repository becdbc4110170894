// Document::save: untouched chunks stay byte-identical, new programs and textures land where
// FORMAT.md §4.1 wants them, a kill at any point leaves the original intact, history survives a
// save, and a save costs about what a file copy does.

#include "../common/sanitizers.h"
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <cstdio>
#include <thread>

#include "editor_test_util.h"
#include "pnb/material_fields.h"
#include "pnb/scene_builder.h"
#include "pnb/writer.h"

namespace {

using namespace pnb;
using namespace pnb::editor;
using namespace pnb::editor::test;


// Chunks of one kind, in file order.
std::vector<const ChunkInfo*> ofKind(const Container& c, Tag tag) { return c.find(tag); }

bool sameStored(const Container& a, const ChunkInfo& ca, const Container& b, const ChunkInfo& cb) {
    auto sa = a.stored(ca), sb = b.stored(cb);
    if (!sa.ok() || !sb.ok()) return false;
    ChunkHeader ha = ca.header, hb = cb.header;
    ha.sequence = hb.sequence = 0;
    return encodeChunkHeader(ha) == encodeChunkHeader(hb) &&
           std::equal(sa->begin(), sa->end(), sb->begin(), sb->end());
}

int verifyWithInspect(const std::string& file) {
    std::string out;
    int rc = run(quote(PNB_INSPECT_EXE) + " --verify " + quote(file), &out);
    EXPECT_EQ(rc, 0) << out;
    return rc;
}

TEST(Save, UntouchedChunksStayByteIdentical) {
    TempDir dir;
    const std::string path = copyScene(dir, "terrain");
    auto doc = openDoc(path);
    ASSERT_TRUE(doc);
    const uint32_t edited = doc->materialCount() - 1;
    ASSERT_TRUE(isOk(doc->setField(edited, "roughness", "0.125")));
    const std::string out = dir.file("edited.pnb");
    auto stats = doc->save(out);
    ASSERT_TRUE(stats.ok()) << stats.error().describe();
    EXPECT_EQ(stats->chunksRewritten, 1u);
    EXPECT_EQ(stats->chunksAdded, 0u);
    EXPECT_EQ(doc->path(), out);
    EXPECT_FALSE(doc->dirty());

    Opened a = openScene(path), b = openScene(out);
    ASSERT_EQ(a.container->chunks().size(), b.container->chunks().size());
    EXPECT_EQ(stats->chunksCopied, a.container->chunks().size() - 1);
    EXPECT_EQ(stats->bytesWritten, b.container->bytes().size());
    uint32_t matl = 0, differing = 0;
    for (size_t i = 0; i < a.container->chunks().size(); ++i) {
        const ChunkInfo& ca = a.container->chunks()[i];
        const ChunkInfo& cb = b.container->chunks()[i];
        ASSERT_TRUE(ca.header.tag == cb.header.tag) << "chunk " << i;
        auto ba = chunkBytes(*a.container, ca), bb = chunkBytes(*b.container, cb);
        bool same = std::equal(ba.begin(), ba.end(), bb.begin(), bb.end());
        bool isEdited = ca.header.tag == tags::kMaterial && matl++ == edited;
        EXPECT_EQ(same, !isEdited) << "chunk " << i << " '" << ca.header.tag.str() << "'";
        differing += !same;
    }
    EXPECT_EQ(differing, 1u);
    EXPECT_EQ(getMaterialField(b.scene.materials[edited], "roughness"), "0.125");
    verifyWithInspect(out);
}

// A file from a newer writer (FORMAT.md 3.5: the next MATL version with an appended field): saving
// other edits copies that chunk as stored, appended field included; editing the newer material
// itself is refused by name instead of silently dropping the field.
TEST(Save, NewerChunkVersionsAreCopiedNeverRewrittenWithoutTheirFields) {
    TempDir dir;
    const std::string today = copyScene(dir, "terrain");
    const std::string future = dir.file("future.pnb");
    {
        Opened src = openScene(today);
        auto w = Writer::create(future);
        ASSERT_TRUE(w.ok());
        bool first = true;
        for (const ChunkInfo& c : src.container->chunks()) {
            if (c.header.tag == tags::kMaterial && first) {
                first = false;
                std::vector<std::byte> v2 = encodeChunk(src.scene.materials[0]);
                v2.insert(v2.end(), 4, std::byte{0x3F}); // an appended field of the next version
                ASSERT_TRUE(isOk(w->addChunk(tags::kMaterial, ChunkTraits<Material>::version + 1, v2)));
            } else {
                ASSERT_TRUE(isOk(w->copyChunk(*src.container, c)));
            }
        }
        ASSERT_TRUE(isOk(w->commit()));
    }
    auto doc = openDoc(future);
    ASSERT_TRUE(doc);
    ASSERT_GE(doc->materialCount(), 2u);
    ASSERT_TRUE(isOk(doc->setField(1, "roughness", "0.25")));
    const std::string other = dir.file("other_edit.pnb");
    auto stats = doc->save(other);
    ASSERT_TRUE(stats.ok()) << stats.error().describe();
    Opened a = openScene(future), b = openScene(other);
    const ChunkInfo& ca = *a.container->find(tags::kMaterial)[0];
    const ChunkInfo& cb = *b.container->find(tags::kMaterial)[0];
    EXPECT_EQ(cb.header.version, ChunkTraits<Material>::version + 1u);
    EXPECT_TRUE(sameStored(*a.container, ca, *b.container, cb));

    ASSERT_TRUE(isOk(doc->setField(0, "roughness", "0.5")));
    const std::string refused = dir.file("refused.pnb");
    auto r = doc->save(refused);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, FormatError::UnsupportedChunkVersion);
    EXPECT_NE(r.error().message.find("material 0 is chunk version " +
                                     std::to_string(ChunkTraits<Material>::version + 1)),
              std::string::npos)
        << r.error().message;
    EXPECT_FALSE(std::filesystem::exists(refused));
}

TEST(Save, DeferredOnlySceneGainsAForwardProgramAndSwitchingBackReusesTheGBufferOne) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    const auto original = readBytes(path);
    Opened before = openScene(path);
    for (uint32_t p = 0; p < before.scene.programs.size(); ++p)
        ASSERT_NE(before.scene.str(before.scene.programs[p].name), "forward") << "deferred only";
    const uint32_t box = materialIndex(before.scene, "box");
    const uint32_t gbuffer = before.scene.materials[box].program;

    auto doc = openDoc(path);
    ASSERT_TRUE(doc);
    ASSERT_TRUE(isOk(doc->setField(box, "shading_path", "forward")));
    auto stats = doc->save();
    ASSERT_TRUE(stats.ok()) << stats.error().describe();
    EXPECT_EQ(stats->chunksAdded, 2u) << "forward.frag and the forward program";
    EXPECT_EQ(stats->chunksRewritten, 2u) << "STRS (the new names) and the box";

    Opened after = openScene(path);
    const Scene& s = after.scene;
    ASSERT_TRUE(isOk(validateScene(s)));
    ASSERT_EQ(s.programs.size(), before.scene.programs.size() + 1);
    ASSERT_EQ(s.shaders.size(), before.scene.shaders.size() + 1);
    const uint32_t forward = s.materials[box].program;
    EXPECT_EQ(forward, before.scene.programs.size()) << "appended after the file's programs";
    // The scene's sun casts shadows, so the forward receiver samples them (SHADOWS).
    EXPECT_EQ(describeProgram(s, forward), "forward[SHADOWS] surface.vert+forward.frag");
    EXPECT_LT(s.programs[forward].shaders[0], before.scene.shaders.size())
        << "surface.vert is the file's";
    EXPECT_EQ(s.str(s.shaders.back().name), "forward.frag");
    EXPECT_EQ(s.shaders.back().stage, ShaderStage::Fragment);
    // Every chunk of the old file is in the new one with the same stored bytes, except the
    // string table and the box.
    for (Tag tag : {tags::kSceneInfo, tags::kRenderSettings, tags::kShader, tags::kProgram,
                    tags::kTexture, tags::kMaterial, tags::kMesh, tags::kLights, tags::kCameras,
                    tags::kNodes, tags::kCameraPath, tags::kTextureMip}) {
        auto x = ofKind(*before.container, tag), y = ofKind(*after.container, tag);
        ASSERT_GE(y.size(), x.size());
        for (size_t k = 0; k < x.size(); ++k)
            EXPECT_EQ(sameStored(*before.container, *x[k], *after.container, *y[k]),
                      !(tag == tags::kMaterial && k == box))
                << tag.str() << " " << k;
    }
    verifyWithInspect(path);

    // Back to deferred, in a new session on the saved file: the file's G-buffer program again,
    // nothing added; the forward program stays (existing programs are kept).
    auto again = openDoc(path);
    ASSERT_TRUE(again);
    ASSERT_TRUE(isOk(again->setField(box, "shading_path", "deferred")));
    EXPECT_EQ(again->scene().materials[box].program, gbuffer);
    auto back = again->save();
    ASSERT_TRUE(back.ok()) << back.error().describe();
    EXPECT_EQ(back->chunksAdded, 0u);
    EXPECT_EQ(back->chunksRewritten, 1u);

    // Forward and back within one session (or undone) saves the original file exactly.
    const std::string copy = dir.file("copy.pnb");
    fs::copy_file(std::string(PNB_SCENE_DIR) + "/grazing-plane.pnb", copy);
    auto roundTrip = openDoc(copy);
    ASSERT_TRUE(isOk(roundTrip->setField(box, "shading_path", "forward")));
    ASSERT_TRUE(isOk(roundTrip->setField(box, "shading_path", "deferred")));
    EXPECT_EQ(roundTrip->scene().materials[box].program, gbuffer);
    auto same = roundTrip->save(dir.file("same.pnb"));
    ASSERT_TRUE(same.ok());
    EXPECT_EQ(same->chunksRewritten + same->chunksAdded, 0u);
    EXPECT_EQ(readBytes(dir.file("same.pnb")), original);
}

TEST(Save, ImportedTexturesLandInStreamableOrder) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    Opened before = openScene(path);
    auto doc = openDoc(path);
    ASSERT_TRUE(doc);
    writeBytes(dir.file("big.png"), checkerPng(256, {250, 200, 0}, {0, 40, 90}));
    writeBytes(dir.file("small.png"), checkerPng(16, {10, 20, 30}, {200, 210, 220}));
    auto big = doc->importTexture(dir.file("big.png"), true);
    auto small = doc->importTexture(dir.file("small.png"), false, "tiny");
    ASSERT_TRUE(big.ok() && small.ok());
    const uint32_t plane = materialIndex(before.scene, "checker-plane");
    ASSERT_TRUE(isOk(doc->apply({{plane, "base_color_texture", "big"},
                                 {plane, "occlusion_texture", "tiny"}})));
    auto stats = doc->save();
    ASSERT_TRUE(stats.ok()) << stats.error().describe();
    // 2 TEXR + 9 + 5 TMIP + a new G-buffer variant's PROG.
    EXPECT_EQ(stats->chunksAdded, 2u + 9u + 5u + 1u);

    Opened after = openScene(path);
    const Scene& s = after.scene;
    ASSERT_EQ(s.textures.size(), 3u);
    EXPECT_EQ(s.str(s.textures[1].name), "big");
    EXPECT_EQ(s.str(s.textures[2].name), "tiny");
    EXPECT_EQ(s.materials[plane].textures[0].texture, 1u);
    EXPECT_EQ(s.materials[plane].textures[3].texture, 2u);
    EXPECT_EQ(describeProgram(s, s.materials[plane].program),
              "gbuffer[HAS_BASE_COLOR_MAP HAS_OCCLUSION_MAP HAS_UV0] surface.vert+gbuffer.frag");
    // Smallest level first across all textures; the file's own mips keep their bytes.
    uint32_t lastLevel = UINT32_MAX;
    for (const TextureMip& m : s.textureMips) {
        EXPECT_LE(m.level, lastLevel);
        lastLevel = m.level;
    }
    auto x = ofKind(*before.container, tags::kTextureMip);
    for (const ChunkInfo* c : x) {
        bool found = false;
        for (const ChunkInfo* d : ofKind(*after.container, tags::kTextureMip))
            found |= sameStored(*before.container, *c, *after.container, *d);
        EXPECT_TRUE(found) << "mip chunk " << c->header.sequence << " copied";
    }
    verifyWithInspect(path);
}

TEST(Save, HistorySurvivesASave) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    auto doc = openDoc(path);
    ASSERT_TRUE(doc);
    const uint32_t plane = materialIndex(doc->scene(), "checker-plane"),
                   box = materialIndex(doc->scene(), "box");
    writeBytes(dir.file("paint.png"), checkerPng(32, {255, 255, 255}, {0, 0, 0}));
    ASSERT_TRUE(doc->importTexture(dir.file("paint.png"), true).ok());
    ASSERT_TRUE(isOk(doc->setField(plane, "base_color_texture", "paint")));
    ASSERT_TRUE(isOk(doc->setField(box, "shading_path", "forward")));
    ASSERT_TRUE(doc->save().ok());
    EXPECT_FALSE(doc->dirty());
    ASSERT_TRUE(doc->canUndo());

    doc->undo(); // box back to deferred: the file's G-buffer program
    EXPECT_TRUE(doc->dirty());
    EXPECT_EQ(describeProgram(doc->scene(), doc->scene().materials[box].program),
              "gbuffer[] surface.vert+gbuffer.frag");
    doc->undo(); // the plane's checker again; the imported texture is now a file texture
    EXPECT_EQ(doc->scene().materials[plane].textures[0].texture, 0u);
    EXPECT_EQ(doc->scene().textures.size(), 2u);
    doc->undo(); // the import itself: already in the file, so nothing to remove
    EXPECT_EQ(doc->scene().textures.size(), 2u);
    EXPECT_FALSE(doc->canUndo());
    EXPECT_TRUE(isOk(validateScene(doc->scene())));
    doc->redo();
    doc->redo();
    doc->redo();
    EXPECT_FALSE(doc->dirty()) << "redone to the saved content";
    EXPECT_EQ(doc->scene().materials[plane].textures[0].texture, 1u);
    doc->undo();
    auto second = doc->save(dir.file("second.pnb"));
    ASSERT_TRUE(second.ok()) << second.error().describe();
    Opened reread = openScene(dir.file("second.pnb"));
    EXPECT_EQ(reread.scene.materials[box].shadingPath, ShadingPath::Deferred);
    EXPECT_EQ(reread.scene.materials[plane].textures[0].texture, 1u);
}

// [SECTION] kill during save

// Set before fork(): the child kills itself at this probe point.
std::string gKillStage;
uint32_t gKillAt = 0;
int gSignalFd = -1;

void killingProbe(std::string_view stage, uint32_t chunks) {
    if (gSignalFd >= 0 && stage == "chunk" && chunks == 1) {
        char c = 'S';
        (void)!::write(gSignalFd, &c, 1);
    }
    if (stage == gKillStage && chunks == gKillAt) ::raise(SIGKILL);
}

// The child's work: the same edits every time (so the result is deterministic), saved in place.
[[noreturn]] void editAndSave(const std::string& path) {
    auto doc = Document::open(path);
    if (!doc.ok()) ::_exit(2);
    Document& d = **doc;
    Status s = d.apply({{0, "shading_path", "forward"}, {1, "roughness", "0.5"}});
    if (!isOk(s)) ::_exit(3);
    Document::setSaveProbeForTesting(killingProbe);
    ::_exit(d.save().ok() ? 0 : 4);
}

std::vector<std::string> temporariesOf(const TempDir& dir, const std::string& name) {
    std::vector<std::string> out;
    for (const std::string& n : dir.list())
        if (n.rfind("." + name + ".tmp.", 0) == 0) out.push_back(n);
    return out;
}

// Forks a child that edits and saves `path` in place; returns its pid. With `startedFd`, the
// child writes one byte to it when its save has written the first chunk.
pid_t forkSave(const std::string& path, int startedFd = -1) {
    gSignalFd = startedFd;
    pid_t child = ::fork();
    if (child == 0) editAndSave(path);
    gSignalFd = -1;
    return child;
}

TEST(Save, KillAtAnyPointLeavesTheOriginalIntact) {
    TempDir dir;
    const std::string path = copyScene(dir, "terrain");
    const auto original = readBytes(path);

    // The complete result (saves are deterministic), and how long a save takes.
    const std::string reference = dir.file("reference.pnb");
    fs::copy_file(path, reference);
    double saveSeconds = 0;
    {
        int fds[2];
        ASSERT_EQ(::pipe(fds), 0);
        gKillStage.clear();
        pid_t child = forkSave(reference, fds[1]);
        ASSERT_GE(child, 0);
        ::close(fds[1]);
        char c;
        ASSERT_EQ(::read(fds[0], &c, 1), 1);
        auto start = std::chrono::steady_clock::now();
        int status = 0;
        ASSERT_EQ(::waitpid(child, &status, 0), child);
        saveSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        ::close(fds[0]);
        ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
    }
    const auto expected = readBytes(reference);
    ASSERT_NE(expected, original);
    const uint32_t chunks = uint32_t(openScene(reference).container->chunks().size());

    enum class Outcome { Original, Complete, Broken };
    // Waits for the child, checks the target and the directory, restores the original.
    auto check = [&](const std::string& what, pid_t child) {
        int status = 0;
        EXPECT_EQ(::waitpid(child, &status, 0), child);
        const auto now = readBytes(path);
        Outcome o = now == original ? Outcome::Original
                                    : now == expected ? Outcome::Complete : Outcome::Broken;
        EXPECT_NE(o, Outcome::Broken) << what << ": the target is neither the original nor the "
                                             "complete save";
        if (o == Outcome::Original) {
            EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << what << ": " << status;
        }
        // Besides the target and the reference, at most the killed writer's temporary.
        auto temps = temporariesOf(dir, "terrain.pnb");
        EXPECT_LE(temps.size(), 1u) << what;
        for (const std::string& t : temps) {
            EXPECT_NE(t.find("." + std::to_string(child) + "."), std::string::npos) << what << t;
            // Partial, so it does not pass for a container; or, killed between writing the
            // footer and the rename, the complete save under its temporary name.
            if (Container::open(dir.file(t)).ok()) {
                EXPECT_EQ(readBytes(dir.file(t)), expected) << what << ": " << t;
            }
            fs::remove(dir.file(t));
        }
        EXPECT_EQ(dir.list(), (std::vector<std::string>{"reference.pnb", "terrain.pnb"})) << what;
        fs::remove(path);
        std::ofstream(path, std::ios::binary | std::ios::trunc)
            .write(reinterpret_cast<const char*>(original.data()), std::streamsize(original.size()));
        return o;
    };

    // Deterministic points: after the first chunk, in the middle, after the last, and just
    // before the TOC is written and the file renamed.
    for (auto [stage, at] : {std::pair<const char*, uint32_t>{"chunk", 1}, {"chunk", chunks / 2},
                             {"chunk", chunks}, {"commit", chunks}}) {
        gKillStage = stage;
        gKillAt = at;
        pid_t child = forkSave(path);
        ASSERT_GE(child, 0);
        EXPECT_EQ(check(std::string(stage) + " " + std::to_string(at), child), Outcome::Original);
    }

    // Timed kills with no help from the probe: SIGKILL at delays spread over 0..1.5x a save.
    gKillStage.clear();
    int midSave = 0, complete = 0;
    for (int i = 0; i < 12; ++i) {
        int fds[2];
        ASSERT_EQ(::pipe(fds), 0);
        pid_t child = forkSave(path, fds[1]);
        ASSERT_GE(child, 0);
        ::close(fds[1]);
        char c;
        ASSERT_EQ(::read(fds[0], &c, 1), 1);
        ::close(fds[0]);
        std::this_thread::sleep_for(std::chrono::duration<double>(saveSeconds * 1.5 * i / 11));
        ::kill(child, SIGKILL);
        Outcome o = check("timed kill " + std::to_string(i), child);
        midSave += o == Outcome::Original;
        complete += o == Outcome::Complete;
    }
    std::printf("[ kill ] save of terrain.pnb takes %.1f ms; timed kills: %d mid-save (original "
                "intact), %d after the rename (complete file)\n",
                saveSeconds * 1e3, midSave, complete);
    EXPECT_GE(midSave, 1) << "no timed kill landed inside a save";
}

// [SECTION] save time against a plain copy

double seconds(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void fsyncFile(const std::string& path) {
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
}

struct Timing {
    double copy = 1e9, copyFsync = 1e9, save = 1e9, reload = 1e9;
};

// Best of `rounds`: copy_file; copy_file + fsync (the save is durable, so this is the fair
// comparison); Document::save of a one-material edit to a new name. Each measurement starts
// after a sync(), so no earlier step's writeback competes with it; all reads come from the page
// cache (the source was just written or read).
Timing timeSaveVersusCopy(const TempDir& dir, const std::string& path, int rounds) {
    Timing t;
    auto doc = openDoc(path);
    if (!doc) return t;
    std::string source = path;
    for (int r = 0; r < rounds; ++r) {
        const std::string copy = dir.file("copy.pnb");
        fs::remove(copy);
        ::sync();
        auto start = std::chrono::steady_clock::now();
        fs::copy_file(source, copy);
        t.copy = std::min(t.copy, seconds(start));
        fs::remove(copy);
        ::sync();
        start = std::chrono::steady_clock::now();
        fs::copy_file(source, copy);
        fsyncFile(copy);
        t.copyFsync = std::min(t.copyFsync, seconds(start));
        fs::remove(copy);

        EXPECT_TRUE(isOk(doc->setField(0, "roughness", r % 2 ? "0.25" : "0.75")));
        const std::string out = dir.file("saved" + std::to_string(r) + ".pnb");
        ::sync();
        auto stats = doc->save(out);
        EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().describe());
        if (stats.ok()) t.save = std::min(t.save, stats->seconds);
        if (stats.ok()) t.reload = std::min(t.reload, stats->reloadSeconds);
        // The document now refers to `out`: the next round copies and saves from it.
        if (source != path) fs::remove(source);
        source = out;
    }
    return t;
}

void printFigure(const char* what, uint64_t bytes, const Timing& t) {
    std::printf("[ figure ] %s, %.1f MiB: copy_file %.1f ms, copy_file+fsync %.1f ms, "
                "Document::save %.1f ms (%.2fx copy, %.2fx copy+fsync; then %.1f ms to read "
                "the file back), %u cores\n",
                what, double(bytes) / (1 << 20), t.copy * 1e3, t.copyFsync * 1e3, t.save * 1e3,
                t.save / t.copy, t.save / t.copyFsync, t.reload * 1e3,
                std::thread::hardware_concurrency());
}

// A save checksums and writes every chunk in user space where copy_file stays in the kernel;
// under AddressSanitizer that user-space work is instrumented (CI measured 5.2x a durable copy of
// 128 MiB with the suite running beside it, 1.2-3x in a release build). The bound still catches a
// save that rewrites or re-encodes the file more than once.
#if defined(PNB_ASAN)
constexpr double kSaveOverDurableCopy = 10.0;
#else
constexpr double kSaveOverDurableCopy = 5.0;
#endif

TEST(Save, CostsAboutAFileCopy) {
    TempDir dir;
    const std::string terrain = copyScene(dir, "terrain");
    const uint64_t terrainBytes = fs::file_size(terrain);
    Timing t = timeSaveVersusCopy(dir, terrain, 3);
    printFigure("terrain.pnb", terrainBytes, t);
    EXPECT_LE(t.save, kSaveOverDurableCopy * t.copyFsync)
        << "a save should cost about a durable file copy";

    // A bigger, generated scene: one material on a mesh of PNB_EDITOR_BENCH_MB (default 128) MiB
    // of incompressible vertex data.
    uint64_t mib = 128;
    if (const char* e = std::getenv("PNB_EDITOR_BENCH_MB")) mib = std::strtoull(e, nullptr, 10);
    if (mib == 0) return;
    const uint32_t vertices = uint32_t((mib << 20) / 12);
    std::vector<float> positions(size_t(vertices) * 3);
    uint64_t x = 0x9E3779B97F4A7C15ull;
    for (float& f : positions) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        f = float(x >> 40) / float(1 << 24);
    }
    SceneBuilder b;
    Scene& s = b.scene;
    Material m;
    m.name = b.intern("big");
    s.materials.push_back(m);
    Mesh mesh;
    mesh.name = b.intern("big");
    mesh.vertexCount = vertices;
    VertexStream vs;
    vs.data = b.keep(positions);
    mesh.streams.push_back(vs);
    const std::vector<uint32_t> indices = {0, 1, 2};
    mesh.indices = b.keep(indices);
    mesh.submeshes.push_back(Submesh{0, 0, 3, 0, 0, {}});
    s.meshes.push_back(mesh);
    const std::string big = dir.file("big.pnb");
    {
        auto w = Writer::create(big);
        ASSERT_TRUE(w.ok());
        ASSERT_TRUE(isOk(writeScene(*w, s)));
        ASSERT_TRUE(isOk(w->commit()));
    }
    positions = {};
    Timing tb = timeSaveVersusCopy(dir, big, 2);
    printFigure("generated scene", fs::file_size(big), tb);
    EXPECT_LE(tb.save, kSaveOverDurableCopy * tb.copyFsync);
}

} // namespace
