// converter/src/texture_processing.cpp — processTextures: one request's pipeline, and the worker
// pool that runs the requests.
//
// Pipeline per request: decode (image_decode.cpp) → linearise sRGB colour → resize to maxSize
// (Lanczos-3, linear light) → plan the stored channels on level 0 (channel_packing.cpp) → for
// each level: box-filter from the previous one (mip_chain.cpp), scale alpha to keep level 0's
// coverage for alpha-masked textures, quantise, optionally block compress (block_compress.cpp).
//
// Orientation: TMIP rows are "bottom-up, OpenGL order", i.e. the first row stored is the one GL
// addresses as t = 0. We store the image's top row first, unflipped, so GL's t = 0 is the top of
// the image. glTF puts UV (0, 0) at the image's top-left and the IR keeps glTF's UVs (v grows
// down the image; the OBJ importer converts), so a shader sampling at (u, v) as-is lands on the
// right texel: no flip in the importers, the player or the shaders. The only visible effect is
// that the texture looks upside down in a GL debugger. (Flipping the rows instead would force
// v' = 1 - v everywhere, including in KHR_texture_transform.)
//
// Choices that are not obvious from the header:
// - Only mipmapping min filters get a mip chain (Nearest/Linear sample level 0 only, so their
//   textures have mipCount 1).
// - HDR textures (float sources, or values outside [0, 1]) are stored as 16-bit float and never
//   block compressed, even with settings.compress (libsquish has no BC6H); psnrDb stays 0.
// - Determinism: each request is processed by one thread from start to end and OIIO runs
//   single-threaded inside it, so bytes do not depend on `jobs`; results are placed by index.
//   The error returned is the lowest-indexed request's: workers stop taking new requests after a
//   failure, and every lower index was taken (and is finished) before the failing one.
#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <new>
#include <optional>
#include <system_error>
#include <thread>

#include "pnb_converter/memory_budget.h"
#include "texture_internal.h"

namespace pnb::converter {

using namespace texture_detail;

namespace {

bool usesMips(MinFilter f) {
    return f != MinFilter::Nearest && f != MinFilter::Linear;
}

uint32_t fullMipCount(uint32_t width, uint32_t height) {
    uint32_t count = 1;
    for (uint32_t m = std::max(width, height); m > 1; m >>= 1)
        ++count;
    return count;
}

// Replaces NaN by 0 and infinities by the largest half (a NaN would otherwise spread through
// every filter kernel it touches). Returns whether any value lies outside [0, 1] and whether any
// is negative.
struct ValueRange {
    bool outside01 = false, negative = false;
};
ValueRange sanitize(ImageF& image) {
    ValueRange r;
    for (float& v : image.texels) {
        if (std::isnan(v))
            v = 0.0f;
        else if (std::isinf(v))
            v = v > 0 ? 65504.0f : -65504.0f;
        r.outside01 |= v < 0.0f || v > 1.0f;
        r.negative |= v < 0.0f;
    }
    return r;
}

// The memory one texture may plan to hold: its job's share of the budget.
struct MemoryShare {
    uint64_t bytes = 0, budget = 0;
    size_t jobs = 1;
};

// Refuses, from the header alone, an image whose processing would need more than `share`.
AdmitImage admitWithin(const MemoryShare& share, const TextureSettings& settings) {
    return [share, &settings](const ImageHeader& h) -> std::optional<std::string> {
        uint64_t need =
            estimateTextureBytes(h.width, h.height, h.channels, h.bytesPerChannel, settings);
        if (need <= share.bytes) return std::nullopt;
        std::string budget = share.jobs > 1
            ? "its share of the memory budget (" + formatBytes(share.bytes) + " = --max-memory " +
                  formatBytes(share.budget) + " / " + std::to_string(share.jobs) +
                  " parallel jobs)"
            : "the memory budget (--max-memory " + formatBytes(share.budget) + ")";
        return "declared " + std::to_string(h.width) + "x" + std::to_string(h.height) + " with " +
               std::to_string(h.channels) + " channel(s) of " + std::to_string(h.bytesPerChannel) +
               " byte(s): processing it needs about " + formatBytes(need) + ", more than " +
               budget;
    };
}

// KHR_materials_pbrSpecularGlossiness per texel (TextureRequest::specGloss): `level` holds the
// decoded request image as the file encodes it (the diffuse texture, or the specular-glossiness
// one when there is no diffuse); it becomes the converted base colour or metallic-roughness, in
// linear light. The specular-glossiness texture is sampled bilinearly at each texel's centre when
// its size differs. Both textures' RGB are sRGB-encoded (the extension says so); glossiness (A)
// is linear.
std::optional<ConvertError> bakeSpecGloss(const TextureRequest& request,
                                          const TextureSettings& settings,
                                          const AdmitImage& admit, ImageF& level) {
    const TextureRequest::SpecGlossBake& bake = *request.specGloss;
    const bool diffuseIsImage = request.image != bake.specularGlossiness;
    ImageF specular;
    if (bake.specularGlossiness) {
        if (!diffuseIsImage) {
            specular = level;
        } else {
            auto decoded = decodeImage(*bake.specularGlossiness, settings.maxSourceTexels, admit);
            if (!decoded) return decoded.error();
            specular = std::move(decoded->image);
            sanitize(specular);
        }
    }
    auto specularAt = [&](uint32_t x, uint32_t y) -> std::array<float, 4> {
        if (specular.texels.empty()) return {1, 1, 1, 1};
        // Texel centres of `level` mapped onto `specular`, bilinear, clamped at the edges.
        const float fx = std::max((float(x) + 0.5f) * float(specular.width) / float(level.width) - 0.5f, 0.0f);
        const float fy = std::max((float(y) + 0.5f) * float(specular.height) / float(level.height) - 0.5f, 0.0f);
        const uint32_t x0 = std::min(uint32_t(fx), specular.width - 1), y0 = std::min(uint32_t(fy), specular.height - 1);
        const uint32_t x1 = std::min(x0 + 1, specular.width - 1), y1 = std::min(y0 + 1, specular.height - 1);
        const float tx = std::min(fx - float(x0), 1.0f), ty = std::min(fy - float(y0), 1.0f);
        std::array<float, 4> out{};
        for (int c = 0; c < 4; ++c) {
            auto at = [&](uint32_t sx, uint32_t sy) { return specular.texels[(size_t(sy) * specular.width + sx) * 4 + c]; };
            const float top = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * tx;
            const float bottom = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * tx;
            out[size_t(c)] = top + (bottom - top) * ty;
        }
        return out;
    };
    const SpecGlossFactors& k = bake.factors;
    for (uint32_t y = 0; y < level.height; ++y) {
        for (uint32_t x = 0; x < level.width; ++x) {
            float* t = &level.texels[(size_t(y) * level.width + x) * 4];
            const std::array<float, 4> sg = specularAt(x, y);
            Vec4 diffuse = k.diffuse;
            if (diffuseIsImage) {
                diffuse = {diffuse.x * srgbToLinear(t[0]), diffuse.y * srgbToLinear(t[1]),
                           diffuse.z * srgbToLinear(t[2]), diffuse.w * t[3]};
            }
            const Vec3 spec{k.specular.x * srgbToLinear(sg[0]), k.specular.y * srgbToLinear(sg[1]),
                            k.specular.z * srgbToLinear(sg[2])};
            const MetalRough mr = specGlossToMetalRough(diffuse, spec, k.glossiness * sg[3]);
            if (bake.toMetallicRoughness) {
                t[0] = 0.0f, t[1] = mr.roughness, t[2] = mr.metallic, t[3] = 1.0f;
            } else {
                t[0] = mr.baseColor.x, t[1] = mr.baseColor.y, t[2] = mr.baseColor.z, t[3] = mr.baseColor.w;
            }
        }
    }
    return std::nullopt;
}

// The longest edge a texture is written with: --max-texture-size, else the largest every
// OpenGL 4.5 GPU takes (kMaxPortableTextureSize; convert.cpp warns when that one applies).
uint32_t edgeLimit(const TextureSettings& settings) {
    return settings.maxSize > 0 ? settings.maxSize : kMaxPortableTextureSize;
}

Result<ProcessedTexture, ConvertError> processOne(const TextureRequest& request,
                                                  const TextureSettings& settings,
                                                  const MemoryShare& share) {
    if (!request.image)
        return ConvertError{ConvertErrorKind::Input, "texture '" + request.name + "': no image"};
    auto decoded =
        decodeImage(*request.image, settings.maxSourceTexels, admitWithin(share, settings));
    if (!decoded) return decoded.error();

    ProcessedTexture out;
    out.sourceWidth = decoded->image.width;
    out.sourceHeight = decoded->image.height;
    out.sourceChannels = decoded->sourceChannels;
    ImageF level = std::move(decoded->image);
    ValueRange range = sanitize(level);
    bool hdr = decoded->floatSource || range.outside01;
    if (request.specGloss) {
        // Linear light out: the generic sRGB step below must not run again.
        if (auto e = bakeSpecGloss(request, settings, admitWithin(share, settings), level)) return *e;
        range = sanitize(level);
        hdr = false;
    }

    // Float sources are linear light whatever the request says (EXR and Radiance HDR are linear
    // by definition); 8/16-bit sRGB data is linearised here, before any filter runs.
    if (request.colorSpace == ColorSpace::Srgb && !hdr && !request.specGloss) {
        for (size_t i = 0, n = level.texelCount(); i < n; ++i)
            for (int c = 0; c < 3; ++c)
                level.texels[i * 4 + c] = srgbToLinear(level.texels[i * 4 + c]);
    }

    uint32_t longest = std::max(level.width, level.height);
    const uint32_t limit = edgeLimit(settings);
    if (longest > limit) {
        double scale = double(limit) / double(longest);
        auto edge = [&](uint32_t e) {
            return std::clamp(uint32_t(std::lround(e * scale)), 1u, limit);
        };
        auto resized = resizeImage(level, edge(level.width), edge(level.height));
        if (!resized)
            return ConvertError{resized.error().kind,
                                describeImage(*request.image) + ": " + resized.error().message};
        level = std::move(*resized);
        // Lanczos lobes overshoot: keep LDR data in [0, 1] and non-negative data non-negative.
        float lo = range.negative ? -65504.0f : 0.0f, hi = hdr ? 65504.0f : 1.0f;
        for (float& v : level.texels)
            v = std::clamp(v, lo, hi);
    }

    ChannelLayout layout = planLayout(level, request, hdr);
    bool compress = settings.compress && !hdr;
    TextureFormat format = compress ? blockFormatFor(layout.positions) : layout.format;

    bool keepCoverage = request.alphaMask && layout.storesAlpha();
    AlphaStorage alphaStorage = hdr ? AlphaStorage::Half : AlphaStorage::Unorm8;
    double targetCoverage =
        keepCoverage ? alphaCoverage(level, request.alphaCutoff, 1.0f, alphaStorage) : 0.0;

    TextureDesc& d = out.desc;
    d.dimension = TextureDimension::Tex2D;
    d.format = format;
    d.colorSpace = layout.colorSpace;
    d.swizzle = layout.swizzle;
    d.width = level.width;
    d.height = level.height;
    d.layers = 1;
    d.mipCount = usesMips(request.minFilter) ? fullMipCount(level.width, level.height) : 1;
    d.minFilter = request.minFilter;
    d.magFilter = request.magFilter;
    d.wrapU = request.wrapU;
    d.wrapV = request.wrapV;

    out.levels.reserve(d.mipCount);
    for (uint32_t l = 0; l < d.mipCount; ++l) {
        // Each level comes from the previous level's unscaled alpha, so the coverage scale of
        // one level never compounds into the next.
        if (l > 0) level = downsample(level);
        float alphaScale = keepCoverage && l > 0 ? findAlphaScale(level, request.alphaCutoff,
                                                                  targetCoverage, alphaStorage)
                                                 : 1.0f;
        std::vector<std::byte> packed = packLevel(level, layout, alphaScale);
        if (!compress) {
            out.levels.push_back(std::move(packed));
            continue;
        }
        std::vector<std::byte> blocks =
            compressLevel(packed, layout.positions, level.width, level.height, format);
        if (l == 0) {
            std::array<bool, 4> used{};
            for (uint32_t p = 0; p < layout.positions; ++p)
                used[p] = layout.source[p] >= 0;
            out.psnrDb =
                psnrDb(packed,
                       decompressLevel(blocks, layout.positions, level.width, level.height, format),
                       layout.positions, used);
        }
        out.levels.push_back(std::move(blocks));
    }
    return out;
}

// Keeps exceptions (allocation failure on a huge image, anything OIIO lets escape) from crossing
// the thread boundary or the module's interface.
Result<ProcessedTexture, ConvertError> processGuarded(const TextureRequest& request,
                                                      const TextureSettings& settings,
                                                      const MemoryShare& share) {
    auto fail = [&](const std::string& what) {
        std::string name =
            request.image ? describeImage(*request.image) : "texture '" + request.name + "'";
        return ConvertError{ConvertErrorKind::Input, name + ": " + what};
    };
    try {
        return processOne(request, settings, share);
    } catch (const std::bad_alloc&) {
        return fail("out of memory");
    } catch (const std::exception& e) {
        return fail(e.what());
    }
}

} // namespace

// Every buffer that lives while one texture is processed, summed (they are not all alive at
// once, so this is an upper bound), per texel of the declared size:
//   - the decoder's copy of the native pixels (OIIO's PNG reader, for one, holds the whole
//     image): channels x bytesPerChannel;
//   - our native read buffer, at most 4 channels: min(channels, 4) x bytesPerChannel;
//   - level 0 as float RGBA: 16 bytes;
//   - the resized level 0 when --max-texture-size scales down: at most 16 bytes;
//   - the next mip level while it is filtered from the current one: at most 16 / 4 = 4 bytes;
//   - the packed levels kept for the container: at most 8 bytes (RGBA16F) x 4/3 for the chain.
uint64_t estimateTextureBytes(uint32_t width, uint32_t height, uint32_t channels,
                              uint32_t bytesPerChannel, const TextureSettings& settings) {
    const uint64_t texels = uint64_t(width) * height;
    const bool resized = std::max(width, height) > edgeLimit(settings);
    const uint64_t perTexel = uint64_t(channels + std::min(channels, 4u)) * bytesPerChannel +
                              16 + (resized ? 16 : 0) + 4;
    const uint64_t packed = texels * 8 + texels * 8 / 3;
    // Declared sizes are at most 2^31 a side, so only a pathological header could overflow.
    if (texels > (uint64_t(1) << 62) / std::max<uint64_t>(perTexel + 11, 1))
        return std::numeric_limits<uint64_t>::max();
    return texels * perTexel + packed;
}

Result<std::vector<ProcessedTexture>, ConvertError>
processTextures(const std::vector<TextureRequest>& requests, const TextureSettings& settings) {
    size_t count = requests.size();
    size_t jobs = settings.jobs ? settings.jobs : std::max(1u, std::thread::hardware_concurrency());
    jobs = std::min(jobs, count);
    // Up to `jobs` textures are in flight at once, each within an equal share of the budget.
    MemoryShare share;
    share.budget = settings.maxMemoryBytes ? settings.maxMemoryBytes : defaultMemoryBudget();
    share.jobs = std::max<size_t>(jobs, 1);
    share.bytes = share.budget / share.jobs;
    std::vector<std::optional<Result<ProcessedTexture, ConvertError>>> results(count);
    std::atomic<size_t> next{0};
    std::atomic<bool> failed{false};
    auto work = [&] {
        while (!failed.load(std::memory_order_relaxed)) {
            size_t i = next.fetch_add(1);
            if (i >= count) break;
            results[i] = processGuarded(requests[i], settings, share);
            if (!results[i]->ok()) failed = true;
        }
    };

    std::vector<std::thread> threads;
    for (size_t j = 1; j < jobs; ++j) {
        try {
            threads.emplace_back(work);
        } catch (const std::system_error&) {
            break; // fewer threads than asked for: slower, same bytes
        }
    }
    work(); // the calling thread is worker 0
    for (std::thread& t : threads)
        t.join();

    std::vector<ProcessedTexture> out;
    out.reserve(count);
    for (auto& r : results) {
        // Unprocessed entries only follow a failure, which returns first.
        assert(r.has_value());
        if (!r->ok()) return r->error();
        out.push_back(std::move(*r).value());
    }
    return out;
}

} // namespace pnb::converter
