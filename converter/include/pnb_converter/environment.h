// pnb_converter/environment.h — the environment of a scene for image-based lighting: an
// equirectangular radiance image (a file, or the analytic Preetham sky baked at the scene's sun)
// turned into the ENVM chunk and its three textures (docs/FORMAT.md "ENVM"):
//   - radiance: the equirect image itself, RGBA16F (RGBA32F when a value exceeds half's 65504,
//     so a 1e5-nit sun stays finite), full box-filtered mip chain, wrapping in u;
//   - specular: a cube whose level m is the radiance convolved with the GGX lobe of roughness
//     m / (levels - 1) (split-sum prefilter, N = V = R), by filtered importance sampling;
//   - brdfLut: the split-sum table (A, B), RG16F;
//   - irradianceSh: 9 SH coefficients of the irradiance, windowed so it is never negative.
// Everything is computed on the CPU with the shared lighting math (pnb_lighting: sh9.h, split_sum.h,
// sky_preetham.h), so converter and shaders share one definition of each formula.
//
// Files: environment_image.cpp (load, clean, sky bake), environment_prefilter.cpp (the cube),
// environment.cpp (mips, formats, the LUT, SH and the chunk).
//
// Deterministic: the bytes do not depend on `jobs` (work is split by texel row; every texel is
// computed alone, in a fixed order of operations).
//
// Does NOT do: the sun disc (the scene's directional light is the sun), rotating the
// environment, cube-map or light-probe inputs (equirectangular only), compression of the texels.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/error.h"
#include "pnb/scene_builder.h"
#include "pnb_converter/scene_ir.h"
#include "pnb_lighting/sky_preetham.h"

namespace pnb::converter {

using lighting::PreethamSkyParams;

// Equirectangular radiance (FORMAT.md "ENVM": row 0 = top = zenith, u = 1/2 looks along +X),
// linear, nits, three floats per texel.
struct RadianceImage {
    uint32_t width = 0, height = 0;
    std::vector<float> rgb;
    // Filled by loadRadianceImage: texels whose NaN, infinite or negative values were set to 0,
    // and warnings (each one line naming the file) for the summary.
    uint64_t cleanedTexels = 0;
    std::vector<std::string> warnings;
};

struct EnvironmentSettings {
    std::string image;          // equirect .hdr/.exr (anything OpenImageIO reads); "" = none
    bool sky = false;           // analytic Preetham sky following the scene's sun
    float skyTurbidity = 3.0f;
    float skyGroundAlbedo = 0.2f;
    uint32_t skyWidth = 512;    // baked sky size (height = width/2)
    uint32_t maxRadianceHeight = 1024; // larger images are box-downsampled by 2 until they fit
    uint32_t specularSize = 128;       // cube face size of level 0 (power of two, >= 4)
    uint32_t specularLevels = 6;       // roughness levels (clamped to the face's mip count)
    uint32_t prefilterSamples = 256;   // GGX samples per texel
    uint32_t lutSize = 64;
    uint32_t lutSamples = 512;
    bool any() const { return sky || !image.empty(); }
};

// What addEnvironment wrote, for the summary.
struct EnvironmentSummary {
    EnvironmentSource source = EnvironmentSource::Image;
    std::string name;
    uint32_t radianceWidth = 0, radianceHeight = 0, radianceMips = 0;
    TextureFormat radianceFormat = TextureFormat::RGBA16F;
    uint32_t specularSize = 0, specularLevels = 0;
    TextureFormat specularFormat = TextureFormat::RGBA16F;
    uint32_t lutSize = 0;
    uint64_t bytes = 0;          // texel bytes of the three textures, all levels
    uint64_t cleanedTexels = 0;  // non-finite or negative texels set to 0 (load and bake)
    uint32_t downsampled = 0;    // times the image was halved to fit maxRadianceHeight and
                                 // kMaxPortableTextureSize
    bool generated = false;      // the converter's default (kDefaultEnvironmentName)
    double seconds = 0;          // bakeEnvironment's time (mips, SH, cube, LUT); convertScene
                                 // reports its whole stage (with the load or the sky)
};

// Loads the first three channels of an image file (grey replicated) as linear radiance and
// cleans it (cleanRadiance). Files with integer samples (PNG, JPEG...) are taken as sRGB-encoded
// and linearised, with a warning (1.0 becomes 1 nit). Errors (Input) name the path: missing,
// unreadable, zero size, or declaring more texels than loading and baking it may hold in
// `maxMemoryBytes` (kEnvironmentBytesPerTexel each; 0 = defaultMemoryBudget()), refused from the
// header before any pixel is read. Any size is accepted otherwise (1x1 is a constant
// environment); a width that is not twice the height warns (the image is still mapped onto the
// whole sphere).
Result<RadianceImage, ConvertError> loadRadianceImage(const std::string& path,
                                                      uint64_t maxMemoryBytes = 0);

// An upper bound of the bytes per source texel that loading and baking an image holds at its
// peak: the decoder's native pixels (up to 16), float RGBA (16), the RGB image and its cleaned
// copy (24), level 0 and the mips as float RGBA (22) and packed (22), the builder's copy (22).
inline constexpr uint64_t kEnvironmentBytesPerTexel = 128;

// Sets NaN, infinite and negative values to 0 (radiance is non-negative and finite) and returns
// how many texels had one.
uint64_t cleanRadiance(RadianceImage& image);

// The Preetham sky sampled at the texel centres of a width x max(1, width/2) equirect image
// (width >= 1). No sun disc.
RadianceImage bakePreethamSky(const PreethamSkyParams& params, uint32_t width);

// The environment computed, not yet in a scene (bakeEnvironment; appendEnvironment adds it).
struct BakedEnvironment {
    struct Texture {
        TextureDesc desc; // name left kNone
        std::vector<std::vector<std::byte>> levels; // level 0 first, all faces of a level
    };
    Texture radiance, specular, lut;
    Environment envm; // name and texture indices left kNone
    EnvironmentSummary summary;
};

// The whole bake. Errors (Input): a settings value out of range (specularSize not a power of two
// >= 4, zero sizes or sample counts), an empty image. `sky`: the sky's inputs to store (source
// AnalyticSky); nullptr for an image. ENVM's sunIlluminance is then the largest channel of
// sky->sunIlluminance (lux per channel); convertScene stores the sun light's intensity instead.
Result<BakedEnvironment, ConvertError> bakeEnvironment(const RadianceImage& radiance,
                                                       const EnvironmentSettings& s,
                                                       EnvironmentSource source,
                                                       std::string_view name, uint32_t jobs,
                                                       const PreethamSkyParams* sky = nullptr);

// Appends the three textures (TEXR + all TMIP levels, data kept by the builder) after the
// textures already in b.scene and sets b.scene.environment to the chunk referring to them.
EnvironmentSummary appendEnvironment(SceneBuilder& b, const BakedEnvironment& baked,
                                     std::string_view name);

// bakeEnvironment then appendEnvironment.
Result<EnvironmentSummary, ConvertError> addEnvironment(SceneBuilder& b,
                                                        const RadianceImage& radiance,
                                                        const EnvironmentSettings& s,
                                                        EnvironmentSource source,
                                                        std::string_view name, uint32_t jobs,
                                                        const PreethamSkyParams* sky = nullptr);

// "RGBA16F", for summaries.
const char* textureFormatName(TextureFormat f);

// [SECTION] the neutral default environment ("default-studio", docs/CONVERTER.md "Defaults")
//
// What convertScene adds when the source has no lights and no environment was asked for
// (ConvertSettings::defaultEnvironment; pnb-convert --no-default-environment leaves it out), as
// glTF viewers light such a model with a neutral studio IBL. Grey (R = G = B), in nits beside the
// default sun's 3 lux, for the player's default exposure 1 and ACES tone mapping:
//   - a gradient: kStudioZenith straight up, kStudioHorizon at the horizon (linear in the
//     direction's height y), kStudioGround below, blended over the soft band y in [-0.15, 0];
//   - kStudioLights soft discs ("softboxes": full radiance inside 0.75 x radius, none outside
//     1.25 x radius, smoothstep between) that polished metals reflect as highlights.
// Mean radiance 0.41 nits. A white diffuse surface facing up receives 2.7 lux from it (it shows
// 0.87 nits: ACES 0.77, sRGB 0.89), one facing the default camera 1.6 lux (0.51 nits: sRGB 0.81),
// one facing down 0.25 lux (0.08 nits: sRGB 0.34); the default sun adds up to 3 lux (0.95 nits)
// on its side and keeps its shadows, so a lit white face stays below ACES's shoulder (about
// 1.5-1.8 nits, sRGB 0.93-0.95) and a shadowed one is grey, not black. The background seen by the
// default camera (30 degrees down) is the floor and the band above it: 0.08-0.2 nits, sRGB
// 0.33-0.58. Directions: elevation above the horizon, azimuth from
// +Z (where the default camera looks from) towards +X, as the default sun's.
inline constexpr const char* kDefaultEnvironmentName = "default-studio";
inline constexpr float kStudioZenith = 0.35f;
inline constexpr float kStudioHorizon = 0.20f;
inline constexpr float kStudioGround = 0.08f;
struct StudioLight {
    float azimuthDegrees, elevationDegrees, radiusDegrees, radiance;
};
inline constexpr StudioLight kStudioLights[] = {
    {45.0f, 30.0f, 18.0f, 3.0f},    // key: front right, the side the default sun lights
    {-60.0f, 20.0f, 20.0f, 1.2f},   // fill: front left, larger and dimmer
    {0.0f, 75.0f, 25.0f, 1.5f},     // overhead
    {180.0f, 40.0f, 15.0f, 2.0f},   // rim: behind the model, above the default frame
};
inline constexpr uint32_t kStudioWidth = 128; // equirect 128 x 64 (2.8 degrees a texel)

// The studio's radiance in unit direction d (world, +Y up), nits.
float studioRadiance(const double d[3]);

// The studio sampled at the texel centres of a width x max(1, width/2) equirect image.
RadianceImage bakeDefaultStudio(uint32_t width = kStudioWidth);

// The bake settings of the default environment: a 32^2 specular cube of 6 levels at 128 samples
// and the default 64^2 LUT. The studio is smooth (its softboxes' edges span 9 degrees or more),
// so this is enough for a mirror, and it keeps what every lightless file carries small: about
// 160 KiB of texels (the defaults, 256-texel image and 128^2 cube, would be 1 MiB).
EnvironmentSettings defaultStudioSettings();

// The default environment, baked once per process (every conversion that adds it writes the same
// bytes; a batch bakes it once), `generated` set. Thread-safe.
const BakedEnvironment& defaultStudioEnvironment(uint32_t jobs);

// [SECTION] internals, exposed for the tests

// The direction of cube texel centre (i, j) of face f (0..5 = +X -X +Y -Y +Z -Z) of a
// size x size face, OpenGL's cube-map orientation (FORMAT.md "TEXR"), row j = 0 stored first
// (t = 0). Unit length.
void cubeTexelDirection(uint32_t face, uint32_t i, uint32_t j, uint32_t size, double out[3]);

} // namespace pnb::converter
