// converter/src/environment.cpp — the ENVM chunk and its textures from a radiance image
// (environment.h): size limit, mip chain, storage formats, irradiance SH, the specular cube
// (environment_prefilter.cpp) and the split-sum table.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <optional>

#include "environment_internal.h"
#include "parallel_for.h"
#include "pnb_converter/environment.h"
#include "pnb_lighting/sh9.h"
#include "pnb_lighting/split_sum.h"

namespace pnb::converter {

namespace {

using environment_detail::ImageF;

constexpr float kHalfMax = 65504.0f;

ConvertError settingsError(const std::string& what) {
    return ConvertError{ConvertErrorKind::Input, "environment: " + what};
}

bool anyAbove(const std::vector<ImageF>& levels, float limit) {
    for (const ImageF& l : levels)
        for (size_t t = 0; t < l.texelCount(); ++t)
            for (int c = 0; c < 3; ++c)
                if (l.texels[t * 4 + c] > limit) return true;
    return false;
}

// RGBA texels as RGBA16F (round to nearest even; values were checked to fit) or RGBA32F.
std::vector<std::byte> packRgba(const ImageF& level, TextureFormat format) {
    const size_t values = level.texelCount() * 4;
    std::vector<std::byte> out;
    if (format == TextureFormat::RGBA32F) {
        out.resize(values * 4);
        std::memcpy(out.data(), level.texels.data(), out.size());
        return out;
    }
    out.resize(values * 2);
    for (size_t k = 0; k < values; ++k) {
        const uint16_t h = texture_detail::floatToHalf(level.texels[k]);
        std::memcpy(out.data() + k * 2, &h, 2);
    }
    return out;
}

// Half when every value fits, else float: a sun above 65504 nits must not become infinity.
TextureFormat hdrFormat(const std::vector<ImageF>& levels) {
    return anyAbove(levels, kHalfMax) ? TextureFormat::RGBA32F : TextureFormat::RGBA16F;
}

uint32_t fullMipCount(uint32_t w, uint32_t h) {
    uint32_t n = 1;
    while (std::max(w, h) >> n) ++n;
    return n;
}

} // namespace

const char* textureFormatName(TextureFormat f) {
    static const char* kNames[] = {"R8",    "RG8",     "RGB8",  "RGBA8", "R16F",
                                   "RG16F", "RGBA16F", "R32F",  "RG32F", "RGBA32F",
                                   "BC1",   "BC3",     "BC4",   "BC5",   "BC7"};
    return size_t(f) < std::size(kNames) ? kNames[size_t(f)] : "?";
}

Result<BakedEnvironment, ConvertError> bakeEnvironment(const RadianceImage& radiance,
                                                       const EnvironmentSettings& s,
                                                       EnvironmentSource source,
                                                       std::string_view name, uint32_t jobs,
                                                       const PreethamSkyParams* sky) {
    const auto start = std::chrono::steady_clock::now();
    if (radiance.width == 0 || radiance.height == 0 ||
        radiance.rgb.size() < size_t(radiance.width) * radiance.height * 3)
        return settingsError("the radiance image '" + std::string(name) + "' is empty");
    if (s.specularSize < 4 || (s.specularSize & (s.specularSize - 1)) != 0)
        return settingsError("specular cube size " + std::to_string(s.specularSize) +
                             " is not a power of two >= 4");
    if (s.specularLevels == 0 || s.prefilterSamples == 0 || s.lutSize == 0 ||
        s.lutSamples == 0 || s.maxRadianceHeight == 0)
        return settingsError("specular levels, sample counts, the table size and the maximum "
                             "radiance height must be at least 1");

    BakedEnvironment out;
    EnvironmentSummary& sum = out.summary;
    sum.source = source;
    sum.name = std::string(name);
    sum.cleanedTexels = radiance.cleanedTexels;

    // [SECTION] radiance: clean (callers may build images themselves), fit, mip chain
    std::vector<ImageF> mips(1);
    {
        RadianceImage clean = radiance;
        sum.cleanedTexels += cleanRadiance(clean);
        ImageF& l0 = mips[0];
        l0.width = clean.width;
        l0.height = clean.height;
        l0.texels.resize(l0.texelCount() * 4);
        for (size_t t = 0; t < l0.texelCount(); ++t) {
            std::memcpy(&l0.texels[t * 4], &clean.rgb[t * 3], 3 * sizeof(float));
            l0.texels[t * 4 + 3] = 1.0f;
        }
    }
    // Halving with the box filter keeps every texel's energy (the mean radiance, hence the SH,
    // is unchanged), which a resampling filter with negative lobes would not near a sun.
    // And no edge beyond what every OpenGL 4.5 GPU takes (a 65535x1 image drew nothing).
    while (mips[0].height > s.maxRadianceHeight || mips[0].width > kMaxPortableTextureSize) {
        mips[0] = texture_detail::downsample(mips[0]);
        ++sum.downsampled;
    }
    const uint32_t radianceMips = fullMipCount(mips[0].width, mips[0].height);
    for (uint32_t m = 1; m < radianceMips; ++m) mips.push_back(texture_detail::downsample(mips[m - 1]));

    // [SECTION] irradiance SH of what is stored (level 0), windowed to stay non-negative
    {
        std::vector<float> rgb(mips[0].texelCount() * 3);
        for (size_t t = 0; t < mips[0].texelCount(); ++t)
            std::memcpy(&rgb[t * 3], &mips[0].texels[t * 4], 3 * sizeof(float));
        const lighting::Sh9Rgb irradiance = lighting::sh9IrradianceCoefficients(
            lighting::sh9ProjectEquirect(rgb, mips[0].width, mips[0].height),
            lighting::ShWindow::NonNegative);
        for (size_t k = 0; k < 9; ++k)
            out.envm.irradianceSh[k] = {float(irradiance.c[k].x), float(irradiance.c[k].y),
                                        float(irradiance.c[k].z)};
    }

    // [SECTION] the three textures
    auto texture = [](TextureDimension dim, TextureFormat format, uint32_t w, uint32_t h,
                      uint32_t mipCount, Wrap wrapU, Wrap wrapV) {
        BakedEnvironment::Texture t;
        t.desc.dimension = dim;
        t.desc.format = format;
        t.desc.colorSpace = ColorSpace::Linear;
        t.desc.width = w;
        t.desc.height = h;
        t.desc.layers = dim == TextureDimension::Cube ? 6 : 1;
        t.desc.mipCount = mipCount;
        t.desc.minFilter = mipCount > 1 ? MinFilter::LinearMipLinear : MinFilter::Linear;
        t.desc.magFilter = MagFilter::Linear;
        t.desc.wrapU = wrapU;
        t.desc.wrapV = wrapV;
        return t;
    };
    // Radiance: periodic in azimuth, clamped at the poles.
    out.radiance = texture(TextureDimension::Tex2D, hdrFormat(mips), mips[0].width, mips[0].height,
                           radianceMips, Wrap::Repeat, Wrap::ClampToEdge);
    for (const ImageF& l : mips) out.radiance.levels.push_back(packRgba(l, out.radiance.desc.format));

    const uint32_t cubeLevels = std::min(s.specularLevels, fullMipCount(s.specularSize, s.specularSize));
    const std::vector<ImageF> cube = environment_detail::prefilterSpecularCube(
        mips, s.specularSize, cubeLevels, s.prefilterSamples, jobs);
    out.specular = texture(TextureDimension::Cube, hdrFormat(cube), s.specularSize, s.specularSize,
                           cubeLevels, Wrap::ClampToEdge, Wrap::ClampToEdge);
    for (const ImageF& l : cube) out.specular.levels.push_back(packRgba(l, out.specular.desc.format));

    // The table: splitSumLut's row j is roughness (j + 0.5) / H and its first row comes first,
    // which is FORMAT.md's order (row 0 first, t = 0) as it is. A and B lie in [0, 1]: half.
    out.lut = texture(TextureDimension::Tex2D, TextureFormat::RG16F, s.lutSize, s.lutSize, 1,
                      Wrap::ClampToEdge, Wrap::ClampToEdge);
    {
        // Its rows on the bake's threads: the table was most of the default studio's bake time
        // (0.1 of 0.13 s on one thread), and is the same for every environment.
        std::vector<float> ab(size_t(s.lutSize) * s.lutSize * 2);
        parallelFor(s.lutSize, jobs, [&](size_t j) {
            lighting::splitSumLutRow(s.lutSize, s.lutSize, s.lutSamples, uint32_t(j),
                                     &ab[j * s.lutSize * 2]);
        });
        std::vector<std::byte> bytes(ab.size() * 2);
        for (size_t k = 0; k < ab.size(); ++k) {
            const uint16_t h = texture_detail::floatToHalf(ab[k]);
            std::memcpy(bytes.data() + k * 2, &h, 2);
        }
        out.lut.levels.push_back(std::move(bytes));
    }

    // [SECTION] the chunk's own fields
    out.envm.source = source;
    if (sky) {
        const glm::dvec3 d = glm::length(sky->sunDirection) > 0 ? glm::normalize(sky->sunDirection)
                                                                : glm::dvec3(0, 1, 0);
        out.envm.sunDirection = {float(d.x), float(d.y), float(d.z)};
        // What the model used (it clamps turbidity to its fit's [2, 10] and albedo to [0, 1]), so
        // that a reader recomputing the sky from ENVM gets this one.
        out.envm.turbidity = float(lighting::PreethamSky(*sky).turbidity());
        const glm::dvec3 albedo = glm::clamp(sky->groundAlbedo, 0.0, 1.0);
        out.envm.groundAlbedo = {float(albedo.x), float(albedo.y), float(albedo.z)};
        // The scene's sun in lux: its luminous channel is what a reader puts beside the sky.
        out.envm.sunIlluminance = float(std::max({sky->sunIlluminance.x, sky->sunIlluminance.y,
                                                  sky->sunIlluminance.z}));
    }

    sum.radianceWidth = out.radiance.desc.width;
    sum.radianceHeight = out.radiance.desc.height;
    sum.radianceMips = radianceMips;
    sum.radianceFormat = out.radiance.desc.format;
    sum.specularSize = s.specularSize;
    sum.specularLevels = cubeLevels;
    sum.specularFormat = out.specular.desc.format;
    sum.lutSize = s.lutSize;
    for (const BakedEnvironment::Texture* t : {&out.radiance, &out.specular, &out.lut})
        for (const auto& l : t->levels) sum.bytes += l.size();
    sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

EnvironmentSummary appendEnvironment(SceneBuilder& b, const BakedEnvironment& baked,
                                     std::string_view name) {
    Scene& scene = b.scene;
    Environment envm = baked.envm;
    envm.name = b.intern(name);
    auto add = [&](const BakedEnvironment::Texture& t, const char* textureName) {
        const uint32_t index = uint32_t(scene.textures.size());
        TextureDesc desc = t.desc;
        desc.name = b.intern(textureName);
        scene.textures.push_back(desc);
        for (uint32_t level = 0; level < t.levels.size(); ++level)
            scene.textureMips.push_back({index, level, std::max(1u, desc.width >> level),
                                         std::max(1u, desc.height >> level), b.keep(t.levels[level])});
        return index;
    };
    envm.radiance = add(baked.radiance, "environment");
    envm.specular = add(baked.specular, "environment-specular");
    envm.brdfLut = add(baked.lut, "environment-brdf-lut");
    scene.environment = envm;
    EnvironmentSummary sum = baked.summary;
    sum.name = std::string(name);
    return sum;
}

Result<EnvironmentSummary, ConvertError> addEnvironment(SceneBuilder& b,
                                                        const RadianceImage& radiance,
                                                        const EnvironmentSettings& s,
                                                        EnvironmentSource source,
                                                        std::string_view name, uint32_t jobs,
                                                        const PreethamSkyParams* sky) {
    auto baked = bakeEnvironment(radiance, s, source, name, jobs, sky);
    if (!baked) return baked.error();
    return appendEnvironment(b, *baked, name);
}

EnvironmentSettings defaultStudioSettings() {
    EnvironmentSettings s;
    s.specularSize = 32;
    s.specularLevels = 6;
    s.prefilterSamples = 128;
    return s;
}

const BakedEnvironment& defaultStudioEnvironment(uint32_t jobs) {
    static std::once_flag once;
    static std::optional<BakedEnvironment> baked;
    std::call_once(once, [jobs] {
        // Fixed, valid settings and a non-empty image: the bake cannot fail.
        auto r = bakeEnvironment(bakeDefaultStudio(), defaultStudioSettings(),
                                 EnvironmentSource::Image, kDefaultEnvironmentName, jobs);
        baked = std::move(*r);
        baked->envm.generated = true;
        baked->summary.generated = true;
    });
    return *baked;
}

} // namespace pnb::converter
