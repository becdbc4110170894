// converter/src/environment_image.cpp — the environment's radiance image: loaded from a file
// (through the converter's image decoders, so every format a texture may be in works here too),
// cleaned, or baked from the analytic sky (environment.h).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include "pnb_converter/environment.h"
#include "pnb_converter/memory_budget.h"
#include "pnb_lighting/sh9.h" // equirectDirection, the one definition of the mapping
#include "texture_internal.h"

namespace pnb::converter {

namespace {

namespace fs = std::filesystem;

} // namespace

uint64_t cleanRadiance(RadianceImage& image) {
    uint64_t cleaned = 0;
    const size_t n = std::min(image.rgb.size() / 3, size_t(image.width) * image.height);
    for (size_t t = 0; t < n; ++t) {
        bool bad = false;
        for (int c = 0; c < 3; ++c) {
            float& v = image.rgb[t * 3 + c];
            // `!(v >= 0)` catches NaN too; radiance is a non-negative, finite quantity.
            if (!(v >= 0.0f) || std::isinf(v)) {
                v = 0.0f;
                bad = true;
            }
        }
        cleaned += bad;
    }
    return cleaned;
}

Result<RadianceImage, ConvertError> loadRadianceImage(const std::string& path,
                                                      uint64_t maxMemoryBytes) {
    IrImage source;
    source.name = fs::path(path).filename().string();
    source.path = path;
    // A header can declare any size: refuse what the budget cannot hold before reading pixels,
    // as textures are (memory_budget.h).
    const uint64_t budget = maxMemoryBytes ? maxMemoryBytes : defaultMemoryBudget();
    auto admit = [budget](const texture_detail::ImageHeader& h) -> std::optional<std::string> {
        const uint64_t need = h.texels() * kEnvironmentBytesPerTexel;
        if (need <= budget) return std::nullopt;
        return "declared " + std::to_string(h.width) + "x" + std::to_string(h.height) +
               ": loading and baking it needs about " + formatBytes(need) +
               ", more than the memory budget (--max-memory " + formatBytes(budget) + ")";
    };
    // The decoders' own checks (missing file, not a regular file, undecodable, zero size, the
    // texel limit textures have) give one-line errors that start with the image and its path.
    auto decoded = texture_detail::decodeImage(source, TextureSettings{}.maxSourceTexels, admit);
    if (!decoded) {
        ConvertError e = decoded.error();
        e.message = "environment " + e.message;
        return e;
    }
    const texture_detail::ImageF& img = decoded->image;
    RadianceImage out;
    out.width = img.width;
    out.height = img.height;
    out.rgb.resize(img.texelCount() * 3);
    // An integer file (PNG, JPEG, 8/16-bit TIFF) holds display-encoded values, not radiance:
    // linearise as sRGB so at least the shape of the light is right.
    const bool encoded = !decoded->floatSource;
    for (size_t t = 0; t < img.texelCount(); ++t)
        for (int c = 0; c < 3; ++c) {
            float v = img.texels[t * 4 + c];
            out.rgb[t * 3 + c] = encoded ? texture_detail::srgbToLinear(v) : v;
        }
    if (encoded)
        out.warnings.push_back("environment " + path +
                               ": not a floating-point image; its values are taken as "
                               "sRGB-encoded and linearised (1.0 = 1 nit)");
    out.cleanedTexels = cleanRadiance(out);
    if (out.cleanedTexels)
        out.warnings.push_back("environment " + path + ": " + std::to_string(out.cleanedTexels) +
                               " texel(s) with NaN, infinite or negative values set to 0");
    if (!(out.width == 1 && out.height == 1) && out.width != 2 * out.height)
        out.warnings.push_back("environment " + path + ": " + std::to_string(out.width) + "x" +
                               std::to_string(out.height) +
                               " is not 2:1; it is stretched over the whole sphere as an "
                               "equirectangular image");
    return out;
}

RadianceImage bakePreethamSky(const PreethamSkyParams& params, uint32_t width) {
    RadianceImage out;
    out.width = std::max(1u, width);
    out.height = std::max(1u, out.width / 2);
    out.rgb.resize(size_t(out.width) * out.height * 3);
    const lighting::PreethamSky sky(params);
    for (uint32_t j = 0; j < out.height; ++j)
        for (uint32_t i = 0; i < out.width; ++i) {
            // Texel centres: the stored texel is the radiance at its centre, which the box mips
            // and the SH projection (texels as constant patches) then treat as its mean.
            glm::dvec3 d = lighting::equirectDirection((i + 0.5) / out.width, (j + 0.5) / out.height);
            glm::dvec3 L = sky.radiance(d);
            float* p = &out.rgb[(size_t(j) * out.width + i) * 3];
            p[0] = float(L.x);
            p[1] = float(L.y);
            p[2] = float(L.z);
        }
    out.cleanedTexels = cleanRadiance(out); // the model promises finite, >= 0: counted, not hidden
    return out;
}

float studioRadiance(const double d[3]) {
    auto smoothstep = [](double e0, double e1, double x) {
        const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
        return t * t * (3 - 2 * t);
    };
    const double y = std::clamp(d[1], -1.0, 1.0);
    const double walls = kStudioHorizon + (kStudioZenith - kStudioHorizon) * std::max(y, 0.0);
    double L = kStudioGround + (walls - kStudioGround) * smoothstep(-0.15, 0.0, y);
    constexpr double kDeg = 3.14159265358979323846 / 180.0;
    for (const StudioLight& l : kStudioLights) {
        const double el = l.elevationDegrees * kDeg, az = l.azimuthDegrees * kDeg;
        const double c = d[0] * std::cos(el) * std::sin(az) + d[1] * std::sin(el) +
                         d[2] * std::cos(el) * std::cos(az);
        const double r = l.radiusDegrees * kDeg;
        L += l.radiance * smoothstep(std::cos(1.25 * r), std::cos(0.75 * r), c);
    }
    return float(L);
}

RadianceImage bakeDefaultStudio(uint32_t width) {
    RadianceImage out;
    out.width = std::max(1u, width);
    out.height = std::max(1u, out.width / 2);
    out.rgb.resize(size_t(out.width) * out.height * 3);
    for (uint32_t j = 0; j < out.height; ++j)
        for (uint32_t i = 0; i < out.width; ++i) {
            const glm::dvec3 d =
                lighting::equirectDirection((i + 0.5) / out.width, (j + 0.5) / out.height);
            const double dir[3] = {d.x, d.y, d.z};
            float* p = &out.rgb[(size_t(j) * out.width + i) * 3];
            p[0] = p[1] = p[2] = studioRadiance(dir);
        }
    return out;
}

} // namespace pnb::converter
