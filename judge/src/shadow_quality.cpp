#include "shadow_quality.h"

#include <cmath>
#include <optional>

#include "judged_scene.h"
#include "pnb_reference/local_light.h"
#include "pnb_reference/shadow_color_metrics.h"
#include "pnb_reference/shadow_metrics.h"
#include "pnb_reference/shadow_tracer.h"

namespace pnb::player {

struct ShadowQuality::Impl {
    std::unique_ptr<JudgedScene> judged; // kept to trace it again at another instant
    glm::dvec3 origin{0.0};
    int judgedLight = -1;
    reference::FramePose tracedAt; // the instant the tracer and the light are posed at (effective)
    std::unique_ptr<reference::ShadowTracer> tracer;
    std::optional<reference::LocalLight> local; // the judged point or spot light, if not the sun

    // The tracer and the judged light posed at `at` (rebuilt only when the instant changes).
    PlayResult<Done> poseAt(const reference::FramePose& at);
    // The last measured frame, for the follow-up's flicker and lastFrame().
    std::vector<float> previousPlayer, previousTruth;
    // With translucent casters (issue 43): the same frame in colour, as compared.
    std::vector<glm::vec3> playerColor, truthColor;
    uint32_t width = 0, height = 0;
};

namespace {

float meanOf(glm::vec3 v) { return (v.r + v.g + v.b) / 3.0f; }

// The metrics' columns from the colour comparison (light through glass): the same names as the
// grey comparison's, with the weighted figures as the mean over the channels, and how many
// pixels the truth sees through glass.
void addColorColumns(const reference::ShadowColorMetrics& m, std::vector<std::pair<std::string, double>>& out) {
    auto mean3 = [](const glm::dvec3& v) { return (v.r + v.g + v.b) / 3.0; };
    out.emplace_back("pixels", double(m.pixels));
    out.emplace_back("misclassified_pct", m.misclassifiedPercent);
    out.emplace_back("false_lit_pct", m.falseLitPercent);
    out.emplace_back("false_shadow_pct", m.falseShadowPercent);
    out.emplace_back("mean_abs_error", m.meanAbsError);
    out.emplace_back("weighted_error_pct", mean3(m.weightedErrorPercent));
    out.emplace_back("weighted_false_lit_pct", mean3(m.weightedFalseLitPercent));
    out.emplace_back("weighted_false_shadow_pct", mean3(m.weightedFalseShadowPercent));
    out.emplace_back("translucent_pixels", double(m.translucentPixels));
}

} // namespace

PlayResult<Done> ShadowQuality::Impl::poseAt(const reference::FramePose& requested) {
    const reference::FramePose at = reference::effectivePose(judged->scene, requested);
    if (tracer && at == tracedAt) return Done{};
    auto built = reference::ShadowTracer::build(judged->scene, origin, at);
    if (!built) return PlayError{PlayErrorKind::Input, "shadow reference: " + built.error().message};
    if (judgedLight >= 0) {
        auto light = reference::placeLocalLight(judged->scene, uint32_t(judgedLight), at);
        if (!light) return PlayError{PlayErrorKind::Usage, "shadows.judged_light: " + light.error().message};
        local = std::move(*light);
    }
    tracer = std::move(*built);
    tracedAt = at;
    return Done{};
}

ShadowQuality::~ShadowQuality() = default;

PlayResult<std::unique_ptr<ShadowQuality>> ShadowQuality::create(const std::string& containerPath,
                                                                 glm::dvec3 origin, int judgedLight) {
    auto judged = JudgedScene::read(containerPath);
    if (!judged) return judged.error();
    std::unique_ptr<ShadowQuality> q(new ShadowQuality());
    q->mImpl = std::make_unique<Impl>();
    q->mImpl->judged = std::move(*judged);
    q->mImpl->origin = origin;
    q->mImpl->judgedLight = judgedLight;
    // Built now at the container as stored, so a scene the tracer refuses fails before any frame.
    if (auto built = q->mImpl->poseAt({}); !built) return built.error();
    return q;
}

PlayResult<std::vector<std::pair<std::string, double>>> ShadowQuality::measure(Renderer& renderer,
                                                                                glm::vec3 towardLight,
                                                                                bool followUp,
                                                                                const reference::FramePose& at) {
    // The truth of the instant this frame was drawn at (the follow-up's own, for its flicker).
    if (auto posed = mImpl->poseAt(at); !posed) return posed.error();
    auto position = renderer.capture(CaptureBuffer::Position);
    if (!position) return position.error();
    auto normal = renderer.capture(CaptureBuffer::Normal);
    if (!normal) return normal.error();
    auto shadow = renderer.capture(CaptureBuffer::Shadow);
    if (!shadow) return shadow.error();
    size_t pixels = size_t(position->width) * position->height;
    // Glass in the scene (the truth's translucent casters): judged in colour, the player's
    // colour capture against the colour truth (whatever shadows.translucent says: with it off,
    // the player's grey verdict meets the truth's tinted one).
    const bool color = mImpl->tracer->stats().translucentCasters > 0;
    std::optional<CapturedImage> shadowColor;
    if (color) {
        auto c = renderer.capture(CaptureBuffer::ShadowColor);
        if (!c) return c.error();
        shadowColor = std::move(*c);
    }

    // Camera-relative positions to the tracer's origin, in double.
    glm::dvec3 shift = renderer.lastView().position - mImpl->tracer->origin();
    std::vector<glm::vec3> cameraRelative(pixels), points(pixels), normals(pixels);
    std::vector<float> player(pixels), cascade(pixels), ratio(pixels), truth(pixels);
    for (size_t i = 0; i < pixels; ++i) {
        glm::dvec3 p(position->f32[i * 3], position->f32[i * 3 + 1], position->f32[i * 3 + 2]);
        cameraRelative[i] = glm::vec3(p);
        points[i] = glm::vec3(p + shift);
        normals[i] = {normal->f32[i * 3], normal->f32[i * 3 + 1], normal->f32[i * 3 + 2]};
        player[i] = shadow->f32[i * 4];         // negative: not classified (facing away, none)
        cascade[i] = shadow->f32[i * 4 + 1];
        ratio[i] = shadow->f32[i * 4 + 2];
    }
    // The eye-relative light, for a judged point or spot light.
    const glm::dvec3 eye = renderer.lastView().position;
    const glm::dvec3 lightFromEye = mImpl->local ? mImpl->local->position - eye : glm::dvec3(0.0);
    std::vector<glm::vec3> playerColor, truthColor;
    if (color) {
        playerColor.resize(pixels);
        truthColor.resize(pixels);
        for (size_t i = 0; i < pixels; ++i) {
            const float* c = &shadowColor->f32[i * 4];
            playerColor[i] = {c[0], c[1], c[2]};
        }
        if (mImpl->local)
            mImpl->tracer->colorVisibilityToPoint(points, glm::vec3(lightFromEye + shift), truthColor, shift);
        else
            mImpl->tracer->colorVisibility(points, towardLight, truthColor, shift);
        // The grey figures (flicker, the texel ratios' pixels) from the same colours: their means.
        for (size_t i = 0; i < pixels; ++i) truth[i] = meanOf(truthColor[i]);
    } else if (mImpl->local) {
        mImpl->tracer->visibilityToPoint(points, glm::vec3(lightFromEye + shift), truth, shift);
    } else {
        mImpl->tracer->visibility(points, towardLight, truth, shift);
    }
    // Surfaces facing away (or, for a local light, out of its reach) are dark whatever the map
    // says: the player leaves them out, and so does the comparison.
    for (size_t i = 0; i < pixels; ++i)
        if (player[i] < 0) {
            truth[i] = std::numeric_limits<float>::quiet_NaN();
            if (color) truthColor[i] = glm::vec3(std::numeric_limits<float>::quiet_NaN());
        }

    std::vector<std::pair<std::string, double>> out;
    out.reserve(8); // also spares GCC 12 a false -Warray-bounds on the first emplace_back
    if (followUp) {
        if (mImpl->previousPlayer.size() == pixels) {
            // Changes of the player's classification the truth does not have.
            uint64_t both = 0, changed = 0, spurious = 0;
            for (size_t i = 0; i < pixels; ++i) {
                float a = mImpl->previousPlayer[i], b = player[i], ta = mImpl->previousTruth[i], tb = truth[i];
                if (!(a >= 0) || !(b >= 0) || !std::isfinite(ta) || !std::isfinite(tb)) continue;
                ++both;
                bool playerChanged = (a < reference::kLitThreshold) != (b < reference::kLitThreshold);
                bool truthChanged = (ta < reference::kLitThreshold) != (tb < reference::kLitThreshold);
                changed += playerChanged;
                spurious += playerChanged && !truthChanged;
            }
            out.emplace_back("flicker_pct", both ? 100.0 * double(changed) / double(both) : 0.0);
            out.emplace_back("spurious_flicker_pct", both ? 100.0 * double(spurious) / double(both) : 0.0);
        }
        return out;
    }
    // Irradiance weights from the shading normal, or the positions' own where the player has
    // none (forward surfaces).
    const std::vector<glm::vec3> fallback =
        reference::normalsFromPositions(cameraRelative, int(position->width), int(position->height));
    if (color) {
        const reference::ShadowColorMetrics m =
            mImpl->local ? reference::compareLocalShadowColor(
                               playerColor, truthColor,
                               reference::localLightWeights(*mImpl->local, lightFromEye, cameraRelative, normals, fallback))
                         : reference::compareShadowColor(playerColor, truthColor,
                                                         reference::lambertWeights(normals, fallback, towardLight));
        addColorColumns(m, out);
    } else {
        reference::ShadowErrorMetrics m;
        if (mImpl->local) {
            const reference::LocalLightWeights w =
                reference::localLightWeights(*mImpl->local, lightFromEye, cameraRelative, normals, fallback);
            m = reference::compareLocalShadow(player, truth, w);
        } else {
            m = reference::compareShadow(player, truth, reference::lambertWeights(normals, fallback, towardLight));
        }
        out.emplace_back("pixels", double(m.pixels));
        out.emplace_back("misclassified_pct", m.misclassifiedPercent);
        out.emplace_back("false_lit_pct", m.falseLitPercent);
        out.emplace_back("false_shadow_pct", m.falseShadowPercent);
        out.emplace_back("mean_abs_error", m.meanAbsError);
        out.emplace_back("weighted_error_pct", m.weightedErrorPercent);
        out.emplace_back("weighted_false_lit_pct", m.weightedFalseLitPercent);
        out.emplace_back("weighted_false_shadow_pct", m.weightedFalseShadowPercent);
    }
    for (const reference::RatioStats& r : reference::texelRatioByCascade(cascade, ratio)) {
        out.emplace_back("texel_ratio_median_c" + std::to_string(r.cascade), r.median);
        out.emplace_back("texel_ratio_p95_c" + std::to_string(r.cascade), r.p95);
    }
    mImpl->previousPlayer = std::move(player);
    mImpl->previousTruth = std::move(truth);
    mImpl->playerColor = std::move(playerColor);
    mImpl->truthColor = std::move(truthColor);
    mImpl->width = position->width;
    mImpl->height = position->height;
    return out;
}

ShadowQuality::Frame ShadowQuality::lastFrame() const {
    return {mImpl->width, mImpl->height, mImpl->previousPlayer, mImpl->previousTruth, mImpl->playerColor,
            mImpl->truthColor};
}

} // namespace pnb::player
