// The shader validation cache (shader_validation_cache.h): each program text is validated once,
// in memory and across processes; a damaged, unreadable or unwritable cache never fails a
// validation (it validates again); a change of text is a miss; a broken program is never
// remembered. And convertScene() uses it: a second conversion compiles nothing.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>

#include "pnb/user_cache_directory.h"
#include "pnb_converter/convert.h"
#include "pnb_converter/shader_permutations.h"
#include "pnb_converter/shader_validation_cache.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;

class ShaderCache : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_shader_cache_" + std::string(info->name()) + "_" + std::to_string(getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::permissions(dir, fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(dir, ec);
    }

    // The programs of one textured deferred material and a forward one: six variants.
    static ShaderPlan plan() {
        Material deferred, forward;
        forward.shadingPath = ShadingPath::Forward;
        forward.alphaMode = AlphaMode::Blend;
        MaterialFeatures textured;
        textured.baseColorMap = textured.uv0 = true;
        return planShaders(std::vector<Material>{deferred, forward},
                           std::vector<MaterialFeatures>{textured, {}}, {.shadows = true});
    }

    static ShaderValidationStats validate(ShaderValidationCache& cache) {
        ShaderValidationStats stats;
        auto r = validateShaders(plan(), builtinShaderFiles(), &cache, &stats);
        EXPECT_TRUE(r.ok()) << r.error().message;
        return stats;
    }

    static std::vector<fs::path> entries(const fs::path& cacheDir) {
        std::vector<fs::path> out;
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(cacheDir / "shader-validation", ec))
            out.push_back(e.path());
        return out;
    }
};

TEST_F(ShaderCache, EachProgramIsValidatedOnceInMemoryAndAcrossProcesses) {
    const size_t n = plan().programs.size();
    ASSERT_GE(n, 4u);
    ShaderValidationCache first(dir.string());
    ShaderValidationStats cold = validate(first);
    EXPECT_EQ(cold.compiled, n);
    EXPECT_EQ(cold.fromCache, 0u);
    EXPECT_EQ(entries(dir).size(), n);
    ShaderValidationStats again = validate(first); // the same process: from memory
    EXPECT_EQ(again.compiled, 0u);
    EXPECT_EQ(again.fromCache, n);

    // A new cache object over the same directory stands for the next process.
    ShaderValidationCache next(dir.string());
    ShaderValidationStats warm = validate(next);
    EXPECT_EQ(warm.compiled, 0u);
    EXPECT_EQ(warm.fromCache, n);
    EXPECT_TRUE(next.takeNotes().empty());

    // Memory only: nothing is written.
    ShaderValidationCache memoryOnly("");
    EXPECT_EQ(validate(memoryOnly).compiled, n);
    EXPECT_EQ(validate(memoryOnly).fromCache, n);
}

TEST_F(ShaderCache, ChangedTextIsAMissAndABrokenProgramIsNeverRemembered) {
    ShaderValidationCache cache(dir.string());
    validate(cache);
    std::vector<ShaderFile> lib(builtinShaderFiles().begin(), builtinShaderFiles().end());
    std::string edited, broken;
    for (ShaderFile& f : lib)
        if (f.name == "tonemap.frag") {
            edited = std::string(f.text) + "\n// a comment changes the text, not the verdict\n";
            f.text = edited;
        }
    ASSERT_FALSE(edited.empty());
    ShaderValidationStats stats;
    ASSERT_TRUE(validateShaders(plan(), lib, &cache, &stats).ok());
    EXPECT_EQ(stats.compiled, 1u) << "only the tonemap program changed";

    broken = "#version 450 core\nvoid main() { undefinedThing = 1; }\n";
    for (ShaderFile& f : lib)
        if (f.name == "tonemap.frag") f.text = broken;
    size_t before = entries(dir).size();
    for (int round = 0; round < 2; ++round) {
        auto r = validateShaders(plan(), lib, &cache);
        ASSERT_FALSE(r.ok()) << "round " << round;
        EXPECT_NE(r.error().message.find("undefinedThing"), std::string::npos);
    }
    EXPECT_EQ(entries(dir).size(), before);
}

TEST_F(ShaderCache, DamagedOrUnreadableEntriesAreValidatedAgainAndRepaired) {
    {
        ShaderValidationCache cache(dir.string());
        validate(cache);
    }
    std::vector<fs::path> files = entries(dir);
    ASSERT_GE(files.size(), 4u);
    const std::string good = [&] {
        std::ifstream f(files[0], std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    }();
    // Garbage, truncated, one flipped byte, appended-to; and a directory where the file was
    // (unreadable as a file, even for root).
    std::ofstream(files[0], std::ios::binary | std::ios::trunc) << "\x01\x02garbage";
    std::ofstream(files[1], std::ios::binary | std::ios::trunc) << good.substr(0, good.size() / 2);
    {
        std::string flipped = good;
        flipped[flipped.size() - 3] ^= 0x01;
        std::ofstream(files[2], std::ios::binary | std::ios::trunc) << flipped;
    }
    std::ofstream(files[3], std::ios::binary | std::ios::app) << "extra";
    fs::remove(files[0]);
    fs::create_directory(files[0]);

    ShaderValidationCache cache(dir.string());
    ShaderValidationStats stats = validate(cache);
    EXPECT_EQ(stats.compiled, 4u);
    EXPECT_EQ(stats.fromCache, files.size() - 4);
    std::vector<std::string> notes = cache.takeNotes();
    EXPECT_GE(notes.size(), 4u);
    // Every entry was rewritten whole: the next "process" compiles nothing.
    ShaderValidationCache next(dir.string());
    EXPECT_EQ(validate(next).compiled, 0u);
    EXPECT_TRUE(fs::is_regular_file(files[0]));
}

TEST_F(ShaderCache, AnUnwritableCacheNeverFailsAValidation) {
    // A cache directory below a regular file cannot be created, whoever runs the test.
    std::ofstream(dir / "a-file") << "x";
    ShaderValidationCache blocked((dir / "a-file" / "cache").string());
    ShaderValidationStats stats = validate(blocked);
    EXPECT_EQ(stats.compiled, plan().programs.size());
    std::vector<std::string> notes = blocked.takeNotes();
    ASSERT_FALSE(notes.empty());
    EXPECT_NE(notes[0].find("not saved"), std::string::npos) << notes[0];
    EXPECT_EQ(validate(blocked).fromCache, plan().programs.size()) << "memory still works";

    // A read-only directory (only enforced for users other than root).
    fs::create_directories(dir / "ro" / "shader-validation");
    fs::permissions(dir / "ro" / "shader-validation", fs::perms::owner_read | fs::perms::owner_exec,
                    fs::perm_options::replace);
    ShaderValidationCache readOnly((dir / "ro").string());
    EXPECT_EQ(validate(readOnly).compiled, plan().programs.size());
    if (geteuid() != 0) {
        EXPECT_FALSE(readOnly.takeNotes().empty());
        EXPECT_TRUE(entries(dir / "ro").empty());
    }
}

TEST_F(ShaderCache, ConvertSceneCompilesEachProgramOncePerCacheDirectory) {
    ConvertSettings s;
    s.input = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
    s.output = (dir / "a.pnb").string();
    s.cacheDir = (dir / "cache").string();
    auto first = convertScene(s);
    ASSERT_TRUE(first.ok()) << first.error().message;
    EXPECT_EQ(first->programsValidated, first->programs.size());
    s.output = (dir / "b.pnb").string();
    auto second = convertScene(s);
    ASSERT_TRUE(second.ok()) << second.error().message;
    EXPECT_EQ(second->programsValidated, 0u);
    EXPECT_EQ(second->programsFromCache, second->programs.size());
    EXPECT_EQ(entries(dir / "cache").size(), first->programs.size());

    s.shaderCache = false; // --no-shader-cache
    s.output = (dir / "c.pnb").string();
    auto uncached = convertScene(s);
    ASSERT_TRUE(uncached.ok());
    EXPECT_EQ(uncached->programsValidated, uncached->programs.size());
}

TEST(CacheDirectory, FollowsPnbCacheDirThenXdgThenHome) {
    auto saved = [](const char* name) {
        const char* v = std::getenv(name);
        return v ? std::optional<std::string>(v) : std::nullopt;
    };
    auto restore = [](const char* name, const std::optional<std::string>& v) {
        if (v)
            setenv(name, v->c_str(), 1);
        else
            unsetenv(name);
    };
    auto pnbDir = saved("PNB_CACHE_DIR"), xdg = saved("XDG_CACHE_HOME"), home = saved("HOME");
    setenv("PNB_CACHE_DIR", "/tmp/pnb-cache", 1);
    setenv("XDG_CACHE_HOME", "/tmp/xdg", 1);
    setenv("HOME", "/home/someone", 1);
    EXPECT_EQ(pnb::userCacheDirectory("PNB_CACHE_DIR"), "/tmp/pnb-cache");
    unsetenv("PNB_CACHE_DIR");
    EXPECT_EQ(pnb::userCacheDirectory("PNB_CACHE_DIR"), "/tmp/xdg/penumbra");
    setenv("XDG_CACHE_HOME", "relative/ignored", 1);
    EXPECT_EQ(pnb::userCacheDirectory("PNB_CACHE_DIR"), "/home/someone/.cache/penumbra");
    EXPECT_EQ(pnb::userCacheDirectory("PNB_CACHE_DIR", "programs"),
              "/home/someone/.cache/penumbra/programs");
    unsetenv("HOME"); // no guess from the password database: no cache
    EXPECT_EQ(pnb::userCacheDirectory("PNB_CACHE_DIR"), "");
    restore("PNB_CACHE_DIR", pnbDir);
    restore("XDG_CACHE_HOME", xdg);
    restore("HOME", home);
}

} // namespace
