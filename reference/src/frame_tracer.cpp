// The whole-frame path tracer (pnb_reference/frame_tracer.h): camera rays, paths, passes.
#include "pnb_reference/frame_tracer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "frame_bsdf.h"
#include "frame_random.h"
#include "frame_scene.h"
#include "pnb_reference/local_light.h"

namespace pnb::reference {

namespace {

// Bounces traced with certainty before Russian roulette may end a path (it is unbiased: a
// surviving path is divided by its survival probability).
constexpr uint32_t kRouletteDepth = 3;
// Up to this many lights are all sampled at every vertex; more, and one is picked at random.
constexpr size_t kAllLightsUpTo = 8;

// One pixel's camera ray: origin-relative origin and unit direction.
struct CameraRay {
    glm::vec3 origin, direction;
};

// The player's projection (player/src/camera/camera.cpp) inverted at the centre of pixel
// (x, y), row 0 the top of the image: NDC x = (x + 1/2) / W x 2 - 1, NDC y = 1 - (y + 1/2) / H x 2.
CameraRay cameraRay(const FrameCamera& camera, glm::dvec3 eye, int x, int y) {
    const double nx = (double(x) + 0.5) / double(camera.width) * 2.0 - 1.0;
    const double ny = 1.0 - (double(y) + 0.5) / double(camera.height) * 2.0;
    if (camera.orthographic) {
        const glm::dvec3 o = eye + camera.worldFromView * glm::dvec3(nx * camera.xmag, ny * camera.ymag, 0.0);
        return {glm::vec3(o), glm::vec3(glm::normalize(camera.worldFromView * glm::dvec3(0.0, 0.0, -1.0)))};
    }
    const double h = std::tan(0.5 * camera.yfovRadians);
    const glm::dvec3 d = camera.worldFromView * glm::dvec3(nx * h * camera.aspect, ny * h, -1.0);
    return {glm::vec3(eye), glm::vec3(glm::normalize(d))};
}

struct PathContext {
    const detail::FrameScene& scene;
    const FrameTraceSettings& settings;
    detail::EnvironmentPose pose;
    const detail::EnvironmentMap* sampled; // the environment drawn from, or null (none, or off)
    detail::TraceContext trace;
    uint64_t rays = 0;
};

// The balance heuristic's weight of the strategy that drew a direction with pdf `a`, the other
// one's pdf for it being `b` (Veach 1997).
float misWeight(float a, float b) { return a + b > 0.0f ? a / (a + b) : 0.0f; }

// Light from the environment at surface s, a direction drawn from the environment's map; its
// weight against BSDF sampling, which draws the same directions at the next vertex's miss.
// Visibility as a path ray sees it (FrameScene::trace: masked holes, Blend passed at random), so
// the two strategies estimate one and the same quantity.
glm::vec3 environmentLight(PathContext& c, const detail::FrameSurface& s, const detail::BsdfLobes& lobes,
                           detail::FrameRandom& rng) {
    const float u[4] = {rng.next(), rng.next(), rng.next(), rng.next()};
    float pdf = 0;
    const glm::vec3 l = c.sampled->sample(u, c.pose, pdf);
    if (!(pdf > 0.0f) || glm::dot(s.geometric, l) <= 0.0f) return glm::vec3(0.0f);
    const float nDotL = glm::dot(s.normal, l);
    if (nDotL <= 0.0f) return glm::vec3(0.0f);
    const glm::vec3 reflected = lobes.value(l) * nDotL;
    if (!(reflected.x > 0.0f || reflected.y > 0.0f || reflected.z > 0.0f)) return glm::vec3(0.0f);
    const float tnear = float(kPointRelativeError * glm::length(glm::dvec3(s.position) - c.trace.eye));
    if (c.scene.trace(c.trace, s.position, l, tnear, rng, c.rays)) return glm::vec3(0.0f);
    return reflected * c.sampled->radiance(l, c.pose) * (misWeight(pdf, lobes.pdf(l)) / pdf);
}

// Direct light from the punctual lights at surface s, seen along -dir (next-event estimation).
glm::vec3 directLight(PathContext& c, const detail::FrameSurface& s, const detail::BsdfLobes& lobes,
                      detail::FrameRandom& rng) {
    const auto& lights = c.scene.lights();
    if (lights.empty()) return glm::vec3(0.0f);
    size_t first = 0, count = lights.size();
    float weight = 1.0f;
    if (count > kAllLightsUpTo) { // one light, picked uniformly: weight = the count
        first = std::min(count - 1, size_t(rng.next() * float(count)));
        weight = float(count);
        count = 1;
    }
    const glm::dvec3 eye = c.trace.eye;
    const double pointBand = kPointRelativeError * glm::length(glm::dvec3(s.position) - eye);
    glm::vec3 sum(0.0f);
    for (size_t i = first; i < first + count; ++i) {
        const detail::FrameLight& light = lights[i];
        glm::vec3 toLight, shadowDir;
        double attenuation = 1.0;
        bool toPoint = false;
        if (light.type == LightType::Directional) {
            toLight = shadowDir = -light.travel;
        } else {
            const glm::dvec3 d = light.position - glm::dvec3(s.position);
            const double d2 = glm::dot(d, d);
            toLight = d2 > 0.0 ? glm::vec3(d / std::sqrt(d2)) : glm::vec3(0.0f, 0.0f, 1.0f);
            attenuation = rangeAttenuation(d2, light.range); // lights.glsl's falloff
            if (light.type == LightType::Spot)
                attenuation *= spotConeFactor(glm::dot(glm::dvec3(light.travel), -glm::dvec3(toLight)), light.cosOuter,
                                              light.cosInner);
            shadowDir = glm::vec3(d);
            toPoint = true;
        }
        if (!(attenuation > 0.0) || glm::dot(s.geometric, toLight) <= 0.0f) continue;
        const float nDotL = glm::dot(s.normal, toLight);
        if (nDotL <= 0.0f) continue;
        const glm::vec3 reflected = lobes.value(toLight) * nDotL * light.radiance * float(attenuation);
        if (!(reflected.x > 0.0f || reflected.y > 0.0f || reflected.z > 0.0f)) continue;
        const double length = toPoint ? std::max(double(glm::length(shadowDir)), 1e-30) : 1.0;
        const double lightBand = toPoint ? kPointRelativeError * glm::length(light.position - eye) : -1.0;
        sum += reflected * c.scene.transmittance(c.trace, s.position, shadowDir, float(pointBand / length), toPoint,
                                                 lightBand, c.rays);
    }
    return sum * weight;
}

// One sample of the radiance along a camera ray.
glm::vec3 pathRadiance(PathContext& c, CameraRay ray, detail::FrameRandom& rng) {
    glm::vec3 radiance(0.0f), throughput(1.0f);
    glm::vec3 org = ray.origin, dir = ray.direction;
    float tnear = 0.0f, bsdfPdf = 0.0f; // the pdf the BSDF drew dir with (0: the camera's ray)
    for (uint32_t depth = 0;; ++depth) {
        const auto s = c.scene.trace(c.trace, org, dir, tnear, rng, c.rays);
        if (!s) { // the background (depth 0) or the environment's light through a bounce
            const float weight = depth > 0 && c.sampled ? misWeight(bsdfPdf, c.sampled->pdf(dir, c.pose)) : 1.0f;
            radiance += throughput * c.scene.environment(dir, c.pose) * weight;
            break;
        }
        if (s->unlit) {
            radiance += throughput * (s->baseColor + s->emissive);
            break;
        }
        radiance += throughput * s->emissive;
        if (depth > c.settings.maxBounces) break; // its emission was the previous vertex's direct light
        const detail::BsdfLobes lobes(s->baseColor, s->metallic, s->roughness, s->normal, -dir,
                                      c.settings.lambertianOnly);
        radiance += throughput * directLight(c, *s, lobes, rng);
        if (c.sampled) radiance += throughput * environmentLight(c, *s, lobes, rng);
        const float u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
        const glm::vec3 l = lobes.sample(u0, u1, u2);
        const float nDotL = glm::dot(s->normal, l);
        if (nDotL <= 0.0f || glm::dot(s->geometric, l) <= 0.0f) break;
        const float pdf = lobes.pdf(l);
        if (!(pdf > 0.0f)) break;
        throughput *= lobes.value(l) * (nDotL / pdf);
        bsdfPdf = pdf;
        if (depth + 1 >= kRouletteDepth) {
            const float survive = std::min(0.95f, std::max({throughput.x, throughput.y, throughput.z}));
            if (!(survive > 0.0f) || rng.next() >= survive) break;
            throughput /= survive;
        }
        org = s->position;
        dir = l;
        tnear = float(kPointRelativeError * glm::length(glm::dvec3(org) - c.trace.eye));
    }
    return radiance;
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

} // namespace

struct FrameTracer::Impl {
    std::unique_ptr<detail::FrameScene> scene;
    glm::dvec3 origin{0.0};
};

FrameTracer::FrameTracer() : mImpl(std::make_unique<Impl>()) {}
FrameTracer::~FrameTracer() = default;

TracerResult<std::unique_ptr<FrameTracer>> FrameTracer::build(const Scene& scene, glm::dvec3 origin,
                                                              const FramePose& at) {
    const auto start = std::chrono::steady_clock::now();
    std::unique_ptr<FrameTracer> tracer(new FrameTracer);
    auto built = detail::FrameScene::build(scene, origin, at, tracer->mStats);
    if (!built) return built.error();
    tracer->mImpl->scene = std::move(*built);
    tracer->mImpl->origin = origin;
    tracer->mStats.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return tracer;
}

FrameImage FrameTracer::render(const FrameCamera& camera, const FrameTraceSettings& settings) const {
    const auto start = std::chrono::steady_clock::now();
    FrameImage image;
    image.stats = mStats;
    image.width = std::max(0, camera.width);
    image.height = std::max(0, camera.height);
    const size_t pixels = size_t(image.width) * size_t(image.height);
    image.mean.assign(pixels, glm::vec3(0.0f));
    image.standardError.assign(pixels, glm::vec3(0.0f));
    if (pixels == 0) return image;

    const detail::FrameScene& scene = *mImpl->scene;
    const glm::dvec3 eye = camera.position - mImpl->origin;
    const double angle = std::isfinite(settings.iblRotationRadians) ? settings.iblRotationRadians : 0.0;
    std::vector<glm::dvec3> sum(pixels, glm::dvec3(0.0)), sum2(pixels, glm::dvec3(0.0));
    const uint32_t perPass = std::max(1u, settings.samplesPerPass);
    const uint32_t maxSamples = std::max(1u, settings.maxSamples);
    const unsigned threads = settings.threads ? settings.threads : std::max(1u, std::thread::hardware_concurrency());
    std::atomic<uint64_t> rays{0}, nonFinite{0};

    uint32_t done = 0;
    while (done < maxSamples) {
        const uint32_t first = done, count = std::min(perPass, maxSamples - done);
        std::atomic<int> nextRow{0};
        auto worker = [&] {
            PathContext c{scene, settings, {std::cos(angle), std::sin(angle), settings.iblIntensity},
                          settings.sampleEnvironment ? scene.sampledEnvironment() : nullptr, scene.context(eye)};
            uint64_t bad = 0;
            for (int y = nextRow.fetch_add(1); y < image.height; y = nextRow.fetch_add(1))
                for (int x = 0; x < image.width; ++x) {
                    const size_t p = size_t(y) * size_t(image.width) + size_t(x);
                    const CameraRay ray = cameraRay(camera, eye, x, y);
                    for (uint32_t k = first; k < first + count; ++k) {
                        detail::FrameRandom rng(settings.seed, p, k);
                        glm::vec3 l = pathRadiance(c, ray, rng);
                        if (!finite(l)) {
                            l = glm::vec3(0.0f);
                            ++bad;
                        }
                        sum[p] += glm::dvec3(l);
                        sum2[p] += glm::dvec3(l) * glm::dvec3(l);
                    }
                }
            rays += c.rays;
            nonFinite += bad;
        };
        std::vector<std::thread> pool;
        for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
        worker();
        for (std::thread& t : pool) t.join();
        done += count;
        ++image.passes;

        // The estimate so far, and its noise (frame_tracer.h: relativeNoise).
        const double n = double(done);
        double noise = 0;
        for (size_t p = 0; p < pixels; ++p) {
            const glm::dvec3 m = sum[p] / n;
            const glm::dvec3 var =
                done > 1 ? glm::max(sum2[p] / n - m * m, glm::dvec3(0.0)) * (n / (n - 1.0)) : glm::dvec3(0.0);
            const glm::dvec3 se2 = var / n;
            image.mean[p] = glm::vec3(m);
            image.standardError[p] = glm::vec3(glm::sqrt(se2));
            for (int ch = 0; ch < 3; ++ch) noise += se2[ch] / (m[ch] * m[ch] + 0.01);
        }
        image.relativeNoise = noise / (3.0 * double(pixels));
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (done >= settings.minSamples && settings.noiseTarget > 0 && image.relativeNoise <= settings.noiseTarget) break;
        if (settings.timeLimitSeconds > 0 && seconds >= settings.timeLimitSeconds) break;
    }
    image.samples = done;
    image.rays = rays;
    image.stats.nonFiniteSamples = nonFinite;
    image.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return image;
}

} // namespace pnb::reference
