#include "gi_quality.h"

#include <cmath>
#include <limits>

#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_reference/indirect_metrics.h"
#include "pnb_reference/shadow_metrics.h"

namespace pnb::player {

struct GiQuality::Impl {
    std::unique_ptr<reference::IndirectTracer> tracer;
    reference::IndirectSettings settings;
    glm::dvec3 origin{0.0};
    std::vector<glm::vec3> previous; // the last measured frame's player indirect light
};

GiQuality::~GiQuality() = default;

PlayResult<std::unique_ptr<GiQuality>> GiQuality::create(const std::string& containerPath, glm::dvec3 origin,
                                                         const reference::IndirectSettings& settings) {
    auto container = Container::open(containerPath);
    if (!container) return PlayError{PlayErrorKind::Input, container.error().describe()};
    auto scene = readScene(*container);
    if (!scene) return PlayError{PlayErrorKind::Input, scene.error().describe()};
    auto tracer = reference::IndirectTracer::build(*scene, origin);
    if (!tracer) return PlayError{PlayErrorKind::Input, "indirect reference: " + tracer.error().message};
    std::unique_ptr<GiQuality> q(new GiQuality());
    q->mImpl = std::make_unique<Impl>();
    q->mImpl->tracer = std::move(*tracer);
    q->mImpl->settings = settings;
    q->mImpl->origin = origin;
    return q;
}

PlayResult<std::vector<std::pair<std::string, double>>> GiQuality::measure(Renderer& renderer, bool followUp) {
    auto indirect = renderer.capture(CaptureBuffer::Indirect);
    if (!indirect) return indirect.error();
    const size_t pixels = size_t(indirect->width) * indirect->height;
    std::vector<glm::vec3> player(pixels);
    for (size_t i = 0; i < pixels; ++i)
        player[i] = {indirect->f32[i * 4], indirect->f32[i * 4 + 1], indirect->f32[i * 4 + 2]};
    std::vector<std::pair<std::string, double>> out;
    if (followUp) {
        if (mImpl->previous.size() == pixels) {
            double changed = 0, total = 0;
            for (size_t i = 0; i < pixels; ++i) {
                double a = reference::luminance(mImpl->previous[i]), b = reference::luminance(player[i]);
                if (!std::isfinite(a) || !std::isfinite(b)) continue;
                changed += std::fabs(b - a);
                total += a;
            }
            out.emplace_back("gi_flicker_pct", total > 0 ? 100.0 * changed / total : 0.0);
        }
        return out;
    }
    auto position = renderer.capture(CaptureBuffer::Position);
    if (!position) return position.error();
    auto normal = renderer.capture(CaptureBuffer::Normal);
    if (!normal) return normal.error();
    // Positions relative to the tracer's origin; the player's shading normal where it has one.
    glm::dvec3 shift = renderer.lastView().position - mImpl->origin;
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
    std::vector<glm::vec3> truth(pixels), error(pixels);
    mImpl->tracer->irradiance(points, normals, mImpl->settings, truth, error, shift);
    reference::IndirectErrorMetrics m = reference::compareIndirect(player, truth, error);
    out.emplace_back("gi_pixels", double(m.pixels));
    out.emplace_back("gi_rmse_pct", m.relativeRmsePercent);
    out.emplace_back("gi_reference_noise_pct", m.referenceNoisePercent);
    out.emplace_back("gi_corrected_rmse_pct", m.correctedRmsePercent);
    out.emplace_back("gi_energy_ratio", m.energyRatio);
    out.emplace_back("gi_red_ratio", m.channelRatio[0]);
    out.emplace_back("gi_green_ratio", m.channelRatio[1]);
    out.emplace_back("gi_blue_ratio", m.channelRatio[2]);
    out.emplace_back("gi_leak_pct", m.leakPercent);
    mImpl->previous = std::move(player);
    return out;
}

} // namespace pnb::player
