// A mapped container truncated by another program while it is being read (issue: pnb-play died
// of SIGBUS). Reads past the new end of file must give an IoError naming the file, never a
// signal; SIGBUS on memory that is not a container's mapping must still kill as before.

#include "../common/sanitizers.h"
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "format_test_util.h"
#include "pnb/reader.h"
#include "pnb/scene.h"

namespace {

using namespace pnb;

class TruncatedMapping : public ::testing::Test {
protected:
    void SetUp() override {
        std::string tmpl = ::testing::TempDir() + "pnb-truncated-XXXXXX";
        ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
        mDir = tmpl;
        mPath = mDir + "/scene.pnb";
        mBytes = test::sampleBytes();
        writeSample();
    }
    void writeSample() {
        int fd = ::open(mPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ASSERT_GE(fd, 0);
        ASSERT_EQ(::write(fd, mBytes.data(), mBytes.size()), ssize_t(mBytes.size()));
        ::close(fd);
    }
    void TearDown() override {
        ::unlink(mPath.c_str());
        ::rmdir(mDir.c_str());
    }
    std::string mDir, mPath;
    std::vector<std::byte> mBytes;
};

TEST_F(TruncatedMapping, ReadsAfterATruncationFailCleanlyNamingTheFile) {
    for (bool checksums : {true, false}) {
        SCOPED_TRACE(checksums ? "checksums verified" : "checksums off");
        writeSample();
        auto c = Container::open(mPath, ReadOptions{.verifyChecksums = checksums});
        ASSERT_TRUE(c.ok()) << c.error().describe();
        EXPECT_TRUE(isOk(c->intact()));
        // Another program cuts the file to its first 4 KiB.
        ASSERT_EQ(::truncate(mPath.c_str(), 4096), 0);

        auto scene = readScene(*c);
        ASSERT_FALSE(scene.ok());
        EXPECT_EQ(scene.error().code, FormatError::IoError) << scene.error().describe();
        EXPECT_NE(scene.error().message.find(mPath), std::string::npos) << scene.error().message;
        EXPECT_NE(scene.error().message.find("shrank while it was being read"), std::string::npos);
        EXPECT_EQ(scene.error().offset, 4096u);
        EXPECT_FALSE(isOk(c->verifyAll()));
        EXPECT_EQ(c->verifyAll().code, FormatError::IoError);

        // Raw access to the mapping (what an upload straight from it does) reads zeros, no
        // signal, and intact() says why.
        const std::byte last = c->bytes().back();
        EXPECT_EQ(last, std::byte{0});
        EXPECT_EQ(c->intact().code, FormatError::IoError);
    }
}

TEST_F(TruncatedMapping, AnUntouchedFileStaysIntactAndOtherSigbusStillKills) {
    {
        auto c = Container::open(mPath);
        ASSERT_TRUE(c.ok());
        ASSERT_TRUE(readScene(*c).ok());
        EXPECT_TRUE(isOk(c->intact()));
    }
    // The guard's handler is installed now; a mapping it does not know must still die of SIGBUS.
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        int fd = ::open(mPath.c_str(), O_RDONLY);
        void* m = ::mmap(nullptr, mBytes.size(), PROT_READ, MAP_PRIVATE, fd, 0);
        if (fd < 0 || m == MAP_FAILED) ::_exit(2);
        if (::truncate(mPath.c_str(), 0) != 0) ::_exit(3);
        volatile const char* p = static_cast<const char*>(m);
        (void)p[mBytes.size() - 1];
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
#if defined(PNB_ASAN)
    // AddressSanitizer's own SIGBUS handler (the one the guard chains to) reports and exits.
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0) << "status " << status;
#else
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGBUS) << "status " << status;
#endif
}

} // namespace
