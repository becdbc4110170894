// The truth metrics behind the player's TruthJudge interface (truth_judges.h).
#include "truth_judges.h"

#include <utility>

#include <filesystem>

#include "frame_error_maps.h"
#include "frame_quality.h"
#include "irradiance_quality.h"
#include "judged_scene.h"
#include "shadow_quality.h"
#include "truth_error_maps.h"

namespace pnb::player {

namespace {

class ShadowJudge final : public TruthJudge {
public:
    ShadowJudge(std::unique_ptr<ShadowQuality> quality, glm::vec3 towardSun)
        : mQuality(std::move(quality)), mTowardSun(towardSun) {}
    PlayResult<std::vector<std::pair<std::string, double>>> measure(Renderer& renderer, bool followUp) override {
        return mQuality->measure(renderer, mTowardSun, followUp, judgedPose(renderer));
    }
    std::vector<ErrorMap> errorMaps() const override { return {shadowErrorMap(mQuality->lastFrame())}; }

private:
    std::unique_ptr<ShadowQuality> mQuality;
    glm::vec3 mTowardSun;
};

// GI or sky: the error map and the side-by-side comparison.
class IrradianceJudge final : public TruthJudge {
public:
    IrradianceJudge(std::unique_ptr<IrradianceQuality> quality, std::string metric)
        : mQuality(std::move(quality)), mMetric(std::move(metric)) {}
    PlayResult<std::vector<std::pair<std::string, double>>> measure(Renderer& renderer, bool followUp) override {
        return mQuality->measure(renderer, followUp, judgedPose(renderer));
    }
    std::vector<ErrorMap> errorMaps() const override {
        return {irradianceErrorMap(mMetric, mQuality->lastFrame()), irradianceSideBySide(mMetric, mQuality->lastFrame())};
    }

private:
    std::unique_ptr<IrradianceQuality> mQuality;
    std::string mMetric;
};

// The whole frame: the FLIP map and the side-by-side comparison.
class FrameJudge final : public TruthJudge {
public:
    explicit FrameJudge(std::unique_ptr<FrameQuality> quality) : mQuality(std::move(quality)) {}
    PlayResult<std::vector<std::pair<std::string, double>>> measure(Renderer& renderer, bool followUp) override {
        return mQuality->measure(renderer, followUp, judgedPose(renderer));
    }
    std::vector<ErrorMap> errorMaps() const override {
        return {frameErrorMap(mQuality->lastFrame()), frameSideBySide(mQuality->lastFrame())};
    }

private:
    std::unique_ptr<FrameQuality> mQuality;
};

} // namespace

PlayResult<std::unique_ptr<TruthJudge>> makeTruthJudge(TruthMetric metric, const TruthRequest& request) {
    switch (metric) {
    case TruthMetric::Shadow: {
        auto q = ShadowQuality::create(request.scene, request.origin, request.judgedLight);
        if (!q) return q.error();
        return std::unique_ptr<TruthJudge>(std::make_unique<ShadowJudge>(std::move(*q), request.towardSun));
    }
    case TruthMetric::Gi: {
        reference::IndirectSettings settings;
        settings.samples = request.giSamples;
        settings.lights = request.giAllLights ? reference::IndirectLights::All : reference::IndirectLights::Sun;
        settings.bounces = request.giBounces;
        auto q = IrradianceQuality::forGi(request.scene, request.origin, settings);
        if (!q) return q.error();
        return std::unique_ptr<TruthJudge>(std::make_unique<IrradianceJudge>(std::move(*q), "gi"));
    }
    case TruthMetric::Sky: {
        reference::SkySettings settings;
        settings.samples = request.skySamples;
        settings.source = request.skyFromSh ? reference::SkySource::Sh : reference::SkySource::Image;
        auto q = IrradianceQuality::forSky(request.scene, request.origin, settings);
        if (!q) return q.error();
        return std::unique_ptr<TruthJudge>(std::make_unique<IrradianceJudge>(std::move(*q), "sky"));
    }
    case TruthMetric::Frame: {
        FrameQuality::Settings settings;
        settings.trace.maxBounces = request.frameBounces;
        settings.trace.maxSamples = request.frameMaxSamples;
        settings.trace.noiseTarget = request.frameNoise;
        settings.trace.timeLimitSeconds = request.frameTimeLimit;
        settings.cacheDir = request.frameTruthCache;
        if (!settings.cacheDir.empty()) {
            std::error_code ec;
            std::filesystem::create_directories(settings.cacheDir, ec);
            if (!std::filesystem::is_directory(settings.cacheDir, ec))
                return PlayError{PlayErrorKind::Io, settings.cacheDir + ": cannot create the truth cache directory"};
        }
        auto q = FrameQuality::create(request.frameTruthScene, request.origin, settings);
        if (!q) return q.error();
        return std::unique_ptr<TruthJudge>(std::make_unique<FrameJudge>(std::move(*q)));
    }
    }
    return PlayError{PlayErrorKind::Usage, "unknown truth metric"};
}

} // namespace pnb::player
