// frame_quality.h — pnb-judge's --frame-metrics: each measured frame's HDR image (CaptureBuffer::
// Hdr: linear radiance before exposure, what tonemap.frag displays) against the whole frame's
// path-traced truth (pnb_reference's FrameTracer) seen by the same camera: LDR-FLIP of the two
// images as the player displays them (its exposure and ACES fit), HDR-FLIP of the linear images,
// relative MSE, and the truth's own noise in both measures, so a reader sees when the truth is
// not converged enough to judge (issue 40: noise below a tenth of the metric it feeds).
//
// The truth depends on the container, the instant posed (clip and clip time), the camera, the
// size, the environment's rotation and intensity and the trace settings, not on any other player setting; with a cache directory it
// is traced once for them and read back by every later run (a sweep's configurations of one
// scene and frame share it). Cache files carry their key and an xxHash of their pixels, are
// written atomically and are re-traced when they do not verify.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "judged_scene.h"
#include "pnb_player/renderer.h"
#include "pnb_reference/frame_tracer.h"

namespace pnb::player {

class FrameQuality {
public:
    struct Settings {
        reference::FrameTraceSettings trace;
        std::string cacheDir; // empty: no cache
    };
    static PlayResult<std::unique_ptr<FrameQuality>> create(const std::string& containerPath, glm::dvec3 origin,
                                                            const Settings& settings);
    ~FrameQuality();

    // Metrics frame_flip_ldr, frame_flip_hdr, frame_relmse, frame_truth_noise_relmse,
    // frame_truth_noise_flip_ldr, frame_truth_samples, frame_truth_ms (0 when read from the
    // cache), frame_truth_cached. Nothing on a follow-up frame (the truth does not flicker).
    // `at`: the instant the frame was drawn at (judgedPose): the truth is traced (and cached)
    // for it, the tracer rebuilt only when the effective instant changes.
    PlayResult<std::vector<std::pair<std::string, double>>> measure(Renderer& renderer, bool followUp,
                                                                     const reference::FramePose& at = {});

    // The last measured frame as compared, rows top-down: the player's and the truth's HDR, the
    // LDR-FLIP map, the exposure both were displayed at. Empty before the first measurement.
    struct Frame {
        uint32_t width = 0, height = 0;
        std::span<const glm::vec3> player, truth;
        std::span<const float> flipLdr;
        double exposure = 1;
    };
    Frame lastFrame() const;

private:
    FrameQuality() = default;
    std::unique_ptr<JudgedScene> mJudged; // kept to trace it again at another instant
    glm::dvec3 mOrigin{0.0};
    reference::FramePose mTracedAt;       // mTracer's instant (effective)
    std::shared_ptr<reference::FrameTracer> mTracer;
    Settings mSettings;
    uint64_t mContainerHash = 0;
    std::vector<glm::vec3> mPlayer, mTruth;
    std::vector<float> mFlipLdr;
    uint32_t mWidth = 0, mHeight = 0;
    double mExposure = 1;
};

// The camera the player drew `view` with, at `width` x `height`, as the tracer takes it.
reference::FrameCamera frameCamera(const ViewMatrices& view, int width, int height);

} // namespace pnb::player
