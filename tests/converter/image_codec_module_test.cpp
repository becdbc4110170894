// The OpenImageIO decoder lives in a module loaded on first use (converter/src/image_decode.cpp);
// PNG and JPEG are decoded without it. A module that cannot be loaded fails every input with an
// image in another format (here a TGA) with an input error naming what was tried, and nothing
// else: a scene without images and a scene with PNG textures still convert. Run as processes,
// since the module is loaded once per process.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "child_process.h"

namespace {

namespace fs = std::filesystem;
using pnb::test::runChild;

// A textured quad: OBJ + MTL + a 2x2 uncompressed true-colour TGA.
void writeTgaScene(const fs::path& dir) {
    std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl tiles\n"
                                       "f 1/1 2/2 3/3 4/4\n";
    std::ofstream(dir / "quad.mtl") << "newmtl tiles\nKd 1 1 1\nmap_Kd tiles.tga\n";
    unsigned char tga[18 + 2 * 2 * 3] = {};
    tga[2] = 2;                  // uncompressed true-colour
    tga[12] = tga[14] = 2;       // 2 x 2
    tga[16] = 24;                // bits per pixel
    for (int i = 18; i < int(sizeof tga); ++i)
        tga[i] = (unsigned char)(i * 40);
    std::ofstream(dir / "tiles.tga", std::ios::binary).write((const char*)tga, sizeof tga);
}

TEST(ImageCodecModule, AMissingModuleFailsOnlyInputsWithOtherFormatsWithAClearError) {
    fs::path dir = fs::temp_directory_path() / ("pnb_codec_" + std::to_string(getpid()));
    fs::create_directories(dir);
    writeTgaScene(dir);
    const std::string log = (dir / "log.txt").string();
    const std::string bogus = (dir / "no-such-codec.so").string();
    setenv("PNB_IMAGE_CODEC", bogus.c_str(), 1);
    setenv("PNB_CACHE_DIR", (dir / "cache").c_str(), 1);
    auto tga = runChild({PNB_CONVERT_EXE, (dir / "quad.obj").string(), "-o",
                         (dir / "t.pnb").string()},
                        log);
    auto png = runChild({PNB_CONVERT_EXE,
                         "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf", "-o",
                         (dir / "png.pnb").string()},
                        log + ".2");
    auto plain = runChild(
        {PNB_CONVERT_EXE, "/usr/share/assimp/models/OBJ/box.obj", "-o", (dir / "p.pnb").string()},
        log + ".3");
    unsetenv("PNB_IMAGE_CODEC");
    unsetenv("PNB_CACHE_DIR");
    EXPECT_EQ(tga.exitCode, 2) << tga.output;
    EXPECT_NE(tga.output.find("cannot load the image decoder module libpnb_image_oiio.so"),
              std::string::npos)
        << tga.output;
    EXPECT_NE(tga.output.find(bogus + ": not found"), std::string::npos) << tga.output;
    EXPECT_NE(tga.output.find("tiles.tga"), std::string::npos) << "names the image\n" << tga.output;
    EXPECT_FALSE(fs::exists(dir / "t.pnb"));
    EXPECT_EQ(png.exitCode, 0) << "PNG needs no module\n" << png.output;
    EXPECT_TRUE(fs::exists(dir / "png.pnb"));
    EXPECT_EQ(plain.exitCode, 0) << plain.output;
    EXPECT_TRUE(fs::exists(dir / "p.pnb"));
    fs::remove_all(dir);
}

} // namespace
