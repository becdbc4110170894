// pnb-convert's batch mode, run as a process (what a user runs): several inputs with -o DIR and
// --batch LIST convert to files byte-identical to one process per input; a bad input is
// reported and named at the end while the others still convert; outputs that would collide are
// refused before anything is written.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "child_process.h"

namespace {

namespace fs = std::filesystem;
using pnb::test::runChild;

const std::string kModels = "/usr/share/assimp/models/";

// Small real models through both importers: OBJ with MTL and a texture, glTF with external,
// embedded and binary buffers and textures, Draco, and one with vertex colours.
const std::vector<std::string> kInputs = {
    kModels + "OBJ/spider.obj",
    kModels + "OBJ/cube_with_vertexcolors.obj",
    kModels + "OBJ/box.obj",
    kModels + "glTF2/BoxTextured-glTF/BoxTextured.gltf",
    kModels + "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
    kModels + "glTF2/cameras/Cameras.gltf",
};

class BatchConvert : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_batch_" + std::string(info->name()) + "_" + std::to_string(getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
        // The children share one cache directory of their own, so the user's is left alone.
        setenv("PNB_CACHE_DIR", (dir / "cache").c_str(), 1);
    }
    void TearDown() override {
        unsetenv("PNB_CACHE_DIR");
        fs::remove_all(dir);
    }

    pnb::test::ChildResult convert(std::vector<std::string> args) {
        args.insert(args.begin(), PNB_CONVERT_EXE);
        return runChild(args, (dir / "child-output.txt").string());
    }

    static std::string bytesOf(const fs::path& p) {
        std::ifstream f(p, std::ios::binary);
        return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
    }
    static std::string stem(const std::string& path) { return fs::path(path).stem().string(); }
};

TEST_F(BatchConvert, OutputIsByteIdenticalToOneProcessPerInput) {
    fs::create_directories(dir / "single");
    for (const std::string& in : kInputs) {
        auto r = convert({in, "-o", (dir / "single" / (stem(in) + ".pnb")).string(), "-q"});
        ASSERT_EQ(r.exitCode, 0) << in << ":\n" << r.output;
    }

    // Several inputs and -o DIR (created by the batch).
    std::vector<std::string> args = kInputs;
    args.insert(args.end(), {"-o", (dir / "batch").string()});
    auto batch = convert(args);
    ASSERT_EQ(batch.exitCode, 0) << batch.output;
    EXPECT_NE(
        batch.output.find("batch: " + std::to_string(kInputs.size()) + " converted, 0 failed"),
        std::string::npos)
        << batch.output;

    // --batch LIST with a comment, a blank line and per-line outputs (tab-separated), converted
    // concurrently.
    std::ofstream list(dir / "list.txt");
    list << "# models\n\n";
    for (const std::string& in : kInputs)
        list << in << "\t" << (dir / "listed" / (stem(in) + ".x.pnb")).string() << "\n";
    list.close();
    fs::create_directories(dir / "listed");
    // -j 4: four inputs in flight at once, whatever the machine's core count.
    auto listed = convert({"--batch", (dir / "list.txt").string(), "-q", "-j", "4"});
    ASSERT_EQ(listed.exitCode, 0) << listed.output;
    EXPECT_EQ(listed.output, "") << "-q prints errors only";

    for (const std::string& in : kInputs) {
        std::string single = bytesOf(dir / "single" / (stem(in) + ".pnb"));
        ASSERT_GT(single.size(), 64u) << in;
        EXPECT_TRUE(single == bytesOf(dir / "batch" / (stem(in) + ".pnb"))) << in;
        EXPECT_TRUE(single == bytesOf(dir / "listed" / (stem(in) + ".x.pnb"))) << in;
    }
}

TEST_F(BatchConvert, ABadInputFailsAloneAndIsNamedAtTheEnd) {
    std::ofstream(dir / "broken.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 9\n"; // index out of range
    const std::string missing = (dir / "missing.gltf").string();
    auto r = convert({kInputs[0], (dir / "broken.obj").string(), kInputs[3], missing, "-o",
                      (dir / "out").string()});
    EXPECT_EQ(r.exitCode, 2) << "the first failure's exit code (input error)\n" << r.output;
    EXPECT_TRUE(fs::exists(dir / "out" / (stem(kInputs[0]) + ".pnb")));
    EXPECT_TRUE(fs::exists(dir / "out" / (stem(kInputs[3]) + ".pnb")));
    EXPECT_FALSE(fs::exists(dir / "out" / "broken.pnb"));
    EXPECT_FALSE(fs::exists(dir / "out" / "missing.pnb"));
    // Each failure is reported where it happens with its reason, and listed at the end.
    size_t end = r.output.find("batch: 2 of 4 input(s) failed:");
    ASSERT_NE(end, std::string::npos) << r.output;
    std::string tail = r.output.substr(end);
    EXPECT_NE(tail.find((dir / "broken.obj").string() + " (argument 2, exit code 2)"),
              std::string::npos)
        << tail;
    EXPECT_NE(tail.find(missing + " (argument 4, exit code 2)"), std::string::npos) << tail;
    EXPECT_NE(r.output.find("Error: [2/4] " + (dir / "broken.obj").string()), std::string::npos)
        << r.output;
}

TEST_F(BatchConvert, CollidingOutputsAndMissingOutputsAreRefusedBeforeConverting) {
    // Three BoxTextured.gltf from different folders would all write DIR/BoxTextured.pnb.
    auto r = convert({kModels + "glTF2/BoxTextured-glTF/BoxTextured.gltf",
                      kModels + "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf", "-o",
                      (dir / "out").string()});
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("is the same file as the output of argument 1"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir / "out"));

    // A list line without an output needs -o DIR; the message names the list and line.
    std::ofstream(dir / "list.txt") << kInputs[0] << "\n";
    auto noDir = convert({"--batch", (dir / "list.txt").string()});
    EXPECT_EQ(noDir.exitCode, 1) << noDir.output;
    EXPECT_NE(noDir.output.find((dir / "list.txt").string() + ":1: no output"), std::string::npos)
        << noDir.output;

    // --depfile names one file: refused with several inputs.
    auto depfile = convert({kInputs[0], kInputs[2], "-o", (dir / "out").string(), "--depfile",
                            (dir / "deps.d").string()});
    EXPECT_EQ(depfile.exitCode, 1) << depfile.output;
    EXPECT_NE(depfile.output.find("--depfile"), std::string::npos) << depfile.output;
    EXPECT_FALSE(fs::exists(dir / "out"));

    auto unreadable = convert({"--batch", (dir / "no-such-list.txt").string(), "-o", "x"});
    EXPECT_EQ(unreadable.exitCode, 1) << unreadable.output;
    EXPECT_NE(unreadable.output.find("cannot read the batch list"), std::string::npos);
}

} // namespace
