// irradiance_quality.h — pnb-play's --gi-metrics and --sky-metrics: each measured frame's
// irradiance as the player applied it (CaptureBuffer::Indirect: GI's one bounce; CaptureBuffer::
// Sky: the environment's light times the sky-visibility term) compared with the ray-traced truth
// (pnb_reference's IndirectTracer or SkyTracer) at the exact pixels the player drew; on the frame
// after it, flicker: how much the player's irradiance changed in 1/60 s of camera motion (the
// truth barely does). Metric names carry the prefix ("gi_rmse_pct", "sky_energy_ratio").
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "judged_scene.h"
#include "pnb_player/renderer.h"
#include "pnb_reference/indirect_tracer.h"
#include "pnb_reference/sky_tracer.h"

namespace pnb::player {

class IrradianceQuality {
public:
    // One bounce of the scene's lights (GI).
    static PlayResult<std::unique_ptr<IrradianceQuality>> forGi(const std::string& containerPath, glm::dvec3 origin,
                                                                const reference::IndirectSettings& settings);
    // Sky light from the container's environment; the rotation and intensity are taken from the
    // renderer's settings at each measurement.
    static PlayResult<std::unique_ptr<IrradianceQuality>> forSky(const std::string& containerPath, glm::dvec3 origin,
                                                                 const reference::SkySettings& settings);
    ~IrradianceQuality();

    // `at`: the instant the frame was drawn at (judgedPose): the truth is traced there (the
    // tracer rebuilt only when the effective instant changes; a follow-up traces nothing).
    PlayResult<std::vector<std::pair<std::string, double>>> measure(Renderer& renderer, bool followUp,
                                                                     const reference::FramePose& at = {});

    // The last measured frame (not a follow-up) exactly as compared: per pixel the player's and
    // the truth's irradiance and the truth's standard error (a pixel counts where
    // reference::comparedPixel holds), rows bottom-up as captured, and the metric's mean truth
    // luminance. Empty (0 x 0) before the first measurement; valid until the next one.
    struct Frame {
        uint32_t width = 0, height = 0;
        std::span<const glm::vec3> player, truth, standardError;
        double referenceMean = 0;
    };
    Frame lastFrame() const;

private:
    IrradianceQuality() = default;
    // Truth at origin-relative points with the eye at `eye` (origin-relative).
    using Trace = std::function<void(const Renderer&, std::span<const glm::vec3> points,
                                     std::span<const glm::vec3> normals, std::span<glm::vec3> truth,
                                     std::span<glm::vec3> error, glm::dvec3 eye)>;
    // A tracer's Trace at an instant; the tracer of the last instant traced.
    using Build = std::function<PlayResult<Trace>(const reference::FramePose&)>;
    PlayResult<Done> poseAt(const reference::FramePose& at);
    std::unique_ptr<JudgedScene> mJudged;
    Build mBuild;
    reference::FramePose mTracedAt;
    CaptureBuffer mBuffer = CaptureBuffer::Indirect;
    std::string mPrefix;
    Trace mTrace;
    glm::dvec3 mOrigin{0.0};
    std::vector<glm::vec3> mPrevious; // the last measured frame's player irradiance
    std::vector<glm::vec3> mLastTruth, mLastError; // and its truth, for lastFrame()
    uint32_t mLastWidth = 0, mLastHeight = 0;
    double mLastReferenceMean = 0;
};

} // namespace pnb::player
