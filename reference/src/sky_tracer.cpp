// Sky irradiance with Embree (see sky_tracer.h).
#include "pnb_reference/sky_tracer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "cosine_sampling.h"
#include "self_intersection.h"
#include "pnb_lighting/sh9.h"
#include "texture_decode.h"
#include "triangle_scene.h"

namespace pnb::reference {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The clamped cosine's zonal coefficients per band (pnb_lighting/sh9.h, FORMAT.md "ENVM").
constexpr double kCosineLobe[3] = {kPi, 2.0 * kPi / 3.0, kPi / 4.0};
constexpr int kBandOf[9] = {0, 1, 1, 1, 2, 2, 2, 2, 2};

const char* formatName(TextureFormat f) {
    switch (f) {
    case TextureFormat::RGBA16F: return "RGBA16F";
    case TextureFormat::RGBA32F: return "RGBA32F";
    default: return "neither RGBA16F nor RGBA32F";
    }
}

} // namespace

struct SkyTracer::Impl {
    std::unique_ptr<detail::TriangleScene> occluders;
    std::optional<detail::LinearTexture> radiance; // the ENVM image, level 0
    lighting::Sh9Rgb radianceSh;                     // irradianceSh / A_l (see sky_tracer.h)
};

SkyTracer::SkyTracer() : mImpl(std::make_unique<Impl>()) {}
SkyTracer::~SkyTracer() = default;

bool SkyTracer::hasRadianceImage() const { return mImpl->radiance.has_value(); }

TracerResult<std::unique_ptr<SkyTracer>> SkyTracer::build(const Scene& scene, glm::dvec3 origin, const FramePose& at) {
    auto start = std::chrono::steady_clock::now();
    if (!scene.environment)
        return TracerError{TracerErrorKind::Input,
                           "the scene has no environment (ENVM chunk): sky light needs one"};
    const Environment& env = *scene.environment;
    std::unique_ptr<SkyTracer> tracer(new SkyTracer);
    Impl& impl = *tracer->mImpl;
    SkyStats& stats = tracer->mStats;

    if (env.radiance != kNone) {
        const std::string what = "the environment's (ENVM) radiance texture " + std::to_string(env.radiance);
        if (env.radiance >= scene.textures.size())
            return TracerError{TracerErrorKind::Input,
                               what + " does not exist (" + std::to_string(scene.textures.size()) + " textures)"};
        const TextureDesc& d = scene.textures[env.radiance];
        if (d.dimension != TextureDimension::Tex2D ||
            (d.format != TextureFormat::RGBA16F && d.format != TextureFormat::RGBA32F))
            return TracerError{TracerErrorKind::Input,
                               what + " is not a 2D RGBA16F or RGBA32F texture (it is " +
                                   (d.dimension == TextureDimension::Cube ? "a cube, " : "2D, ") +
                                   formatName(d.format) + ")"};
        auto decoded = detail::decodeTexture(scene, env.radiance);
        if (!decoded)
            return TracerError{TracerErrorKind::Input, what + " has no level 0 of its full size"};
        // The equirectangular mapping wraps in azimuth and stops at the poles, whatever the
        // descriptor's wrap modes say (FORMAT.md "ENVM").
        decoded->wrapU = Wrap::Repeat;
        decoded->wrapV = Wrap::ClampToEdge;
        stats.radianceWidth = decoded->width;
        stats.radianceHeight = decoded->height;
        impl.radiance = std::move(*decoded);
    }
    for (int k = 0; k < 9; ++k) {
        const Vec3& c = env.irradianceSh[size_t(k)];
        impl.radianceSh.c[size_t(k)] = glm::dvec3(c.x, c.y, c.z) / kCosineLobe[kBandOf[k]];
    }

    auto posed = detail::PosedScene::make(scene, at);
    if (!posed) return posed.error();
    auto occluders = detail::buildTriangleScene(scene, *posed, origin);
    if (!occluders) return occluders.error();
    impl.occluders = std::move(*occluders);
    stats.triangles = impl.occluders->triangles;
    stats.instances = impl.occluders->instances;
    stats.translucentInstances = impl.occluders->translucentInstances;
    stats.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return tracer;
}

void SkyTracer::irradiance(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                           const SkySettings& settings, std::span<glm::vec3> mean,
                           std::span<glm::vec3> standardError, glm::dvec3 eye) const {
    const Impl& impl = *mImpl;
    const size_t count = positions.size();
    const glm::vec3 nan(std::numeric_limits<float>::quiet_NaN());
    std::fill(mean.begin(), mean.end(), nan);
    std::fill(standardError.begin(), standardError.end(), nan);
    if (normals.size() != count || mean.size() != count || standardError.size() != count || settings.samples == 0 ||
        (settings.source == SkySource::Image && !impl.radiance))
        return;

    // The environment's rotation: a world direction w sees the environment at R_y(-angle) w
    // (sh9RotateY's sense); the Sh source is rotated once, exactly, by sh9RotateY itself.
    const double angle = std::isfinite(settings.rotationRadians) ? double(settings.rotationRadians) : 0.0;
    const double ca = std::cos(angle), sa = std::sin(angle);
    const lighting::Sh9Rgb rotatedSh = lighting::sh9RotateY(impl.radianceSh, angle);
    const double intensity = settings.intensity;
    auto radiance = [&](const glm::vec3& w) -> glm::dvec3 {
        if (settings.source == SkySource::Sh) return lighting::sh9Evaluate(rotatedSh, glm::dvec3(w)) * intensity;
        const glm::dvec3 local(ca * w.x - sa * w.z, w.y, sa * w.x + ca * w.z); // R_y(-angle) w
        return glm::dvec3(glm::vec3(impl.radiance->sample(glm::vec2(lighting::equirectUv(local))))) * intensity;
    };

    const uint32_t samples = settings.samples;
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<size_t> next{0};
    auto worker = [&] {
        detail::TraceContext context;
        rtcInitIntersectContext(&context.embree);
        context.eye = eye;
        context.fixedBand = kVertexRelativeError * glm::length(eye) + impl.occluders->worldBand;
        std::vector<detail::TranslucentHit> crossed; // the translucent surfaces of one ray
        context.translucentHits = &crossed;
        for (size_t i = next.fetch_add(1); i < count; i = next.fetch_add(1)) {
            const glm::vec3 p = positions[i], n = normals[i];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
                !std::isfinite(n.x + n.y + n.z) || !(glm::length(n) > 0.0f))
                continue;
            const detail::CosineFrame frame(glm::normalize(n));
            // Rays start at the point itself; the own-surface filter (self_intersection.h), not
            // an offset along n, keeps the surface the point lies on from hiding its own sky.
            const float tnear = float(kPointRelativeError * glm::length(glm::dvec3(p) - eye));
            glm::dvec3 sum(0.0), sum2(0.0);
            for (uint32_t s = 0; s < samples; ++s) {
                const glm::vec3 dir = frame.direction(settings.seed, i, s);
                glm::dvec3 transmittance(1.0);
                if (settings.visibility) {
                    crossed.clear();
                    RTCRay ray;
                    ray.org_x = p.x, ray.org_y = p.y, ray.org_z = p.z;
                    ray.dir_x = dir.x, ray.dir_y = dir.y, ray.dir_z = dir.z;
                    ray.tnear = tnear;
                    ray.tfar = std::numeric_limits<float>::infinity();
                    ray.time = 0, ray.mask = 0xFFFFFFFFu, ray.id = 0, ray.flags = 0;
                    rtcOccluded1(impl.occluders->scene, &context.embree, &ray);
                    if (ray.tfar < 0.0f) continue; // Embree marks an occluded ray with tfar = -inf
                    // The sky seen through glass is tinted (translucency.h).
                    transmittance = glm::dvec3(impl.occluders->translucent.product(crossed));
                }
                const glm::dvec3 l = radiance(dir) * transmittance;
                sum += l;
                sum2 += l * l;
            }
            // E = pi x mean(L V): the pdf cos / pi cancels the cosine of the integrand.
            const double n1 = double(samples);
            const glm::dvec3 m = sum / n1;
            const glm::dvec3 var =
                samples > 1 ? glm::max(sum2 / n1 - m * m, glm::dvec3(0.0)) * (n1 / (n1 - 1.0)) : glm::dvec3(0.0);
            mean[i] = glm::vec3(kPi * m);
            standardError[i] = glm::vec3(kPi * glm::sqrt(var / n1));
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
}

} // namespace pnb::reference
