// Texture files decoded while the OBJ is parsed (image_prefetch.h): the OBJ importer reports the
// files its materials name, a prefetched image is the image decodeImage gives, anything a
// prefetch cannot do (missing or corrupt file, a memory share that refuses the image) falls back
// to the ordinary decode, and a conversion writes the same bytes with the prefetch (2 jobs) and
// without it (-j 1).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "image_prefetch.h"
#include "import_test_support.h"
#include "pnb_converter/convert.h"
#include "pnb_converter/importers.h"
#include "texture_internal.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
using namespace pnb::converter::test;
using texture_detail::decodeImage;
using texture_detail::ImageHeader;

const std::string kSpiderObj = (kModels / "OBJ/spider.obj").string();
const std::string kWoodJpg = (kModels / "OBJ/drkwood2.jpg").string();

std::string bytesOf(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

TEST(ImagePrefetch, ObjImporterReportsTheTextureFilesItsMaterialsUse) {
    std::set<std::string> reported;
    auto r = importObj(kSpiderObj, [&](const std::string& path) { reported.insert(path); });
    ASSERT_TRUE(r.ok()) << r.error().message;
    std::set<std::string> used;
    for (const IrImage& image : r->images) used.insert(image.path);
    ASSERT_FALSE(used.empty());
    // Every image file the scene uses was reported, by the path IrImage holds; a material the
    // MTL defines and no face uses reports its file too (spider.mtl has one).
    for (const std::string& path : used) EXPECT_EQ(reported.count(path), 1u) << path;
    EXPECT_EQ(reported.size(), used.size() + 1);

    // Missing texture files are not reported (the importer warns about them instead).
    TempDir dir("prefetch_scene");
    const std::string file = writeHandWrittenScene(dir.path);
    reported.clear();
    auto h = importObj(file, [&](const std::string& path) { reported.insert(path); });
    ASSERT_TRUE(h.ok()) << h.error().message;
    for (const std::string& path : reported) EXPECT_TRUE(fs::exists(path)) << path;
}

TEST(ImagePrefetch, APrefetchedImageIsTheDecodedImage) {
    ImagePrefetch prefetch(1u << 28, uint64_t(1) << 30);
    prefetch.add(kWoodJpg);
    prefetch.add(kWoodJpg); // once
    prefetch.finish();
    auto got = prefetch.take(kWoodJpg, {});
    ASSERT_TRUE(got.has_value());
    IrImage image;
    image.name = "drkwood2.jpg";
    image.path = kWoodJpg;
    auto direct = decodeImage(image, 1u << 28, {});
    ASSERT_TRUE(direct.ok()) << direct.error().message;
    EXPECT_EQ(got->image.width, direct->image.width);
    EXPECT_EQ(got->image.height, direct->image.height);
    EXPECT_EQ(got->sourceChannels, direct->sourceChannels);
    EXPECT_TRUE(got->image.texels == direct->image.texels);
    EXPECT_FALSE(prefetch.take(kWoodJpg, {}).has_value()) << "handed out once";
    EXPECT_EQ(prefetch.taken(), 1u);
    EXPECT_FALSE(prefetch.take("/never/added.png", {}).has_value());
}

TEST(ImagePrefetch, FailuresAndRefusalsFallBackToTheOrdinaryDecode) {
    TempDir dir("prefetch_bad");
    writeFile(dir.path / "corrupt.png", "\x89PNG\r\n\x1a\n this is not a PNG");
    ImagePrefetch prefetch(1u << 28, uint64_t(1) << 30);
    prefetch.add((dir.path / "missing.png").string());
    prefetch.add((dir.path / "corrupt.png").string());
    prefetch.add(kWoodJpg);
    prefetch.finish();
    EXPECT_FALSE(prefetch.take((dir.path / "missing.png").string(), {}).has_value());
    EXPECT_FALSE(prefetch.take((dir.path / "corrupt.png").string(), {}).has_value());
    // The texture stage's memory share refuses it: not handed out (its decode reports why).
    bool asked = false;
    auto refuse = [&](const ImageHeader& h) -> std::optional<std::string> {
        asked = true;
        EXPECT_GT(h.width, 0u);
        return std::string("too big");
    };
    EXPECT_FALSE(prefetch.take(kWoodJpg, refuse).has_value());
    EXPECT_TRUE(asked);
    EXPECT_EQ(prefetch.taken(), 0u);

    // An image larger than what the prefetch may hold is not decoded ahead at all.
    ImagePrefetch tiny(1u << 28, 1024);
    tiny.add(kWoodJpg);
    tiny.finish();
    EXPECT_FALSE(tiny.take(kWoodJpg, {}).has_value());

    // A file not started when the texture stage asks is struck from the queue, not waited for.
    ImagePrefetch busy(1u << 28, uint64_t(1) << 30);
    for (const char* name : {"SpiderTex.jpg", "engineflare1.jpg", "wal67ar_small.jpg"})
        busy.add((kModels / "OBJ" / name).string());
    busy.add(kWoodJpg);
    const bool gotLast = busy.take(kWoodJpg, {}).has_value();
    busy.finish();
    EXPECT_FALSE(busy.take(kWoodJpg, {}).has_value()) << "struck, or handed out once";
    (void)gotLast; // whether the thread reached it first is timing
}

// The determinism the prefetch must keep: the same container with 1 job (no prefetch) and 2
// (the textures decoded while the OBJ is parsed), and the summary says the prefetch was used.
TEST(ImagePrefetch, ConversionBytesDoNotDependOnThePrefetch) {
    TempDir dir("prefetch_convert");
    ConvertSettings s;
    s.input = kSpiderObj;
    s.jobs = 1;
    s.output = (dir.path / "one.pnb").string();
    auto one = convertScene(s);
    ASSERT_TRUE(one.ok()) << one.error().message;
    for (const std::string& n : one->notes) EXPECT_EQ(n.find("decoded while"), std::string::npos);
    // Whether the background decode is ahead of the texture stage is a matter of timing: a few
    // tries until one conversion took at least one image from it (the note says how many).
    s.jobs = 2;
    s.output = (dir.path / "two.pnb").string();
    size_t taken = 0;
    for (int attempt = 0; attempt < 10 && taken == 0; ++attempt) {
        auto two = convertScene(s);
        ASSERT_TRUE(two.ok()) << two.error().message;
        ASSERT_GT(two->textures, 0u);
        bool noted = false;
        for (const std::string& n : two->notes) {
            if (n.rfind("textures: ", 0) != 0 || n.find("decoded while") == std::string::npos)
                continue;
            noted = true;
            taken = std::stoul(n.substr(10));
        }
        ASSERT_TRUE(noted) << "an OBJ with textures and 2 jobs uses the prefetch";
        EXPECT_EQ(bytesOf(dir.path / "one.pnb"), bytesOf(dir.path / "two.pnb"));
    }
    EXPECT_GT(taken, 0u) << "no conversion took a prefetched image";
}

} // namespace
