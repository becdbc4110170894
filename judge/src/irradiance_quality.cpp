#include "irradiance_quality.h"

#include <cmath>
#include <limits>

#include "judged_scene.h"
#include "pnb_reference/indirect_metrics.h"
#include "pnb_reference/shadow_metrics.h"

namespace pnb::player {

IrradianceQuality::~IrradianceQuality() = default;

PlayResult<Done> IrradianceQuality::poseAt(const reference::FramePose& requested) {
    const reference::FramePose at = reference::effectivePose(mJudged->scene, requested);
    if (mTrace && at == mTracedAt) return Done{};
    auto trace = mBuild(at);
    if (!trace) return trace.error();
    mTrace = std::move(*trace);
    mTracedAt = at;
    return Done{};
}

PlayResult<std::unique_ptr<IrradianceQuality>> IrradianceQuality::forGi(const std::string& containerPath,
                                                                        glm::dvec3 origin,
                                                                        const reference::IndirectSettings& settings) {
    auto judged = JudgedScene::read(containerPath);
    if (!judged) return judged.error();
    std::unique_ptr<IrradianceQuality> q(new IrradianceQuality());
    q->mBuffer = CaptureBuffer::Indirect;
    q->mPrefix = "gi_";
    q->mOrigin = origin;
    q->mJudged = std::move(*judged);
    q->mBuild = [scene = &q->mJudged->scene, origin, settings](const reference::FramePose& at) -> PlayResult<Trace> {
        auto tracer = reference::IndirectTracer::build(*scene, origin, at);
        if (!tracer) return PlayError{PlayErrorKind::Input, "indirect reference: " + tracer.error().message};
        std::shared_ptr<reference::IndirectTracer> t(std::move(*tracer));
        return Trace([t, settings](const Renderer&, auto points, auto normals, auto truth, auto error, glm::dvec3 eye) {
            t->irradiance(points, normals, settings, truth, error, eye);
        });
    };
    if (auto built = q->poseAt({}); !built) return built.error(); // a refused scene fails now
    return q;
}

PlayResult<std::unique_ptr<IrradianceQuality>> IrradianceQuality::forSky(const std::string& containerPath,
                                                                         glm::dvec3 origin,
                                                                         const reference::SkySettings& settings) {
    auto judged = JudgedScene::read(containerPath);
    if (!judged) return judged.error();
    std::unique_ptr<IrradianceQuality> q(new IrradianceQuality());
    q->mBuffer = CaptureBuffer::Sky;
    q->mPrefix = "sky_";
    q->mOrigin = origin;
    q->mJudged = std::move(*judged);
    q->mBuild = [scene = &q->mJudged->scene, origin, settings](const reference::FramePose& at) -> PlayResult<Trace> {
        auto tracer = reference::SkyTracer::build(*scene, origin, at);
        if (!tracer) return PlayError{PlayErrorKind::Input, "sky reference: " + tracer.error().message};
        std::shared_ptr<reference::SkyTracer> t(std::move(*tracer));
        return Trace([t, settings](const Renderer& r, auto points, auto normals, auto truth, auto error, glm::dvec3 eye) {
            reference::SkySettings s = settings;
            s.rotationRadians = r.settings().iblRotationDeg * (3.14159265358979f / 180.0f);
            s.intensity = r.settings().iblIntensity;
            t->irradiance(points, normals, s, truth, error, eye);
        });
    };
    if (auto built = q->poseAt({}); !built) return built.error();
    return q;
}

PlayResult<std::vector<std::pair<std::string, double>>> IrradianceQuality::measure(Renderer& renderer, bool followUp,
                                                                                   const reference::FramePose& at) {
    auto indirect = renderer.capture(mBuffer);
    if (!indirect) return indirect.error();
    const size_t pixels = size_t(indirect->width) * indirect->height;
    std::vector<glm::vec3> player(pixels);
    for (size_t i = 0; i < pixels; ++i)
        player[i] = {indirect->f32[i * 4], indirect->f32[i * 4 + 1], indirect->f32[i * 4 + 2]};
    std::vector<std::pair<std::string, double>> out;
    if (followUp) {
        if (mPrevious.size() == pixels) {
            double changed = 0, total = 0;
            for (size_t i = 0; i < pixels; ++i) {
                double a = reference::luminance(mPrevious[i]), b = reference::luminance(player[i]);
                if (!std::isfinite(a) || !std::isfinite(b)) continue;
                changed += std::fabs(b - a);
                total += a;
            }
            out.emplace_back(mPrefix + "flicker_pct", total > 0 ? 100.0 * changed / total : 0.0);
        }
        return out;
    }
    auto position = renderer.capture(CaptureBuffer::Position);
    if (!position) return position.error();
    auto normal = renderer.capture(CaptureBuffer::Normal);
    if (!normal) return normal.error();
    // Positions relative to the tracer's origin; the player's shading normal where it has one.
    glm::dvec3 shift = renderer.lastView().position - mOrigin;
    std::vector<glm::vec3> cameraRelative(pixels), points(pixels), normals(pixels);
    for (size_t i = 0; i < pixels; ++i) {
        glm::dvec3 p(position->f32[i * 3], position->f32[i * 3 + 1], position->f32[i * 3 + 2]);
        cameraRelative[i] = glm::vec3(p);
        points[i] = glm::vec3(p + shift);
    }
    std::vector<glm::vec3> geometric =
        reference::normalsFromPositions(cameraRelative, int(position->width), int(position->height));
    for (size_t i = 0; i < pixels; ++i) {
        glm::vec3 n(normal->f32[i * 3], normal->f32[i * 3 + 1], normal->f32[i * 3 + 2]);
        normals[i] = glm::length(n) > 0.5f ? n : geometric[i];
        if (!std::isfinite(points[i].x)) player[i] = glm::vec3(std::numeric_limits<float>::quiet_NaN());
    }
    if (auto posed = poseAt(at); !posed) return posed.error(); // the truth of this frame's instant
    std::vector<glm::vec3> truth(pixels), error(pixels);
    mTrace(renderer, points, normals, truth, error, shift);
    reference::IndirectErrorMetrics m = reference::compareIndirect(player, truth, error);
    out.emplace_back(mPrefix + "pixels", double(m.pixels));
    out.emplace_back(mPrefix + "rmse_pct", m.relativeRmsePercent);
    out.emplace_back(mPrefix + "reference_noise_pct", m.referenceNoisePercent);
    out.emplace_back(mPrefix + "corrected_rmse_pct", m.correctedRmsePercent);
    out.emplace_back(mPrefix + "energy_ratio", m.energyRatio);
    out.emplace_back(mPrefix + "red_ratio", m.channelRatio[0]);
    out.emplace_back(mPrefix + "green_ratio", m.channelRatio[1]);
    out.emplace_back(mPrefix + "blue_ratio", m.channelRatio[2]);
    out.emplace_back(mPrefix + "leak_pct", m.leakPercent);
    out.emplace_back(mPrefix + "zero_rmse_pct", m.zeroRmsePercent);
    out.emplace_back(mPrefix + "best_constant_rmse_pct", m.bestConstantRmsePercent);
    out.emplace_back(mPrefix + "best_scale", m.bestScale);
    out.emplace_back(mPrefix + "scaled_rmse_pct", m.scaledRmsePercent);
    out.emplace_back(mPrefix + "correlation", m.correlation);
    out.emplace_back(mPrefix + "rmse_over_constant", m.rmseOverBestConstant);
    mPrevious = std::move(player);
    mLastTruth = std::move(truth);
    mLastError = std::move(error);
    mLastWidth = indirect->width;
    mLastHeight = indirect->height;
    mLastReferenceMean = m.referenceMean;
    return out;
}

IrradianceQuality::Frame IrradianceQuality::lastFrame() const {
    return {mLastWidth, mLastHeight, mPrevious, mLastTruth, mLastError, mLastReferenceMean};
}

} // namespace pnb::player
