// The image decoder lives in a module loaded on first use (converter/src/image_decode.cpp). A
// module that cannot be loaded fails every textured input with an input error naming what was
// tried, and nothing else: a scene without images still converts. Run as processes, since the
// module is loaded once per process.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "child_process.h"

namespace {

namespace fs = std::filesystem;
using pnb::test::runChild;

TEST(ImageCodecModule, AMissingModuleFailsOnlyTexturedInputsWithAClearError) {
    fs::path dir = fs::temp_directory_path() / ("pnb_codec_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const std::string log = (dir / "log.txt").string();
    const std::string bogus = (dir / "no-such-codec.so").string();
    setenv("PNB_IMAGE_CODEC", bogus.c_str(), 1);
    setenv("PNB_CACHE_DIR", (dir / "cache").c_str(), 1);
    auto textured = runChild({PNB_CONVERT_EXE,
                              "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf",
                              "-o", (dir / "t.pnb").string()},
                             log);
    auto plain = runChild(
        {PNB_CONVERT_EXE, "/usr/share/assimp/models/OBJ/box.obj", "-o", (dir / "p.pnb").string()},
        log + ".2");
    unsetenv("PNB_IMAGE_CODEC");
    unsetenv("PNB_CACHE_DIR");
    EXPECT_EQ(textured.exitCode, 2) << textured.output;
    EXPECT_NE(textured.output.find("cannot load the image decoder module libpnb_image_oiio.so"),
              std::string::npos)
        << textured.output;
    EXPECT_NE(textured.output.find(bogus + ": not found"), std::string::npos) << textured.output;
    EXPECT_NE(textured.output.find("CesiumLogoFlat.png"), std::string::npos) << "names the image\n"
                                                                             << textured.output;
    EXPECT_FALSE(fs::exists(dir / "t.pnb"));
    EXPECT_EQ(plain.exitCode, 0) << plain.output;
    EXPECT_TRUE(fs::exists(dir / "p.pnb"));
    fs::remove_all(dir);
}

} // namespace
