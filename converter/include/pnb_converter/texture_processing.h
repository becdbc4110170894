// pnb_converter/texture_processing.h — source images into container-ready textures.
//
// Per texture: decode (OpenImageIO: PNG, JPEG, TGA, BMP, EXR, HDR, and what else it reads);
// resize to --max-texture-size; build the full mip chain filtered in linear light (sRGB data is
// linearised before filtering and re-encoded after); preserve alpha coverage in the mips of
// alpha-masked textures; store only the channels its uses read, dropping constant channels and
// merging duplicates into a swizzle (greyscale RGBA → R8 + swizzle R,R,R,One); optionally block
// compress (BC1/BC3/BC4/BC5 with libsquish) and report the PSNR it cost. Textures are processed
// in parallel; the result does not depend on the number of jobs.
//
// Does NOT do: deciding usages (the caller groups material slots per image), writing the
// container.
//
// Based on: Castaño, "Computing Alpha Mipmaps" (2010) for coverage preservation.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/error.h"
#include "pnb_converter/scene_ir.h"

namespace pnb::converter {

// Which source channels are read, and how they are interpreted.
struct TextureRequest {
    const IrImage* image = nullptr;
    std::string name;
    ColorSpace colorSpace = ColorSpace::Linear; // Srgb for base colour and emissive
    bool channels[4] = {true, true, true, true}; // r, g, b, a read by some material slot
    bool alphaMask = false;   // alpha is compared with alphaCutoff (MASK materials)
    float alphaCutoff = 0.5f;
    MinFilter minFilter = MinFilter::LinearMipLinear;
    MagFilter magFilter = MagFilter::Linear;
    Wrap wrapU = Wrap::Repeat, wrapV = Wrap::Repeat;
    // Set for a KHR_materials_pbrSpecularGlossiness material's converted texture: `image` is its
    // diffuse texture (nullptr: white), `specularGlossiness` its specular-glossiness texture
    // (nullptr: white), sampled at the diffuse texture's texels; the texels are converted with
    // `factors` (pnb_converter/spec_gloss.h) into base colour (linear RGBA) or, with
    // `toMetallicRoughness`, glTF's metallic-roughness layout (G roughness, B metallic).
    struct SpecGlossBake {
        const IrImage* specularGlossiness = nullptr;
        SpecGlossFactors factors;
        bool toMetallicRoughness = false;
    };
    std::optional<SpecGlossBake> specGloss;
};

struct TextureSettings {
    bool compress = false;     // BC1/BC3/BC4/BC5 block compression. Default: false.
    // Longest edge in texels after resizing; 0 = kMaxPortableTextureSize (16384, the largest
    // every OpenGL 4.5 GPU takes). Default: 0.
    uint32_t maxSize = 0;
    uint32_t jobs = 0;         // worker threads; 0 = hardware concurrency. Default: 0.
    uint32_t maxSourceTexels = 1u << 28; // refuse larger decoded images (a clear error, not an
                                         // out-of-memory). Default: 268 M texels.
    // Memory the textures being processed at once may hold together (--max-memory); each of the
    // parallel jobs gets an equal share. A texture whose header says it needs more than its
    // share is refused before any pixel buffer is allocated. 0 = defaultMemoryBudget()
    // (memory_budget.h). Default: 0.
    uint64_t maxMemoryBytes = 0;
};

// An upper bound of the bytes processing one texture holds, from its declared size alone
// (texture_processing.cpp lists the buffers it counts). `channels` and `bytesPerChannel` are the
// file's; `settings` decides resizing.
uint64_t estimateTextureBytes(uint32_t width, uint32_t height, uint32_t channels,
                              uint32_t bytesPerChannel, const TextureSettings& settings);

// Loads the image decoder module (OpenImageIO, see image_decode.cpp) now, on the calling
// thread, if it is not loaded yet; processTextures would otherwise load it on first use. The
// converter calls it on a helper thread as soon as it knows the scene has an image that needs it
// (imageNeedsDecoderModule), so the load (0.2-0.5 s of dynamic linking) overlaps mesh processing.
// Harmless to call from several threads.
void loadImageDecoder();

// False for PNG and JPEG (by their first bytes), which are decoded without the module.
bool imageNeedsDecoderModule(const IrImage& image);

struct ProcessedTexture {
    TextureDesc desc;                            // name left kNone: the writer interns it
    std::vector<std::vector<std::byte>> levels; // level 0 first, each all layers
    uint32_t sourceWidth = 0, sourceHeight = 0, sourceChannels = 0;
    double psnrDb = 0; // of level 0 after compression, over the stored channels; 0 if lossless
};

// Processes every request. Errors (Input) name the image: missing file, undecodable data, zero
// size, over maxSourceTexels, over its share of maxMemoryBytes (the message gives the declared
// size, the estimate and the budget); with several failures, the lowest-indexed request's error is
// returned. Deterministic for any `jobs`.
//
// Results, per request (texture_processing.cpp and channel_packing.cpp give the reasons):
// - Rows are stored top row of the image first: GL's t = 0 is the image's top, so glTF UVs
//   (v down the image, as the IR keeps them) sample correctly with no flip anywhere.
// - Integer (8/16-bit) sources: R8/RG8/RGB8/RGBA8 (BC4/BC5/BC1/BC3 with `compress`). Srgb keeps
//   sRGB storage (colorSpace Srgb, RGB8/RGBA8/BC1/BC3) when two or more colour channels remain;
//   a single colour channel (greyscale) is stored linearised in R8/RG8/BC4/BC5, colorSpace
//   Linear, as GL has no core one- or two-channel sRGB format.
// - HDR sources (float files such as EXR and Radiance HDR, or values outside [0, 1]):
//   R16F/RG16F/RGBA16F, Linear, never block compressed (psnrDb stays 0).
// - mipCount is the full chain to 1×1 for mipmapping min filters, 1 for Nearest/Linear.
Result<std::vector<ProcessedTexture>, ConvertError>
processTextures(const std::vector<TextureRequest>& requests, const TextureSettings& settings);

} // namespace pnb::converter
