// The environment bake (pnb_converter/environment.h): ENVM and its textures against the math
// they are defined by (FORMAT.md "ENVM"): SH irradiance of a constant, the split-sum table, cube
// face orientation, a 1e5-nit sun (finite storage, no fireflies, measured against the exact
// convolution), the sky following the scene's sun, determinism, what is written without an
// environment, and the command line. Inputs are written with OpenImageIO at test time.

#include <gtest/gtest.h>

#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "child_process.h"
#include "pnb/node_transform.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/procedural_scenes.h"
#include "pnb_converter/convert.h"
#include "pnb_converter/environment.h"
#include "pnb_lighting/sh9.h"
#include "pnb_lighting/split_sum.h"
#include "environment_internal.h"
#include "texture_internal.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;
using pnb::test::runChild;

const char* kBoxTextured = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
constexpr double kPi = 3.14159265358979323846;

class Environment : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_env_" + std::string(info->name()) + "_" + std::to_string(getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    // Writes three-channel float texels (row 0 = top) to `name`, format from the extension.
    std::string writeImage(const std::string& name, const RadianceImage& img) {
        const std::string path = (dir / name).string();
        auto out = OIIO::ImageOutput::create(path);
        EXPECT_TRUE(out) << OIIO::geterror();
        if (!out) return path;
        OIIO::ImageSpec spec(int(img.width), int(img.height), 3, OIIO::TypeDesc::FLOAT);
        EXPECT_TRUE(out->open(path, spec)) << out->geterror();
        EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, img.rgb.data())) << out->geterror();
        out->close();
        return path;
    }

    fs::path writeScene(const char* name, const assets::gltf::Document& doc) {
        fs::path p = dir / (std::string(name) + ".glb");
        auto bytes = assets::gltf::encodeGlb(doc);
        std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                 std::streamsize(bytes.size()));
        return p;
    }

    static std::vector<char> bytesOf(const std::string& path) {
        std::ifstream f(path, std::ios::binary);
        return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
    }
};

// Small sizes keep the tests fast; the code paths are those of the defaults.
EnvironmentSettings smallSettings() {
    EnvironmentSettings s;
    s.skyWidth = 64;
    s.specularSize = 16;
    s.specularLevels = 5;
    s.prefilterSamples = 64;
    s.lutSize = 16;
    s.lutSamples = 128;
    return s;
}

RadianceImage constantImage(uint32_t w, uint32_t h, float r, float g, float b) {
    RadianceImage img{w, h, std::vector<float>(size_t(w) * h * 3)};
    for (size_t t = 0; t < size_t(w) * h; ++t) {
        img.rgb[t * 3] = r;
        img.rgb[t * 3 + 1] = g;
        img.rgb[t * 3 + 2] = b;
    }
    return img;
}

// Level `level` of texture `texture` as floats, `channels` per texel (RGBA16F/32F, RG16F).
std::vector<float> texels(const Scene& scene, uint32_t texture, uint32_t level) {
    const TextureDesc& desc = scene.textures.at(texture);
    for (const TextureMip& m : scene.textureMips) {
        if (m.texture != texture || m.level != level) continue;
        std::vector<float> out;
        const bool full = desc.format == TextureFormat::RGBA32F || desc.format == TextureFormat::RG32F;
        const size_t n = m.data.size() / (full ? 4 : 2);
        out.resize(n);
        for (size_t k = 0; k < n; ++k) {
            if (full) {
                std::memcpy(&out[k], m.data.data() + k * 4, 4);
            } else {
                uint16_t h;
                std::memcpy(&h, m.data.data() + k * 2, 2);
                out[k] = texture_detail::halfToFloat(h);
            }
        }
        return out;
    }
    ADD_FAILURE() << "texture " << texture << " has no level " << level;
    return {};
}

lighting::Sh9Rgb shOf(const pnb::Environment& e) {
    lighting::Sh9Rgb sh;
    for (size_t k = 0; k < 9; ++k)
        sh.c[k] = {e.irradianceSh[k].x, e.irradianceSh[k].y, e.irradianceSh[k].z};
    return sh;
}

// Unit directions spread evenly over the sphere (Fibonacci lattice).
std::vector<glm::dvec3> sphereDirections(int n) {
    std::vector<glm::dvec3> out;
    for (int k = 0; k < n; ++k) {
        double y = 1.0 - (k + 0.5) * 2.0 / n, r = std::sqrt(1.0 - y * y);
        double phi = k * kPi * (3.0 - std::sqrt(5.0));
        out.push_back({r * std::cos(phi), y, r * std::sin(phi)});
    }
    return out;
}

// [SECTION] the bake against its definitions

TEST_F(Environment, ConstantEnvironmentGivesPiLIrradianceAndAConstantCube) {
    const glm::dvec3 L(2.0, 3.0, 0.5);
    SceneBuilder b;
    auto sum = addEnvironment(b, constantImage(1, 1, float(L.x), float(L.y), float(L.z)),
                              smallSettings(), EnvironmentSource::Image, "grey.exr", 2);
    ASSERT_TRUE(sum.ok()) << sum.error().message;
    ASSERT_TRUE(b.scene.environment.has_value());
    const pnb::Environment& e = *b.scene.environment;
    EXPECT_TRUE(isOk(validateEnvironment(b.scene, e)));
    EXPECT_EQ(b.scene.str(e.name), "grey.exr");
    for (const glm::dvec3& n : sphereDirections(7)) {
        glm::dvec3 E = lighting::sh9Evaluate(shOf(e), n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(E[c], kPi * L[c], 1e-5 * kPi * L[c]) << c;
    }
    const TextureDesc& cube = b.scene.textures.at(e.specular);
    EXPECT_EQ(cube.dimension, TextureDimension::Cube);
    EXPECT_EQ(cube.format, TextureFormat::RGBA16F);
    EXPECT_EQ(cube.mipCount, 5u);
    for (uint32_t level = 0; level < cube.mipCount; ++level) {
        std::vector<float> t = texels(b.scene, e.specular, level);
        const uint32_t n = std::max(1u, cube.width >> level);
        ASSERT_EQ(t.size(), size_t(n) * n * 6 * 4);
        for (size_t k = 0; k < t.size() / 4; ++k)
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(t[k * 4 + c], L[c], L[c] * 1e-3) << "level " << level << " texel " << k;
    }
    // The radiance texture: 1x1, one level, the constant itself.
    const TextureDesc& rad = b.scene.textures.at(e.radiance);
    EXPECT_EQ(rad.width, 1u);
    EXPECT_EQ(rad.mipCount, 1u);
    EXPECT_EQ(texels(b.scene, e.radiance, 0), (std::vector<float>{2.0f, 3.0f, 0.5f, 1.0f}));
}

TEST_F(Environment, BrdfTableHoldsSplitSumAtTexelCentresRowZeroFirst) {
    SceneBuilder b;
    EnvironmentSettings s = smallSettings();
    s.lutSize = 32;
    s.lutSamples = 256;
    ASSERT_TRUE(addEnvironment(b, constantImage(1, 1, 1, 1, 1), s, EnvironmentSource::Image, "c", 1).ok());
    const pnb::Environment& e = *b.scene.environment;
    const TextureDesc& lut = b.scene.textures.at(e.brdfLut);
    EXPECT_EQ(lut.format, TextureFormat::RG16F);
    EXPECT_EQ(lut.width, 32u);
    EXPECT_EQ(lut.height, 32u);
    std::vector<float> ab = texels(b.scene, e.brdfLut, 0);
    ASSERT_EQ(ab.size(), 32u * 32u * 2u);
    // Texel (i, j): NdotV = (i + 0.5) / W along the row, roughness = (j + 0.5) / H down the rows.
    for (auto [i, j] : {std::pair{0u, 0u}, {31u, 0u}, {0u, 31u}, {5u, 20u}, {20u, 5u}, {31u, 31u}}) {
        glm::dvec2 want = lighting::splitSumBrdf((i + 0.5) / 32.0, (j + 0.5) / 32.0, 256);
        EXPECT_NEAR(ab[(j * 32 + i) * 2 + 0], want.x, 2e-3) << i << "," << j;
        EXPECT_NEAR(ab[(j * 32 + i) * 2 + 1], want.y, 2e-3) << i << "," << j;
    }
    // Not symmetric in its axes, so a transposed table would fail above: make sure it is not.
    EXPECT_GT(std::abs(ab[(20 * 32 + 5) * 2] - ab[(5 * 32 + 20) * 2]), 0.01f);
}

TEST_F(Environment, CubeFacesFollowGlOrientationAndUHalfLooksAlongPlusX) {
    // Red is bright where x > 0 (u in [1/4, 3/4)), green where y > 0 (the top half of the rows).
    const uint32_t W = 64, H = 32;
    RadianceImage img{W, H, {}};
    for (uint32_t j = 0; j < H; ++j)
        for (uint32_t i = 0; i < W; ++i)
            img.rgb.insert(img.rgb.end(), {i >= W / 4 && i < 3 * W / 4 ? 10.0f : 1.0f,
                                           j < H / 2 ? 10.0f : 1.0f, 1.0f});
    const std::string path = writeImage("halves.exr", img);
    auto loaded = loadRadianceImage(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_TRUE(loaded->warnings.empty()) << loaded->warnings.front();
    SceneBuilder b;
    ASSERT_TRUE(addEnvironment(b, *loaded, smallSettings(), EnvironmentSource::Image, "halves.exr", 2).ok());
    const pnb::Environment& e = *b.scene.environment;
    // The radiance texture is stored as the image shows it: the centre column (u = 1/2) is red.
    std::vector<float> rad = texels(b.scene, e.radiance, 0);
    EXPECT_EQ(rad[(0 * W + W / 2) * 4], 10.0f);
    EXPECT_EQ(rad[(0 * W + 0) * 4], 1.0f);
    EXPECT_EQ(rad[(0 * W) * 4 + 1], 10.0f);
    EXPECT_EQ(rad[((H - 1) * W) * 4 + 1], 1.0f);

    const uint32_t n = b.scene.textures.at(e.specular).width;
    std::vector<float> cube = texels(b.scene, e.specular, 0);
    auto at = [&](uint32_t face, uint32_t i, uint32_t j, int c) {
        return cube[((size_t(face) * n + j) * n + i) * 4 + c];
    };
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            EXPECT_NEAR(at(0, i, j, 0), 10.0f, 0.01f) << "+X is bright red";
            EXPECT_NEAR(at(1, i, j, 0), 1.0f, 0.01f) << "-X is dark";
            EXPECT_NEAR(at(2, i, j, 1), 10.0f, 0.01f) << "+Y (up) is bright green";
            EXPECT_NEAR(at(3, i, j, 1), 1.0f, 0.01f) << "-Y is dark";
        }
    // Within a face: +X's first row (t = 0) is its top (tc = -y), +Z's last column (s = 1) is +x.
    EXPECT_NEAR(at(0, n / 2, 0, 1), 10.0f, 0.01f);
    EXPECT_NEAR(at(0, n / 2, n - 1, 1), 1.0f, 0.01f);
    EXPECT_NEAR(at(4, n - 1, n / 2, 0), 10.0f, 0.01f);
    EXPECT_NEAR(at(4, 0, n / 2, 0), 1.0f, 0.01f);
    EXPECT_NEAR(at(5, 0, n / 2, 0), 10.0f, 0.01f) << "-Z: sc = -x";
    // The prefilter's own copy of the mapping is the player's (sh9.h).
    for (const glm::dvec3& w : sphereDirections(200)) {
        double uv[2], unit[3] = {w.x, w.y, w.z};
        environment_detail::equirectUvOfUnit(unit, uv);
        glm::dvec2 want = lighting::equirectUv(w);
        double du = std::abs(uv[0] - want.x);
        EXPECT_LT(std::min(du, 1.0 - du), 1e-12);
        EXPECT_NEAR(uv[1], want.y, 1e-12);
    }
    double d[3];
    cubeTexelDirection(4, n - 1, 0, n, d);
    EXPECT_GT(d[0], 0.5) << "the +Z face's last column and first row: +x, +y";
    EXPECT_GT(d[1], 0.5);
    EXPECT_GT(d[2], 0.5);
}

// The exact value level m should hold at direction r for a piecewise-constant equirect image:
// the integral of L(l) (n.l) D(h) / 4 over the sphere divided by that of (n.l) D(h) / 4, with
// N = V = r (the estimator environment_prefilter.cpp samples), by 4x4 points per source texel.
glm::dvec3 exactPrefilter(const RadianceImage& img, const glm::dvec3& r, double roughness) {
    const double alpha = lighting::ggxAlpha(roughness);
    glm::dvec3 acc(0);
    double weight = 0;
    for (uint32_t j = 0; j < img.height; ++j)
        for (uint32_t i = 0; i < img.width; ++i)
            for (int sj = 0; sj < 4; ++sj)
                for (int si = 0; si < 4; ++si) {
                    double u = (i + (si + 0.5) / 4) / img.width, v = (j + (sj + 0.5) / 4) / img.height;
                    glm::dvec3 l = lighting::equirectDirection(u, v);
                    double nDotL = glm::dot(r, l);
                    if (nDotL <= 0) continue;
                    double dOmega = std::sin(kPi * v); // the common factors cancel
                    glm::dvec3 h = glm::normalize(l + r);
                    double w = nDotL * lighting::ggxD(glm::dot(r, h), alpha) * dOmega;
                    const float* p = &img.rgb[(size_t(j) * img.width + i) * 3];
                    acc += w * glm::dvec3(p[0], p[1], p[2]);
                    weight += w;
                }
    return acc / weight;
}

// Level `level` (face size n) of the specular cube `cube`, red channel, beside the exact value
// (exactPrefilter at `roughness`) of every texel, in face, row, column order.
void levelAgainstExact(const Scene& scene, uint32_t cube, uint32_t level, uint32_t n, const RadianceImage& img,
                       double roughness, std::vector<double>& got, std::vector<double>& want) {
    std::vector<float> t = texels(scene, cube, level);
    for (uint32_t face = 0; face < 6; ++face)
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                double d[3];
                cubeTexelDirection(face, i, j, n, d);
                want.push_back(exactPrefilter(img, {d[0], d[1], d[2]}, roughness).x);
                got.push_back(t[((size_t(face) * n + j) * n + i) * 4]);
            }
}

TEST_F(Environment, SunPixelsStayFiniteAndMakeNoFireflies) {
    // 1 nit everywhere, two 2x2 suns of 1e5 nits (above half's 65504), and three bad texels.
    const uint32_t W = 64, H = 32;
    RadianceImage img = constantImage(W, H, 1, 1, 1);
    auto set = [&](uint32_t i, uint32_t j, float v) {
        for (int c = 0; c < 3; ++c) img.rgb[(size_t(j) * W + i) * 3 + c] = v;
    };
    for (auto [i0, j0] : {std::pair{40u, 10u}, {12u, 14u}})
        for (uint32_t dj = 0; dj < 2; ++dj)
            for (uint32_t di = 0; di < 2; ++di) set(i0 + di, j0 + dj, 1e5f);
    RadianceImage bad = img;
    bad.rgb[(5 * W + 5) * 3] = NAN;
    bad.rgb[(6 * W + 7) * 3 + 1] = -3.0f;
    bad.rgb[(30 * W + 60) * 3 + 2] = INFINITY;
    const std::string path = writeImage("suns.exr", bad);
    auto loaded = loadRadianceImage(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->cleanedTexels, 3u);
    ASSERT_EQ(loaded->warnings.size(), 1u);
    EXPECT_NE(loaded->warnings[0].find(path), std::string::npos) << loaded->warnings[0];
    EXPECT_NE(loaded->warnings[0].find(" 3 texel"), std::string::npos) << loaded->warnings[0];
    img.rgb[(5 * W + 5) * 3] = 0; // what cleaning makes of them, for the reference below
    img.rgb[(6 * W + 7) * 3 + 1] = 0;
    img.rgb[(30 * W + 60) * 3 + 2] = 0;
    EXPECT_EQ(loaded->rgb, img.rgb);

    EnvironmentSettings s = smallSettings();
    s.specularSize = 32;
    s.specularLevels = 4; // 32, 16, 8, 4: the roughest level has 96 texels
    s.prefilterSamples = 256;
    SceneBuilder b;
    ASSERT_TRUE(addEnvironment(b, *loaded, s, EnvironmentSource::Image, "suns.exr", 2).ok());
    const pnb::Environment& e = *b.scene.environment;
    EXPECT_EQ(b.scene.textures.at(e.radiance).format, TextureFormat::RGBA32F);
    EXPECT_EQ(b.scene.textures.at(e.specular).format, TextureFormat::RGBA32F);
    for (uint32_t t : {e.radiance, e.specular})
        for (uint32_t m = 0; m < b.scene.textures.at(t).mipCount; ++m)
            for (float v : texels(b.scene, t, m)) ASSERT_TRUE(std::isfinite(v) && v >= 0) << t << " " << m;
    for (const glm::dvec3& n : sphereDirections(64)) {
        glm::dvec3 E = lighting::sh9Evaluate(shOf(e), n);
        for (int c = 0; c < 3; ++c) EXPECT_GE(E[c], 0.0) << n.x << " " << n.y << " " << n.z;
    }

    // The roughest level against the exact convolution, texel by texel: a firefly (one sample
    // landing on a sun at full weight) would be ~1e5 / 256 = 390 nits too bright in one texel.
    const uint32_t last = s.specularLevels - 1, n = s.specularSize >> last;
    std::vector<double> got, want;
    levelAgainstExact(b.scene, e.specular, last, n, img, 1.0, got, want);
    // 256 samples cannot resolve a sun of 4 texels exactly: the error is measured against the
    // peak. Unfiltered sampling measured 0.76 here and a max/median of 3.7 (the exact: 1.9);
    // filtered importance sampling 0.23 and 2.0 (environment_prefilter.cpp).
    const double peak = *std::max_element(want.begin(), want.end());
    double worstOfPeak = 0;
    for (size_t k = 0; k < got.size(); ++k)
        worstOfPeak = std::max(worstOfPeak, std::abs(got[k] - want[k]) / peak);
    EXPECT_LT(worstOfPeak, 0.3);
    auto maxOverMedian = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v.back() / v[v.size() / 2];
    };
    const double ratio = maxOverMedian(got), exactRatio = maxOverMedian(want);
    EXPECT_LT(ratio, 50.0);
    EXPECT_LT(ratio, 1.2 * exactRatio) << "exact " << exactRatio;
    std::printf("roughest level: max/median %.3f (exact %.3f), worst error %.3f of the peak\n",
                ratio, exactRatio, worstOfPeak);
}

TEST_F(Environment, PrefilterConvergesToTheExactGgxConvolution) {
    // With many samples every level m > 0 approaches the integral it estimates, for a smooth
    // environment and for a sharp sun alike: the filtering blurs what each sample reads, it does
    // not move the result.
    const uint32_t W = 64, H = 32;
    for (int variant = 0; variant < 2; ++variant) {
        RadianceImage img = constantImage(W, H, 1, 1, 1);
        for (uint32_t j = 0; j < H; ++j)
            for (uint32_t i = 0; i < W; ++i) {
                float v = variant == 0 ? (i >= W / 4 && i < 3 * W / 4 ? 10.0f : 1.0f)
                                       : (i >= 40 && i < 42 && j >= 10 && j < 12 ? 1e5f : 1.0f);
                for (int c = 0; c < 3; ++c) img.rgb[(j * W + i) * 3 + c] = v;
            }
        EnvironmentSettings s = smallSettings();
        s.specularSize = 16;
        s.specularLevels = 3; // roughness 0, 0.5, 1
        s.prefilterSamples = 4096;
        SceneBuilder b;
        ASSERT_TRUE(addEnvironment(b, img, s, EnvironmentSource::Image, "x", 2).ok());
        for (uint32_t level = 1; level < 3; ++level) {
            const uint32_t n = s.specularSize >> level;
            std::vector<double> got, want;
            levelAgainstExact(b.scene, b.scene.environment->specular, level, n, img, level / 2.0, got, want);
            const double peak = *std::max_element(want.begin(), want.end());
            for (size_t k = 0; k < got.size(); ++k)
                ASSERT_NEAR(got[k], want[k], 0.03 * peak) << "variant " << variant << " level " << level << " texel " << k;
        }
    }
}

TEST_F(Environment, LoaderErrorsAndWarningsNameTheFile) {
    const std::string missing = (dir / "no-such-sky.exr").string();
    auto r = loadRadianceImage(missing);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, ConvertErrorKind::Input);
    EXPECT_NE(r.error().message.find(missing), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << "one line";
    std::ofstream(dir / "junk.hdr") << "not an image";
    auto junk = loadRadianceImage((dir / "junk.hdr").string());
    ASSERT_FALSE(junk.ok());
    EXPECT_NE(junk.error().message.find("junk.hdr"), std::string::npos) << junk.error().message;
    // The memory budget refuses from the header, naming the file and the budget.
    const std::string eight = writeImage("eight.exr", constantImage(8, 4, 1, 1, 1));
    auto refused = loadRadianceImage(eight, 32 * kEnvironmentBytesPerTexel - 1);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find(eight), std::string::npos) << refused.error().message;
    EXPECT_NE(refused.error().message.find("memory budget"), std::string::npos) << refused.error().message;
    EXPECT_TRUE(loadRadianceImage(eight, 32 * kEnvironmentBytesPerTexel).ok());
    // Any size loads; only a 2:1 image (or a 1x1 constant) goes without the aspect warning.
    for (auto [w, h, warns] : {std::tuple{1u, 1u, false}, {8u, 4u, false}, {3u, 2u, true}}) {
        auto img = loadRadianceImage(writeImage("s" + std::to_string(w) + ".hdr",
                                                constantImage(w, h, 1, 2, 3)));
        ASSERT_TRUE(img.ok()) << img.error().message;
        EXPECT_EQ(img->width, w);
        EXPECT_EQ(!img->warnings.empty(), warns) << w << "x" << h;
        EXPECT_NEAR(img->rgb[1], 2.0f, 0.02f) << "Radiance HDR keeps the values (8-bit mantissa)";
    }
}

TEST_F(Environment, LargeImagesAreHalvedToTheHeightLimitKeepingTheMean) {
    RadianceImage img = constantImage(64, 32, 1, 1, 1);
    for (size_t k = 0; k < 64 * 3; ++k) img.rgb[k] = 5.0f; // a bright top row
    EnvironmentSettings s = smallSettings();
    s.maxRadianceHeight = 10;
    SceneBuilder b;
    auto sum = addEnvironment(b, img, s, EnvironmentSource::Image, "big", 1);
    ASSERT_TRUE(sum.ok());
    EXPECT_EQ(sum->downsampled, 2u);
    const TextureDesc& rad = b.scene.textures.at(b.scene.environment->radiance);
    EXPECT_EQ(rad.width, 16u);
    EXPECT_EQ(rad.height, 8u);
    EXPECT_EQ(rad.mipCount, 5u);
    EXPECT_EQ(rad.wrapU, Wrap::Repeat);
    EXPECT_EQ(rad.wrapV, Wrap::ClampToEdge);
    std::vector<float> top = texels(b.scene, b.scene.environment->radiance, 0);
    EXPECT_FLOAT_EQ(top[0], 2.0f) << "the top row of 4 averaged: (5 + 1 + 1 + 1) / 4";
    EXPECT_FLOAT_EQ(top[16 * 4], 1.0f);
}

// [SECTION] in a conversion

TEST_F(Environment, SkyFollowsTheScenesSunAndLightsTowardsIt) {
    ConvertSettings s;
    s.input = kBoxTextured;
    s.output = (dir / "sky.pnb").string();
    s.environment = smallSettings();
    s.environment.sky = true;
    auto sum = convertScene(s);
    ASSERT_TRUE(sum.ok()) << sum.error().message;
    ASSERT_TRUE(sum->environment.has_value());
    EXPECT_EQ(sum->environment->name, "preetham");
    auto c = Container::open(s.output);
    ASSERT_TRUE(c.ok());
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok());
    ASSERT_TRUE(scene->environment.has_value());
    const pnb::Environment& e = *scene->environment;
    EXPECT_EQ(e.source, EnvironmentSource::AnalyticSky);
    EXPECT_EQ(scene->str(e.name), "preetham");
    EXPECT_FLOAT_EQ(e.turbidity, 3.0f);
    EXPECT_FLOAT_EQ(e.groundAlbedo.y, 0.2f);
    // BoxTextured has no light: the sky follows the default sun, whose +Z points at the sun.
    ASSERT_EQ(scene->lights.lights.size(), 1u);
    EXPECT_FLOAT_EQ(e.sunIlluminance, scene->lights.lights[0].intensity);
    std::vector<Matrix4d> world = nodeWorldMatrices(scene->nodes);
    glm::dvec3 toSun(0);
    for (size_t i = 0; i < scene->nodes.nodes.size(); ++i)
        if (scene->nodes.nodes[i].light == 0) toSun = glm::normalize(glm::dvec3(world[i][8], world[i][9], world[i][10]));
    EXPECT_NEAR(e.sunDirection.x, toSun.x, 1e-5);
    EXPECT_NEAR(e.sunDirection.y, toSun.y, 1e-5);
    EXPECT_NEAR(e.sunDirection.z, toSun.z, 1e-5);
    EXPECT_GT(toSun.y, 0.5) << "the default sun is 50 degrees up";
    glm::dvec3 towards = lighting::sh9Evaluate(shOf(e), toSun);
    glm::dvec3 away = lighting::sh9Evaluate(shOf(e), -toSun);
    for (int c2 = 0; c2 < 3; ++c2) EXPECT_GT(towards[c2], away[c2]) << c2;
    // The sky keeps its physical ratio to the scene's sun (3 lux here): a clear sky's light on
    // a surface facing the sun is a tenth to a half of the direct sun's, not 10^4 times it.
    const double ratio = towards.y / e.sunIlluminance;
    EXPECT_GT(ratio, 0.1);
    EXPECT_LT(ratio, 0.5);
    const double physical = lighting::preethamSunIlluminance(3.0, toSun);
    EXPECT_GT(physical, 60000.0) << "a clear sun 50 degrees up";
    EXPECT_LT(physical, 110000.0);
}

TEST_F(Environment, SkyTakesTheSourcesFirstDirectionalLight) {
    // A point light first, then two suns: the sky follows the first directional one, whose node
    // shines down -Z along (0.4, -1, -0.6), so the sun is towards (-0.4, 1, 0.6).
    assets::gltf::Document doc = assets::buildOneTriangle();
    auto addLight = [&](assets::gltf::LightType type, float intensity, assets::gltf::Float3 forward) {
        assets::gltf::Light l;
        l.name = "light" + std::to_string(doc.lights.size());
        l.type = type;
        l.intensity = intensity;
        doc.lights.push_back(l);
        assets::gltf::Node n;
        n.name = l.name;
        n.light = int32_t(doc.lights.size() - 1);
        n.rotation = assets::gltf::lookRotation(forward);
        doc.nodes.push_back(n);
    };
    ASSERT_EQ(doc.lights.size(), 1u) << "one-triangle's own sun";
    doc.lights[0].type = assets::gltf::LightType::Point; // now the point light that comes first
    addLight(assets::gltf::LightType::Directional, 7.0f, {0.4f, -1.0f, -0.6f});
    addLight(assets::gltf::LightType::Directional, 2.0f, {-1.0f, -1.0f, 0.0f});
    ConvertSettings s;
    s.input = writeScene("lit", doc).string();
    s.output = (dir / "lit.pnb").string();
    s.environment = smallSettings();
    s.environment.sky = true;
    auto sum = convertScene(s);
    ASSERT_TRUE(sum.ok()) << sum.error().message;
    EXPECT_FALSE(sum->defaultSun);
    auto c = Container::open(s.output);
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok() && scene->environment);
    const glm::dvec3 want = glm::normalize(glm::dvec3(-0.4, 1.0, 0.6));
    EXPECT_NEAR(scene->environment->sunDirection.x, want.x, 1e-5);
    EXPECT_NEAR(scene->environment->sunDirection.y, want.y, 1e-5);
    EXPECT_NEAR(scene->environment->sunDirection.z, want.z, 1e-5);
    EXPECT_FLOAT_EQ(scene->environment->sunIlluminance, 7.0f);

    // What is stored is what the model used: it clamps turbidity to [2, 10].
    SceneBuilder b;
    PreethamSkyParams p;
    p.turbidity = 40.0;
    ASSERT_TRUE(addEnvironment(b, bakePreethamSky(p, 16), smallSettings(),
                               EnvironmentSource::AnalyticSky, "preetham", 1, &p).ok());
    EXPECT_FLOAT_EQ(b.scene.environment->turbidity, 10.0f);
}

TEST_F(Environment, OutputIsIdenticalForOneAndTwoJobs) {
    RadianceImage img = constantImage(32, 16, 1, 1, 1);
    for (size_t k = 0; k < img.rgb.size(); ++k) img.rgb[k] = float(1 + (k * 7919) % 13);
    img.rgb[100] = 2e5f;
    const std::string hdr = writeImage("env.exr", img);
    fs::path in = writeScene("room", assets::buildBoxRoomGltf({}));
    std::vector<std::vector<char>> outputs;
    for (uint32_t jobs : {1u, 2u}) {
        ConvertSettings s;
        s.input = in.string();
        s.output = (dir / ("j" + std::to_string(jobs) + ".pnb")).string();
        s.jobs = jobs;
        s.environment = smallSettings();
        s.environment.image = hdr;
        s.depfile = s.output + ".d";
        auto sum = convertScene(s);
        ASSERT_TRUE(sum.ok()) << sum.error().message;
        EXPECT_NE(std::find(sum->dependencies.begin(), sum->dependencies.end(), hdr),
                  sum->dependencies.end());
        std::vector<char> dep = bytesOf(s.depfile);
        EXPECT_NE(std::string(dep.begin(), dep.end()).find("env.exr"), std::string::npos);
        outputs.push_back(bytesOf(s.output));
    }
    EXPECT_EQ(outputs[0], outputs[1]);
}

TEST_F(Environment, LightingProgramsCarryIblOnlyWithAnEnvironment) {
    fs::path in = writeScene("room", assets::buildBoxRoomGltf({}));
    auto programs = [&](bool withEnvironment) {
        ConvertSettings s;
        s.input = in.string();
        s.output = (dir / "p.pnb").string();
        if (withEnvironment) {
            s.environment = smallSettings();
            s.environment.sky = true;
        }
        auto sum = convertScene(s);
        EXPECT_TRUE(sum.ok()) << sum.error().message;
        const std::string omitted =
            "environment (no --environment or --sky): no sky light, IBL programs, cube map or SH";
        EXPECT_EQ(std::count(sum->omitted.begin(), sum->omitted.end(), omitted),
                  withEnvironment ? 0 : 1);
        auto c = Container::open(s.output);
        auto scene = readScene(*c);
        EXPECT_EQ(scene->environment.has_value(), withEnvironment);
        std::vector<std::pair<std::string, std::vector<std::string>>> out;
        for (const Program& p : scene->programs) {
            std::vector<std::string> d;
            for (StringRef r : p.defines) d.emplace_back(scene->str(r));
            out.emplace_back(std::string(scene->str(p.name)), d);
        }
        return out;
    };
    auto has = [](const std::vector<std::string>& d, const char* x) {
        return std::find(d.begin(), d.end(), x) != d.end();
    };
    int lighting = 0;
    for (const auto& [name, defines] : programs(true)) {
        if (name == "forward" || name == "deferred_lighting") {
            EXPECT_TRUE(has(defines, "IBL")) << name;
            ++lighting;
        } else {
            EXPECT_FALSE(has(defines, "IBL")) << name << ": not a lighting program";
        }
    }
    EXPECT_GE(lighting, 2) << "the box room has deferred and forward (glass) materials";
    for (const auto& [name, defines] : programs(false)) EXPECT_FALSE(has(defines, "IBL")) << name;
    // With GI too, an opaque forward material keeps its G-buffer twin, whose defines are the
    // forward program's but SHADOWS, GI and IBL (FORMAT.md "PROG"): how the player finds it.
    // The twin draws the reflective shadow map, which no environment lights: no IBL in it.
    std::ofstream(dir / "forward.json") << R"({"materials": {"*": {"shading_path": "forward"}}})";
    ConvertSettings s;
    s.input = kBoxTextured;
    s.output = (dir / "gi.pnb").string();
    s.sidecar = (dir / "forward.json").string();
    s.environment = smallSettings();
    s.environment.sky = true;
    s.renderSettings.emplace_back("gi.enabled", "true");
    ASSERT_TRUE(convertScene(s).ok());
    auto c = Container::open(s.output);
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok());
    ASSERT_EQ(scene->materials.size(), 1u);
    const Program& forward = scene->programs.at(scene->materials[0].program);
    ASSERT_EQ(scene->str(forward.name), "forward");
    std::vector<std::string> twin;
    bool ibl = false, gi = false;
    for (StringRef r : forward.defines) {
        std::string d(scene->str(r));
        ibl |= d == "IBL";
        gi |= d == "GI";
        if (d != "SHADOWS" && d != "GI" && d != "IBL") twin.push_back(d);
    }
    EXPECT_TRUE(ibl && gi);
    int twins = 0;
    for (const Program& p : scene->programs) {
        std::vector<std::string> d;
        for (StringRef r : p.defines) d.emplace_back(scene->str(r));
        twins += scene->str(p.name) == "gbuffer" && d == twin;
        if (scene->str(p.name) == "gbuffer") {
            EXPECT_FALSE(has(d, "IBL"));
        }
    }
    EXPECT_EQ(twins, 1);
}

TEST_F(Environment, WithoutAnEnvironmentTheContainerIsUnchanged) {
    // The container of a conversion without an environment must not depend on this feature:
    // the same bytes whether or not the (unused) environment settings differ.
    ConvertSettings a, b2;
    a.input = b2.input = kBoxTextured;
    a.output = (dir / "a.pnb").string();
    b2.output = (dir / "b.pnb").string();
    b2.environment.specularSize = 8; // not used: no image, no sky
    b2.environment.skyTurbidity = 9;
    ASSERT_TRUE(convertScene(a).ok());
    ASSERT_TRUE(convertScene(b2).ok());
    EXPECT_EQ(bytesOf(a.output), bytesOf(b2.output));
    auto c = Container::open(a.output);
    auto scene = readScene(*c);
    ASSERT_TRUE(scene.ok());
    EXPECT_FALSE(scene->environment.has_value());
    EXPECT_EQ(scene->textures.size(), 1u) << "only the box's own texture";
}

// [SECTION] the command line

TEST_F(Environment, CommandLineSkyEnvironmentAndTheirErrors) {
    const std::string log = (dir / "log.txt").string();
    auto run = [&](std::vector<std::string> args) {
        args.insert(args.begin(), PNB_CONVERT_EXE);
        return runChild(args, log);
    };
    const std::string out = (dir / "o.pnb").string();
    auto sky = run({kBoxTextured, "-o", out, "--sky", "--specular-size", "16", "--sky-turbidity",
                    "4", "--sky-ground-albedo", "0.3", "--environment-size", "64"});
    EXPECT_EQ(sky.exitCode, 0) << sky.output;
    EXPECT_NE(sky.output.find("environment: preetham 128x64 RGBA16F, specular cube 16^2 x 5 levels"), std::string::npos) << sky.output;
    EXPECT_NE(sky.output.find("programs"), std::string::npos);
    {
        auto c = Container::open(out);
        ASSERT_TRUE(c.ok());
        auto scene = readScene(*c);
        ASSERT_TRUE(scene.ok() && scene->environment);
        EXPECT_FLOAT_EQ(scene->environment->turbidity, 4.0f);
        EXPECT_FLOAT_EQ(scene->environment->groundAlbedo.x, 0.3f);
        EXPECT_EQ(scene->textures.at(scene->environment->specular).width, 16u);
    }
    const std::string missing = (dir / "missing.exr").string();
    auto noFile = run({kBoxTextured, "-o", out, "--environment", missing});
    EXPECT_EQ(noFile.exitCode, 2) << noFile.output;
    EXPECT_NE(noFile.output.find("Error: environment image 'missing.exr' (" + missing + "): file not found"),
              std::string::npos)
        << noFile.output;
    auto both = run({kBoxTextured, "-o", out, "--sky", "--environment", missing});
    EXPECT_EQ(both.exitCode, 1) << both.output;
    for (std::vector<std::string> bad :
         {std::vector<std::string>{"--specular-size", "100"}, {"--specular-size", "2"},
          {"--sky-turbidity", "11"}, {"--sky-ground-albedo", "x"}, {"--environment-size", "0"}}) {
        bad.insert(bad.begin(), {kBoxTextured, "-o", out, "--sky"});
        auto r = run(bad);
        EXPECT_EQ(r.exitCode, 1) << bad[4] << " " << bad[5] << ": " << r.output;
    }
}

} // namespace

namespace {

// The environment named by a sidecar: an image relative to the sidecar, or the sky with its
// parameters; the command line wins; bad keys are errors naming the sidecar.
TEST_F(Environment, TheSidecarCanNameTheEnvironmentAndTheCommandLineWins) {
    RadianceImage grey;
    grey.width = 2;
    grey.height = 1;
    grey.rgb.assign(6, 0.5f);
    fs::create_directories(dir / "skies");
    writeImage("skies/grey.exr", grey);
    auto convertWith = [&](const std::string& sidecarJson, const EnvironmentSettings& cli,
                           std::optional<pnb::Environment>& out) -> std::string {
        const fs::path sidecar = dir / "scene.pnb.json";
        std::ofstream(sidecar) << sidecarJson;
        ConvertSettings s;
        s.input = kBoxTextured;
        s.output = (dir / "out.pnb").string();
        s.sidecar = sidecar.string();
        s.environment = cli;
        s.environment.skyWidth = 32;
        s.environment.specularSize = 8;
        s.environment.specularLevels = 2;
        s.environment.prefilterSamples = 16;
        s.environment.lutSize = 8;
        s.environment.lutSamples = 16;
        auto r = convertScene(s);
        if (!r) return r.error().message;
        auto c = Container::open(s.output);
        auto scene = readScene(*c);
        if (!scene) return scene.error().describe();
        out = scene->environment;
        return "";
    };
    std::optional<pnb::Environment> e;
    ASSERT_EQ(convertWith(R"({"environment": {"image": "skies/grey.exr"}})", {}, e), "");
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(e->source, EnvironmentSource::Image);
    EXPECT_NEAR(e->irradianceSh[0].x, 0.5 * kPi * 2.0 * std::sqrt(kPi), 1e-3) << "pi L in band 0 x 2 sqrt(pi)";
    ASSERT_EQ(convertWith(R"({"environment": {"sky": true, "turbidity": 5, "ground_albedo": 0.4}})", {}, e), "");
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(e->source, EnvironmentSource::AnalyticSky);
    EXPECT_FLOAT_EQ(e->turbidity, 5.0f);
    EXPECT_FLOAT_EQ(e->groundAlbedo.x, 0.4f);
    EnvironmentSettings cliSky;
    cliSky.sky = true;
    ASSERT_EQ(convertWith(R"({"environment": {"image": "skies/grey.exr"}})", cliSky, e), "");
    EXPECT_EQ(e->source, EnvironmentSource::AnalyticSky) << "the command line wins";
    ASSERT_EQ(convertWith(R"({"materials": {}})", {}, e), "");
    EXPECT_FALSE(e.has_value());
    // Each error names what is wrong: the sidecar, or the missing image the sidecar named.
    const std::pair<const char*, const char*> bad[] = {
        {R"({"environment": {"image": 3}})", "scene.pnb.json"},
        {R"({"environment": {"sky": true, "image": "a.exr"}})", "scene.pnb.json"},
        {R"({"environment": {"ground_albedo": 2}})", "scene.pnb.json"},
        {R"({"environment": []})", "scene.pnb.json"},
        {R"({"environment": {"image": "skies/missing.exr"}})", "missing.exr"}};
    for (const auto& [json, named] : bad) {
        std::string error = convertWith(json, {}, e);
        EXPECT_NE(error.find(named), std::string::npos) << json << " -> " << error;
    }
}

} // namespace
