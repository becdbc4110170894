// Atomic saves (writer.h): a save that is killed, abandoned or completed must never leave the
// target half-written. The kill test forks a real writer process and SIGKILLs it mid-save.

#include <gtest/gtest.h>

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "format_test_util.h"
#include "pnb/atomic_file.h"

namespace {

using namespace pnb;
using namespace pnb::test;

std::vector<std::byte> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::byte> bytes(chars.size());
    if (!chars.empty()) std::memcpy(bytes.data(), chars.data(), chars.size());
    return bytes;
}

uint64_t fileSize(const std::string& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 ? uint64_t(st.st_size) : 0;
}

class AtomicSave : public ::testing::Test {
protected:
    void SetUp() override {
        std::string tmpl = ::testing::TempDir() + "pnb-atomic-XXXXXX";
        ASSERT_NE(::mkdtemp(tmpl.data()), nullptr) << std::strerror(errno);
        mDir = tmpl;
        mTarget = mDir + "/scene.pnb";
    }
    void TearDown() override {
        for (const std::string& name : listDir()) ::unlink((mDir + "/" + name).c_str());
        ::rmdir(mDir.c_str());
    }

    std::vector<std::string> listDir() const {
        std::vector<std::string> names;
        if (DIR* d = ::opendir(mDir.c_str())) {
            while (dirent* e = ::readdir(d)) {
                std::string n = e->d_name;
                if (n != "." && n != "..") names.push_back(n);
            }
            ::closedir(d);
        }
        return names;
    }
    // Temporaries of `scene.pnb` as writer.h names them: ".scene.pnb.tmp.<pid>.<n>".
    std::vector<std::string> temporaries(const std::string& pidPart = "") const {
        std::vector<std::string> out;
        const std::string prefix = ".scene.pnb.tmp." + pidPart;
        for (const std::string& n : listDir())
            if (n.rfind(prefix, 0) == 0) out.push_back(n);
        return out;
    }

    // Saves the box room to the target through the real file path and returns its bytes.
    std::vector<std::byte> saveOriginal() {
        SceneBuilder b;
        assets::buildBoxRoom(b);
        auto w = Writer::create(mTarget);
        EXPECT_TRUE(w.ok()) << w.error().describe();
        if (!w.ok()) return {};
        EXPECT_TRUE(isOk(writeScene(*w, b.scene)));
        EXPECT_TRUE(isOk(w->commit()));
        return readFile(mTarget);
    }

    void expectTargetIs(const std::vector<std::byte>& expected) {
        EXPECT_EQ(readFile(mTarget), expected) << "the target changed";
        auto c = Container::open(mTarget);
        ASSERT_TRUE(c.ok()) << c.error().describe();
        EXPECT_TRUE(isOk(c->verifyAll()));
        EXPECT_TRUE(readScene(*c).ok());
    }

    std::string mDir, mTarget;
};

// What the killed child writes: 200 chunks of 1 MiB, deterministic but incompressible. Asking
// for zstd anyway makes each chunk cost a failed compression (the writer then stores it raw), so
// the whole save takes seconds while 4 MiB arrive in about 0.1 s: the parent cannot miss the
// window even on a loaded machine.
[[noreturn]] void slowSaveAndExit(const std::string& target) {
    auto w = Writer::create(target);
    if (!w.ok()) ::_exit(2);
    std::vector<std::byte> chunk(size_t(1) << 20);
    uint64_t x = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < 200; ++i) {
        for (size_t k = 0; k + 8 <= chunk.size(); k += 8) {
            x ^= x << 13, x ^= x >> 7, x ^= x << 17; // xorshift64
            std::memcpy(&chunk[k], &x, 8);
        }
        if (!isOk(w->addChunk(Tag{{'B', 'U', 'L', 'K'}}, 1, chunk, Compression::Zstd)))
            ::_exit(3);
    }
    // _exit, not exit: the child must not run the parent's gtest/atexit machinery.
    ::_exit(isOk(w->commit()) ? 0 : 4);
}

TEST_F(AtomicSave, KillMidSaveLeavesTheOriginalIntact) {
    const std::vector<std::byte> original = saveOriginal();
    ASSERT_FALSE(original.empty());

    const pid_t child = ::fork();
    ASSERT_GE(child, 0) << std::strerror(errno);
    if (child == 0) slowSaveAndExit(mTarget);

    // Wait until the child's temporary has passed 4 MiB, then kill it without warning.
    const std::string pidPart = std::to_string(child) + ".";
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    std::string temp;
    bool killed = false, exitedEarly = false;
    int status = 0;
    while (std::chrono::steady_clock::now() < deadline) {
        std::vector<std::string> t = temporaries(pidPart);
        uint64_t size = t.empty() ? 0 : fileSize(mDir + "/" + t[0]);
        if (size > (uint64_t(4) << 20)) {
            temp = t[0];
            ASSERT_EQ(::kill(child, SIGKILL), 0);
            killed = true;
            std::cout << "[ kill ] writer killed with its temporary at " << size << " bytes\n";
            break;
        }
        if (::waitpid(child, &status, WNOHANG) == child) {
            exitedEarly = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    if (!killed && !exitedEarly) ::kill(child, SIGKILL);
    if (!exitedEarly) {
        ASSERT_EQ(::waitpid(child, &status, 0), child);
    }
    ASSERT_TRUE(killed) << "the child " << (exitedEarly ? "finished" : "never got going")
                        << " before it could be killed (status " << status << ")";
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "status " << status;

    // The target is exactly what it was, and still a valid container.
    expectTargetIs(original);

    // SIGKILL gives the writer no chance to clean up: its partial temporary stays behind until
    // the next save of the same file. It must not pass for a container meanwhile.
    std::vector<std::string> left = temporaries(pidPart);
    ASSERT_EQ(left.size(), 1u);
    EXPECT_EQ(left[0], temp);
    for (bool useToc : {true, false}) {
        auto partial = Container::open(mDir + "/" + temp, ReadOptions{.useToc = useToc});
        ASSERT_FALSE(partial.ok()) << "a killed save's temporary opened as a container";
        EXPECT_EQ(partial.error().code, FormatError::Truncated) << partial.error().describe();
    }

    // The next save removes it: its writer holds no lock any more (a temporary younger than a
    // second is left alone, so wait that out). A live writer's temporary, locked, survives.
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    auto live = Writer::create(mTarget);
    ASSERT_TRUE(live.ok()) << live.error().describe();
    EXPECT_TRUE(temporaries(pidPart).empty()) << "the dead writer's temporary is still there";
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    EXPECT_EQ(removeStaleTemporaries(mTarget), 0u);
    EXPECT_EQ(temporaries().size(), 1u) << "the live writer's temporary was removed";
    // Files that merely look alike are not ours to remove.
    for (const char* name : {".scene.pnb.tmp.x.1", ".scene.pnb.tmp.12", ".other.pnb.tmp.1.2"})
        std::ofstream(mDir + "/" + name) << "user data";
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    EXPECT_EQ(removeStaleTemporaries(mTarget), 0u);
    for (const char* name : {".scene.pnb.tmp.x.1", ".scene.pnb.tmp.12", ".other.pnb.tmp.1.2"})
        EXPECT_EQ(::access((mDir + "/" + name).c_str(), F_OK), 0) << name;
}

TEST_F(AtomicSave, WriterDestroyedWithoutCommitLeavesTargetAndRemovesTemporary) {
    const std::vector<std::byte> original = saveOriginal();
    ASSERT_FALSE(original.empty());
    ASSERT_TRUE(temporaries().empty()) << "a committed save left a temporary";
    {
        auto w = Writer::create(mTarget);
        ASSERT_TRUE(w.ok()) << w.error().describe();
        std::vector<std::byte> payload(100000, std::byte{0x42});
        ASSERT_TRUE(isOk(w->addChunk(Tag{{'B', 'U', 'L', 'K'}}, 1, payload)));
        EXPECT_EQ(temporaries().size(), 1u) << "the save should be going to a temporary";
        expectTargetIs(original); // untouched while the save is in progress
    }
    EXPECT_TRUE(temporaries().empty()) << "an abandoned save left its temporary";
    expectTargetIs(original);

    // Abandoning a save to a new name creates nothing at all.
    const std::string fresh = mDir + "/fresh.pnb";
    { ASSERT_TRUE(Writer::create(fresh).ok()); }
    EXPECT_EQ(::access(fresh.c_str(), F_OK), -1);
    EXPECT_EQ(listDir().size(), 1u) << "only the original target should remain";
}

TEST_F(AtomicSave, CommitReplacesTargetAndLeavesNoTemporary) {
    const std::vector<std::byte> original = saveOriginal();
    ASSERT_FALSE(original.empty());
    // A reader holding the old file keeps a valid view: rename swaps names, not inodes.
    auto before = Container::open(mTarget);
    ASSERT_TRUE(before.ok());

    SceneBuilder smaller;
    assets::buildBoxRoom(smaller, assets::BoxRoomOptions{.textureSize = 16});
    const std::vector<std::byte> expected = writeToMemory(smaller.scene);
    ASSERT_NE(expected, original);
    {
        auto w = Writer::create(mTarget);
        ASSERT_TRUE(w.ok()) << w.error().describe();
        ASSERT_TRUE(isOk(writeScene(*w, smaller.scene)));
        EXPECT_EQ(readFile(mTarget), original) << "the target changed before commit";
        ASSERT_TRUE(isOk(w->commit()));
        EXPECT_FALSE(isOk(w->commit())) << "a second commit must be refused";
    }
    // The file sink and the memory sink produce the same bytes (determinism across sinks).
    EXPECT_EQ(readFile(mTarget), expected);
    expectTargetIs(expected);
    EXPECT_TRUE(temporaries().empty()) << "a committed save left a temporary";
    EXPECT_EQ(listDir().size(), 1u);
    EXPECT_TRUE(isOk(before->verifyAll())) << "the old mapping must stay valid";
    EXPECT_EQ(before->bytes().size(), original.size());
}

TEST_F(AtomicSave, CreateInMissingDirectoryFailsWithIoError) {
    auto w = Writer::create(mDir + "/no-such-dir/scene.pnb");
    ASSERT_FALSE(w.ok());
    EXPECT_EQ(w.error().code, FormatError::IoError);
    EXPECT_NE(w.error().message.find("no-such-dir"), std::string::npos) << w.error().message;
    EXPECT_TRUE(listDir().empty());
}

} // namespace
