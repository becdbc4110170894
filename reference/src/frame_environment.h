// frame_environment.h — the environment (ENVM radiance, equirectangular) as FrameTracer sees and
// samples it: radiance along a direction (bilinear, u wrapping, v clamped, as SkyTracer and the
// player's background read it), and directions drawn in proportion to each texel's luminance x
// its solid angle, with their pdf per steradian, for next-event estimation of the sky combined
// with BSDF sampling by multiple importance sampling (frame_tracer.cpp). Internal to pnb_reference.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "texture_decode.h"

namespace pnb::reference::detail {

// The environment's orientation and scale for one render: a world direction w sees the image
// at R_y(-angle) w (SkyTracer's convention), times intensity.
struct EnvironmentPose {
    double cosAngle = 1, sinAngle = 0, intensity = 1;
};

class EnvironmentMap {
public:
    explicit EnvironmentMap(LinearTexture image);

    glm::vec3 radiance(glm::vec3 w, const EnvironmentPose& pose) const;
    // A world direction drawn from four uniform numbers (row, column, within the texel), its pdf
    // (per steradian) in `pdf`; `pdf` 0 when the image is black everywhere (nothing to sample).
    glm::vec3 sample(const float u[4], const EnvironmentPose& pose, float& pdf) const;
    // The pdf with which sample() draws world direction w.
    float pdf(glm::vec3 w, const EnvironmentPose& pose) const;
    bool sampleable() const { return mTotal > 0.0; }

private:
    LinearTexture mImage;
    std::vector<double> mRowCdf;    // H + 1 entries, normalised: rows by their summed weight
    std::vector<double> mColumnCdf; // H x (W + 1), each row's columns, normalised
    std::vector<double> mTexelProbability; // W x H: the probability of drawing each texel
    double mTotal = 0;
};

} // namespace pnb::reference::detail
