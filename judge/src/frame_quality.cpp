// --frame-metrics (frame_quality.h): the player's HDR frame against the path-traced truth.
#include "frame_quality.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <random>

#include <glm/mat3x3.hpp>
#include <xxhash.h>

#include "pnb/atomic_file.h"
#include "judged_scene.h"
#include "pnb_reference/flip.h"
#include "pnb_reference/image_error.h"

namespace pnb::player {

namespace {

// The truth cache's file: this header, then the mean and the standard error (rgb float each,
// rows top-down). Any change to the tracer's model must bump kTruthModelVersion below,
// which is part of every key, so that old truths are never read as new ones.
constexpr char kCacheMagic[8] = {'P', 'N', 'B', 'T', 'R', 'U', 'T', 'H'};
constexpr uint32_t kCacheFileVersion = 1; // the layout below
constexpr uint32_t kTruthModelVersion = 1;
struct CacheHeader {
    char magic[8];
    uint32_t version, width, height, samples;
    uint64_t key, pixelHash;
    double relativeNoise;
};

// xxHash of the container's bytes: the truth is of this exact file.
PlayResult<uint64_t> hashFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return PlayError{PlayErrorKind::Input, path + ": cannot read"};
    XXH3_state_t* state = XXH3_createState();
    XXH3_64bits_reset(state);
    std::vector<char> chunk(1 << 20);
    while (in) {
        in.read(chunk.data(), std::streamsize(chunk.size()));
        XXH3_64bits_update(state, chunk.data(), size_t(in.gcount()));
    }
    const uint64_t h = XXH3_64bits_digest(state);
    XXH3_freeState(state);
    return h;
}

// Everything the truth depends on, hashed (the thread count does not change it). `at` is the
// effective instant (reference::effectivePose): the container as stored adds nothing to the key,
// so the truths cached before moving frames keep theirs.
uint64_t truthKey(uint64_t containerHash, const reference::FrameCamera& c, const reference::FrameTraceSettings& s,
                  const reference::FramePose& at) {
    std::vector<double> v = {double(kTruthModelVersion), double(containerHash >> 32), double(containerHash & 0xffffffffu),
                             c.position.x, c.position.y, c.position.z};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) v.push_back(c.worldFromView[i][j]);
    v.insert(v.end(), {double(c.orthographic), c.yfovRadians, c.aspect, c.xmag, c.ymag, double(c.width),
                       double(c.height), double(s.maxBounces), double(s.samplesPerPass), double(s.minSamples),
                       double(s.maxSamples), s.noiseTarget, s.timeLimitSeconds, double(s.seed >> 32),
                       double(s.seed & 0xffffffffu), s.iblRotationRadians, s.iblIntensity, double(s.lambertianOnly)});
    if (at.animated) v.insert(v.end(), {1.0, at.clip ? double(*at.clip) : -1.0, at.clipTime});
    return XXH3_64bits(v.data(), v.size() * sizeof(double));
}

std::string cachePath(const std::string& dir, uint64_t key) {
    char name[40];
    std::snprintf(name, sizeof name, "frame-truth-%016llx.bin", (unsigned long long)key);
    return dir + "/" + name;
}

// The cached truth for `key`, or nothing when absent or when it does not verify (then re-traced).
std::optional<reference::FrameImage> readCachedTruth(const std::string& path, uint64_t key, int width, int height) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    CacheHeader h{};
    if (!in.read(reinterpret_cast<char*>(&h), sizeof h)) return std::nullopt;
    if (std::memcmp(h.magic, kCacheMagic, 8) != 0 || h.version != kCacheFileVersion || h.key != key || int(h.width) != width ||
        int(h.height) != height)
        return std::nullopt;
    const size_t pixels = size_t(width) * size_t(height);
    std::vector<glm::vec3> payload(pixels * 2);
    if (!in.read(reinterpret_cast<char*>(payload.data()), std::streamsize(payload.size() * sizeof(glm::vec3))))
        return std::nullopt;
    if (XXH3_64bits(payload.data(), payload.size() * sizeof(glm::vec3)) != h.pixelHash) return std::nullopt;
    reference::FrameImage image;
    image.width = width;
    image.height = height;
    image.samples = h.samples;
    image.relativeNoise = h.relativeNoise;
    image.mean.assign(payload.begin(), payload.begin() + std::ptrdiff_t(pixels));
    image.standardError.assign(payload.begin() + std::ptrdiff_t(pixels), payload.end());
    return image;
}

Status writeCachedTruth(const std::string& path, uint64_t key, const reference::FrameImage& image) {
    std::vector<glm::vec3> payload = image.mean;
    payload.insert(payload.end(), image.standardError.begin(), image.standardError.end());
    CacheHeader h{};
    std::memcpy(h.magic, kCacheMagic, 8);
    h.version = kCacheFileVersion;
    h.width = uint32_t(image.width);
    h.height = uint32_t(image.height);
    h.samples = image.samples;
    h.key = key;
    h.pixelHash = XXH3_64bits(payload.data(), payload.size() * sizeof(glm::vec3));
    h.relativeNoise = image.relativeNoise;
    std::vector<uint8_t> bytes(sizeof h + payload.size() * sizeof(glm::vec3));
    std::memcpy(bytes.data(), &h, sizeof h);
    std::memcpy(bytes.data() + sizeof h, payload.data(), payload.size() * sizeof(glm::vec3));
    return writeFileAtomic(path, bytes);
}

// One independent draw of the truth's noise around it: the LDR-FLIP such a draw scores against
// the truth is what the truth's own noise adds to the player's frame_flip_ldr (seeded: the same
// truth gives the same figure).
double noiseFlipLdr(const reference::FrameImage& truth, double exposure) {
    std::mt19937_64 rng(0x5eed);
    std::normal_distribution<float> normal;
    std::vector<glm::vec3> draw(truth.mean.size());
    for (size_t i = 0; i < draw.size(); ++i)
        for (int c = 0; c < 3; ++c) draw[i][c] = std::max(0.0f, truth.mean[i][c] + truth.standardError[i][c] * normal(rng));
    return reference::summarizeError(reference::playerLdrFlip(draw, truth.mean, truth.width, truth.height, exposure))
        .mean;
}

} // namespace

reference::FrameCamera frameCamera(const ViewMatrices& view, int width, int height) {
    reference::FrameCamera c;
    c.position = view.position;
    c.worldFromView = glm::transpose(glm::dmat3(glm::mat3(view.view))); // view is a rotation
    c.orthographic = view.orthographic;
    c.yfovRadians = view.yfov;
    c.aspect = view.aspect;
    c.ymag = view.ymag;
    c.xmag = double(view.ymag) * double(view.aspect); // the player's half width (camera.h)
    c.width = width;
    c.height = height;
    return c;
}

FrameQuality::~FrameQuality() = default;

PlayResult<std::unique_ptr<FrameQuality>> FrameQuality::create(const std::string& containerPath, glm::dvec3 origin,
                                                              const Settings& settings) {
    auto judged = JudgedScene::read(containerPath);
    if (!judged) return judged.error();
    // Built now at the container as stored, so a scene the tracer refuses fails before any frame.
    auto tracer = reference::FrameTracer::build((*judged)->scene, origin);
    if (!tracer) return PlayError{PlayErrorKind::Input, "whole-frame reference: " + tracer.error().message};
    std::unique_ptr<FrameQuality> q(new FrameQuality());
    q->mJudged = std::move(*judged);
    q->mOrigin = origin;
    if (!settings.cacheDir.empty()) {
        auto hash = hashFile(containerPath);
        if (!hash) return hash.error();
        q->mContainerHash = *hash;
    }
    q->mTracer = std::move(*tracer);
    q->mSettings = settings;
    return q;
}

PlayResult<std::vector<std::pair<std::string, double>>> FrameQuality::measure(Renderer& renderer, bool followUp,
                                                                              const reference::FramePose& requested) {
    if (followUp) return std::vector<std::pair<std::string, double>>{};
    auto hdr = renderer.capture(CaptureBuffer::Hdr);
    if (!hdr) return hdr.error();
    const int w = int(hdr->width), h = int(hdr->height);
    std::vector<glm::vec3> player(size_t(w) * size_t(h));
    for (int y = 0; y < h; ++y) // captured bottom-up; the truth's rows are top-down
        for (int x = 0; x < w; ++x) {
            const float* p = &hdr->f32[(size_t(h - 1 - y) * size_t(w) + size_t(x)) * 4];
            player[size_t(y) * size_t(w) + size_t(x)] = {p[0], p[1], p[2]};
        }

    reference::FrameTraceSettings trace = mSettings.trace;
    trace.iblRotationRadians = double(renderer.settings().iblRotationDeg) * (3.14159265358979 / 180.0);
    trace.iblIntensity = renderer.settings().iblIntensity;
    const reference::FrameCamera camera = frameCamera(renderer.lastView(), w, h); // world: any origin
    const reference::FramePose at = reference::effectivePose(mJudged->scene, requested); // the frame's instant
    const uint64_t key = truthKey(mContainerHash, camera, trace, at);
    std::optional<reference::FrameImage> truth;
    const std::string path = mSettings.cacheDir.empty() ? std::string() : cachePath(mSettings.cacheDir, key);
    if (!path.empty()) truth = readCachedTruth(path, key, w, h);
    const bool cached = truth.has_value();
    if (!truth) {
        if (!(at == mTracedAt)) { // the geometry and lights of this instant
            auto tracer = reference::FrameTracer::build(mJudged->scene, mOrigin, at);
            if (!tracer) return PlayError{PlayErrorKind::Input, "whole-frame reference: " + tracer.error().message};
            mTracer = std::move(*tracer);
            mTracedAt = at;
        }
        truth = mTracer->render(camera, trace);
        if (!path.empty())
            if (Status s = writeCachedTruth(path, key, *truth); !isOk(s))
                return PlayError{PlayErrorKind::Io, "--frame-truth-cache: " + s.describe()};
    }

    const double exposure = renderer.settings().exposure;
    std::vector<float> flipLdr = reference::playerLdrFlip(player, truth->mean, w, h, exposure);
    const reference::HdrFlipResult flipHdr = reference::hdrFlip(player, truth->mean, w, h);
    const reference::RelativeMse rel = reference::relativeMse(player, truth->mean);
    std::vector<std::pair<std::string, double>> out = {
        {"frame_flip_ldr", reference::summarizeError(flipLdr).mean},
        {"frame_flip_hdr", reference::summarizeError(flipHdr.error).mean},
        {"frame_relmse", rel.mean},
        {"frame_truth_noise_relmse", reference::noiseRelativeMse(truth->mean, truth->standardError)},
        {"frame_truth_noise_flip_ldr", noiseFlipLdr(*truth, exposure)},
        {"frame_truth_samples", double(truth->samples)},
        {"frame_truth_ms", cached ? 0.0 : truth->ms},
        {"frame_truth_cached", cached ? 1.0 : 0.0},
    };
    mPlayer = std::move(player);
    mTruth = std::move(truth->mean);
    mFlipLdr = std::move(flipLdr);
    mWidth = uint32_t(w);
    mHeight = uint32_t(h);
    mExposure = exposure;
    return out;
}

FrameQuality::Frame FrameQuality::lastFrame() const { return {mWidth, mHeight, mPlayer, mTruth, mFlipLdr, mExposure}; }

} // namespace pnb::player
