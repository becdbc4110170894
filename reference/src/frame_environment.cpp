// The whole-frame tracer's environment (frame_environment.h).
#include "frame_environment.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "pnb_lighting/sh9.h"

namespace pnb::reference::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The index i with cdf[i] <= x < cdf[i + 1] (cdf non-decreasing, cdf[0] = 0, cdf.back() = 1),
// skipping empty bins.
size_t findBin(const double* cdf, size_t bins, double x) {
    const double* it = std::upper_bound(cdf, cdf + bins + 1, x);
    size_t i = size_t(std::max<std::ptrdiff_t>(0, (it - cdf) - 1));
    i = std::min(i, bins - 1);
    while (i + 1 < bins && !(cdf[i + 1] > cdf[i])) ++i; // an empty bin cannot be drawn
    return i;
}

glm::dvec3 toLocal(glm::vec3 w, const EnvironmentPose& p) {
    return {p.cosAngle * w.x - p.sinAngle * w.z, w.y, p.sinAngle * w.x + p.cosAngle * w.z}; // R_y(-angle) w
}

glm::vec3 toWorld(glm::dvec3 l, const EnvironmentPose& p) {
    return glm::vec3(glm::dvec3(p.cosAngle * l.x + p.sinAngle * l.z, l.y, -p.sinAngle * l.x + p.cosAngle * l.z));
}

} // namespace

EnvironmentMap::EnvironmentMap(LinearTexture image) : mImage(std::move(image)) {
    const size_t w = mImage.width, h = mImage.height;
    if (w == 0 || h == 0) return;
    mTexelProbability.assign(w * h, 0.0);
    mColumnCdf.assign(h * (w + 1), 0.0);
    mRowCdf.assign(h + 1, 0.0);
    // Weight: luminance x the row's solid angle (sin theta at its centre); non-finite or
    // negative texels weigh nothing.
    for (size_t j = 0; j < h; ++j) {
        const double sinTheta = std::sin(kPi * (double(j) + 0.5) / double(h));
        double* cdf = &mColumnCdf[j * (w + 1)];
        for (size_t i = 0; i < w; ++i) {
            const glm::vec4 t = mImage.texels[j * w + i];
            double weight = (0.2126 * t.x + 0.7152 * t.y + 0.0722 * t.z) * sinTheta;
            if (!std::isfinite(weight) || weight < 0) weight = 0;
            mTexelProbability[j * w + i] = weight;
            cdf[i + 1] = cdf[i] + weight;
        }
        mRowCdf[j + 1] = mRowCdf[j] + cdf[w];
    }
    mTotal = mRowCdf[h];
    if (!(mTotal > 0.0)) return;
    for (size_t j = 0; j < h; ++j) {
        double* cdf = &mColumnCdf[j * (w + 1)];
        const double row = cdf[w];
        for (size_t i = 0; i <= w; ++i) cdf[i] = row > 0 ? cdf[i] / row : double(i) / double(w);
    }
    for (double& c : mRowCdf) c /= mTotal;
    for (double& p : mTexelProbability) p /= mTotal;
}

glm::vec3 EnvironmentMap::radiance(glm::vec3 w, const EnvironmentPose& pose) const {
    const glm::dvec2 uv = lighting::equirectUv(toLocal(w, pose));
    return glm::vec3(glm::dvec3(glm::vec3(mImage.sample(glm::vec2(uv)))) * pose.intensity);
}

glm::vec3 EnvironmentMap::sample(const float r[4], const EnvironmentPose& pose, float& pdfOut) const {
    pdfOut = 0;
    if (!sampleable()) return glm::vec3(0.0f, 1.0f, 0.0f);
    const size_t w = mImage.width, h = mImage.height;
    const size_t j = findBin(mRowCdf.data(), h, double(r[0]));
    const size_t i = findBin(&mColumnCdf[j * (w + 1)], w, double(r[1]));
    const double u = (double(i) + double(r[2])) / double(w), v = (double(j) + double(r[3])) / double(h); // uniform in the texel
    const glm::vec3 world = toWorld(lighting::equirectDirection(u, v), pose);
    pdfOut = pdf(world, pose);
    return world;
}

float EnvironmentMap::pdf(glm::vec3 w, const EnvironmentPose& pose) const {
    if (!sampleable()) return 0.0f;
    const size_t width = mImage.width, height = mImage.height;
    const glm::dvec2 uv = lighting::equirectUv(toLocal(w, pose));
    const size_t i = std::min(width - 1, size_t(uv.x * double(width)));
    const size_t j = std::min(height - 1, size_t(uv.y * double(height)));
    const double sinTheta = std::sin(kPi * uv.y);
    if (!(sinTheta > 0.0)) return 0.0f;
    // Uniform in (u, v) within the texel: density p W H per unit uv square, and
    // d(omega) = 2 pi^2 sin(theta) du dv.
    return float(mTexelProbability[j * width + i] * double(width) * double(height) / (2.0 * kPi * kPi * sinTheta));
}

} // namespace pnb::reference::detail
