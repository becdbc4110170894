// Two writers of one container (issue 44): the file lock (pnb/file_lock.h) and the editor's
// compare-before-rename, reload and merge. The process-level race (two pnb-edit runs, 40 rounds)
// is edit_race_test.py; the window's "changed on disk" prompt is edit_gui_test.sh.

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "editor_test_util.h"
#include "pnb/file_lock.h"
#include "pnb/material_fields.h"
#include "pnb/writer.h"

namespace {

using namespace pnb;
using namespace pnb::editor;
using namespace pnb::editor::test;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

FileLock::Options waitAtMost(double seconds) {
    FileLock::Options o;
    o.timeoutSeconds = seconds;
    return o;
}

std::string field(const Document& d, const char* material, const char* name) {
    return getMaterialField(d.scene().materials[materialIndex(d.scene(), material)], name);
}

std::string fieldOnDisk(const std::string& path, const char* material, const char* name) {
    auto d = openDoc(path);
    return d ? field(*d, material, name) : "";
}

// One field of the material named `material`, as a window or --set would.
Status edit(Document& d, const char* material, const char* field, const char* value) {
    return d.setField(materialIndex(d.scene(), material), field, value);
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// [SECTION] the lock

TEST(FileLock, ASecondHolderWaitsThenGivesUpNamingTheFile) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    auto first = FileLock::acquire(path);
    ASSERT_TRUE(first.ok()) << first.error().describe();
    ASSERT_TRUE(first->held());
    bool announced = false;
    FileLock::Options o = waitAtMost(0.3);
    o.onWait = [&] { announced = true; };
    const auto start = Clock::now();
    auto second = FileLock::acquire(path, o);
    ASSERT_FALSE(second.ok());
    EXPECT_GE(since(start), 0.3);
    EXPECT_EQ(second.error().code, FormatError::Locked);
    EXPECT_TRUE(contains(second.error().message, path)) << second.error().message;
    EXPECT_TRUE(announced);
    first->release();
    EXPECT_TRUE(FileLock::acquire(path, waitAtMost(0)).ok());
}

TEST(FileLock, DoesNotOutliveAKilledHolder) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) { // a pnb-edit batch run holding the lock from read to rename
        ::close(fds[0]);
        DocumentOpenOptions o;
        o.holdLock = true;
        auto doc = Document::open(path, o);
        char ok = doc.ok() ? 1 : 0;
        if (::write(fds[1], &ok, 1) != 1) ::_exit(3);
        ::pause();
        ::_exit(0);
    }
    ::close(fds[1]);
    char ok = 0;
    ASSERT_EQ(::read(fds[0], &ok, 1), 1);
    ::close(fds[0]);
    ASSERT_EQ(ok, 1);
    auto whileAlive = FileLock::acquire(path, waitAtMost(0.2));
    EXPECT_FALSE(whileAlive.ok()) << "the child holds the lock";
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status));
    const auto start = Clock::now();
    auto afterDeath = FileLock::acquire(path, waitAtMost(5));
    ASSERT_TRUE(afterDeath.ok()) << afterDeath.error().describe();
    EXPECT_LT(since(start), 0.5) << "the kernel drops the lock with its holder";
}

TEST(FileLock, FollowsTheFileAHolderRenamedOverThePath) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    auto first = FileLock::acquire(path);
    ASSERT_TRUE(first.ok());
    std::optional<Result<FileLock>> second;
    std::thread waiter([&] { second.emplace(FileLock::acquire(path, waitAtMost(10))); });
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    // The first holder replaces the file (as a save in place does) and lets go.
    fs::copy_file(std::string(PNB_SCENE_DIR) + "/box-room.pnb", dir.file("new.pnb"));
    ASSERT_EQ(::rename(dir.file("new.pnb").c_str(), path.c_str()), 0);
    first->release();
    waiter.join();
    ASSERT_TRUE(second && second->ok());
    // It holds the lock of the file now at the path, not of the replaced one.
    EXPECT_FALSE(FileLock::acquire(path, waitAtMost(0.1)).ok());
}

TEST(FileLock, AMissingFileHasNothingToLock) {
    TempDir dir;
    auto lock = FileLock::acquire(dir.file("new.pnb"));
    ASSERT_TRUE(lock.ok());
    EXPECT_FALSE(lock->held());
}

TEST(FileLock, AWriterReplacesTheFileOnlyOnceTheLockIsFree) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    const std::string source = std::string(PNB_SCENE_DIR) + "/box-room.pnb";
    auto rewrite = [&](double timeout) -> Status {
        auto c = Container::open(source);
        if (!c) return c.error();
        WriteOptions o;
        o.lock = waitAtMost(timeout);
        auto w = Writer::create(path, o);
        if (!w) return w.error();
        for (const ChunkInfo& chunk : c->chunks())
            if (Status s = w->copyChunk(*c, chunk); !isOk(s)) return s;
        return w->commit();
    };
    auto before = stampOf(path);
    ASSERT_TRUE(before.ok());
    auto held = FileLock::acquire(path);
    ASSERT_TRUE(held.ok());

    Status gaveUp = rewrite(0.2);
    EXPECT_EQ(gaveUp.code, FormatError::Locked) << gaveUp.describe();
    EXPECT_TRUE(*stampOf(path) == *before) << "the target is untouched";
    EXPECT_EQ(dir.list(), std::vector<std::string>{"grazing-plane.pnb"}) << "no temporary left";

    Status waited;
    std::thread writer([&] { waited = rewrite(10); });
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_TRUE(*stampOf(path) == *before) << "replaced while the lock was held";
    held->release();
    writer.join();
    EXPECT_TRUE(isOk(waited)) << waited.describe();
    EXPECT_EQ(readBytes(path), readBytes(source));
}

TEST(FileStamp, SeesARenameAndAnInPlaceRewrite) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    auto a = stampOf(path);
    ASSERT_TRUE(a.ok());
    EXPECT_TRUE(a->exists);
    EXPECT_NE(a->tocChecksum, 0u);
    EXPECT_TRUE(*stampOf(path) == *a);
    // Same bytes under a new inode.
    fs::copy_file(path, dir.file("copy.pnb"));
    ASSERT_EQ(::rename(dir.file("copy.pnb").c_str(), path.c_str()), 0);
    auto b = stampOf(path);
    EXPECT_FALSE(*b == *a);
    // Other bytes written into the same inode.
    fs::copy_file(std::string(PNB_SCENE_DIR) + "/box-room.pnb", path,
                  fs::copy_options::overwrite_existing);
    auto c = stampOf(path);
    EXPECT_EQ(c->inode, b->inode);
    EXPECT_FALSE(*c == *b);
    EXPECT_NE(c->tocChecksum, b->tocChecksum);
    EXPECT_FALSE(stampOf(dir.file("none.pnb"))->exists);
}

// [SECTION] the document: compare before rename, reload, merge

TEST(ConcurrentSave, HeldLockMakesASecondBatchEditWaitThenReadTheFirstOnesResult) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    DocumentOpenOptions hold;
    hold.holdLock = true;
    auto first = Document::open(path, hold);
    ASSERT_TRUE(first.ok());
    hold.lock = waitAtMost(0.2);
    auto blocked = Document::open(path, hold);
    ASSERT_FALSE(blocked.ok());
    EXPECT_EQ(blocked.error().code, FormatError::Locked);

    ASSERT_TRUE(isOk(edit(**first, "box", "roughness", "0.125")));
    std::unique_ptr<Document> second;
    std::thread waiter([&] {
        DocumentOpenOptions o;
        o.holdLock = true;
        auto d = Document::open(path, o);
        if (d) second = std::move(*d);
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    ASSERT_TRUE((*first)->save().ok());
    waiter.join();
    ASSERT_TRUE(second);
    EXPECT_EQ(field(*second, "box", "roughness"), "0.125") << "it read the first edit's result";
    ASSERT_TRUE(isOk(edit(*second, "pole", "metallic", "1")));
    ASSERT_TRUE(second->save().ok());
    EXPECT_EQ(fieldOnDisk(path, "box", "roughness"), "0.125");
    EXPECT_EQ(fieldOnDisk(path, "pole", "metallic"), "1");
}

TEST(ConcurrentSave, SaveInPlaceRefusesAFileAnotherProgramSavedAndMergeKeepsBothEdits) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    auto mine = openDoc(path);
    auto theirs = openDoc(path);
    ASSERT_TRUE(mine && theirs);
    const std::string originalRoughness = field(*mine, "box", "roughness");
    ASSERT_TRUE(isOk(edit(*theirs, "pole", "metallic", "0.5")));
    ASSERT_TRUE(theirs->save().ok());
    ASSERT_TRUE(isOk(edit(*mine, "box", "roughness", "0.75")));

    auto change = mine->compareWithDisk();
    ASSERT_TRUE(change.ok());
    EXPECT_TRUE(change->changed());
    EXPECT_EQ(change->mine, 1u);
    EXPECT_TRUE(change->conflicts.empty());
    ASSERT_EQ(change->theirs.size(), 1u);
    EXPECT_EQ(change->theirs[0], "'pole'.metallic: 0 -> 0.5");

    const auto theirBytes = readBytes(path);
    auto refused = mine->save();
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, FormatError::ChangedOnDisk);
    EXPECT_TRUE(contains(refused.error().message, "'pole'.metallic: 0 -> 0.5"))
        << refused.error().message;
    EXPECT_TRUE(contains(refused.error().message, "Nothing was written"));
    EXPECT_EQ(readBytes(path), theirBytes) << "their save is intact";
    EXPECT_EQ(dir.list(), std::vector<std::string>{"grazing-plane.pnb"}) << "no temporary left";
    EXPECT_TRUE(mine->dirty()) << "the refused edit is still in the document";

    ASSERT_TRUE(isOk(mine->reload(Document::Reload::Merge)));
    EXPECT_EQ(field(*mine, "box", "roughness"), "0.75");
    EXPECT_EQ(field(*mine, "pole", "metallic"), "0.5");
    EXPECT_TRUE(mine->dirty());
    EXPECT_FALSE(mine->compareWithDisk()->changed());
    ASSERT_TRUE(mine->save().ok());
    EXPECT_EQ(fieldOnDisk(path, "box", "roughness"), "0.75");
    EXPECT_EQ(fieldOnDisk(path, "pole", "metallic"), "0.5");
    // The merge is one undo step: undo shows the file as the other program left it.
    mine->undo();
    EXPECT_EQ(field(*mine, "box", "roughness"), originalRoughness);
    EXPECT_EQ(field(*mine, "pole", "metallic"), "0.5");
}

TEST(ConcurrentSave, ConflictsAreNamedAndResolvedOnlyByAnExplicitChoice) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    auto mine = openDoc(path);
    auto theirs = openDoc(path);
    ASSERT_TRUE(mine && theirs);
    ASSERT_TRUE(isOk(edit(*theirs, "box", "metallic", "0.875")));
    ASSERT_TRUE(theirs->save().ok());
    ASSERT_TRUE(isOk(edit(*mine, "box", "metallic", "0.25")));

    Status merge = mine->reload(Document::Reload::Merge);
    EXPECT_EQ(merge.code, FormatError::ChangedOnDisk);
    EXPECT_TRUE(contains(merge.message, "'box'.metallic: mine 0.25, theirs 0.875")) << merge.message;
    EXPECT_EQ(field(*mine, "box", "metallic"), "0.25") << "a refused merge changes nothing";
    EXPECT_TRUE(mine->compareWithDisk()->changed());

    ASSERT_TRUE(isOk(mine->reload(Document::Reload::MergeMineWin)));
    EXPECT_EQ(field(*mine, "box", "metallic"), "0.25");
    ASSERT_TRUE(isOk(mine->reload(Document::Reload::Discard)));
    EXPECT_EQ(field(*mine, "box", "metallic"), "0.875");
    EXPECT_FALSE(mine->dirty());
    EXPECT_FALSE(mine->canUndo());
}

TEST(ConcurrentSave, AProgramThatIgnoresTheLockAndRewritesInPlaceIsStillNoticed) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    auto mine = openDoc(path);
    auto theirs = openDoc(path);
    ASSERT_TRUE(mine && theirs);
    ASSERT_TRUE(isOk(edit(*mine, "box", "metallic", "1")));
    ASSERT_TRUE(isOk(edit(*theirs, "wall", "roughness", "0.5")));
    ASSERT_TRUE(theirs->save(dir.file("theirs.pnb")).ok());
    // cp over the open file: the same inode rewritten, no lock taken, no rename.
    fs::copy_file(dir.file("theirs.pnb"), path, fs::copy_options::overwrite_existing);
    auto refused = mine->save();
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, FormatError::ChangedOnDisk);
    EXPECT_TRUE(contains(refused.error().message, "their changes: 'wall'.roughness: "))
        << refused.error().message;
    EXPECT_TRUE(contains(refused.error().message, " -> 0.5")) << refused.error().message;
    EXPECT_EQ(readBytes(path), readBytes(dir.file("theirs.pnb")));
    // The mapping changed under the document: Save As refuses rather than copy torn chunks ...
    auto saveAs = mine->save(dir.file("mine.pnb"));
    ASSERT_FALSE(saveAs.ok());
    EXPECT_TRUE(contains(saveAs.error().message, "rewritten in place")) << saveAs.error().message;
    // ... and the merge, which reads the file anew, keeps the edit.
    ASSERT_TRUE(isOk(mine->reload(Document::Reload::Merge)));
    ASSERT_TRUE(mine->save().ok());
    EXPECT_EQ(fieldOnDisk(path, "box", "metallic"), "1");
    EXPECT_EQ(fieldOnDisk(path, "wall", "roughness"), "0.5");
}

TEST(ConcurrentSave, AMergeIntoAnotherSceneRefusesNamingWhatIsGone) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    auto mine = openDoc(path);
    ASSERT_TRUE(mine);
    ASSERT_TRUE(isOk(edit(*mine, "box", "metallic", "1")));
    // A reconversion of another scene lands on the path (atomically, as the tools write).
    fs::copy_file(std::string(PNB_SCENE_DIR) + "/box-room.pnb", dir.file("other.pnb"));
    ASSERT_EQ(::rename(dir.file("other.pnb").c_str(), path.c_str()), 0);
    auto change = mine->compareWithDisk();
    ASSERT_TRUE(change.ok());
    EXPECT_TRUE(contains(change->describe(path), "material 'box' is gone"))
        << change->describe(path);
    Status merge = mine->reload(Document::Reload::MergeMineWin);
    EXPECT_EQ(merge.code, FormatError::ChangedOnDisk);
    EXPECT_TRUE(contains(merge.message, "'box'.metallic: you edited it")) << merge.message;
    // The old file is still mapped (a rename does not touch it): Save As keeps the edit.
    ASSERT_TRUE(mine->save(dir.file("mine.pnb")).ok());
    EXPECT_EQ(fieldOnDisk(dir.file("mine.pnb"), "box", "metallic"), "1");
}

TEST(ConcurrentSave, MergeKeepsImportedTextures) {
    TempDir dir;
    const std::string path = copyScene(dir, "grazing-plane");
    auto mine = openDoc(path);
    auto theirs = openDoc(path);
    ASSERT_TRUE(mine && theirs);
    writeBytes(dir.file("stripes.png"), checkerPng(16, {255, 0, 0}, {0, 0, 255}));
    auto t = mine->importTexture(dir.file("stripes.png"), true);
    ASSERT_TRUE(t.ok()) << t.error().describe();
    ASSERT_TRUE(isOk(edit(*mine, "checker-plane", "base_color_texture", "stripes")));
    ASSERT_TRUE(isOk(edit(*theirs, "wall", "roughness", "0.5")));
    ASSERT_TRUE(theirs->save().ok());
    ASSERT_TRUE(isOk(mine->reload(Document::Reload::Merge)));
    ASSERT_TRUE(mine->save().ok());
    auto back = openDoc(path);
    ASSERT_TRUE(back);
    const Scene& s = back->scene();
    const std::string slot = field(*back, "checker-plane", "base_color_texture");
    ASSERT_NE(slot, "none");
    EXPECT_EQ(s.str(s.textures[std::stoul(slot)].name), "stripes");
    EXPECT_EQ(field(*back, "wall", "roughness"), "0.5");
}

} // namespace
