// Colour shadow metrics (see shadow_color_metrics.h). Pure arithmetic; no Embree.
#include "pnb_reference/shadow_color_metrics.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace pnb::reference {

namespace {

bool playerValid(glm::vec3 v) {
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(v[c]) || v[c] < 0.0f) return false;
    return true;
}
bool referenceValid(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The step from the truth's state to the state the player's value is nearest (ties to the
// brighter): -1 a darker state, 0 the truth's own, +1 a brighter one. States: 0, t when
// 0 < t < 1, and 1.
int channelStep(float player, float truth) {
    if (!(truth > 0.0f)) return player >= 0.5f ? 1 : 0;
    if (!(truth < 1.0f)) return player >= 0.5f ? 0 : -1;
    // Nearer 0 than t: below t / 2; nearer 1 than t (or as near): at or above (1 + t) / 2.
    if (player < 0.5f * truth) return -1;
    return player >= 0.5f * (1.0f + truth) ? 1 : 0;
}

double percentOf(uint64_t part, uint64_t whole) { return whole ? 100.0 * double(part) / double(whole) : 0.0; }

} // namespace

ShadowColorClass classifyShadowColor(glm::vec3 player, glm::vec3 reference) {
    if (!playerValid(player) || !referenceValid(reference)) return ShadowColorClass::Unclassified;
    int steps = 0, misclassified = 0;
    double difference = 0;
    for (int c = 0; c < 3; ++c) {
        const int step = channelStep(player[c], reference[c]);
        if (step == 0) continue;
        steps += step;
        ++misclassified;
        difference += double(player[c]) - double(reference[c]);
    }
    if (misclassified) {
        const bool brighter = steps != 0 ? steps > 0 : difference > 0;
        return brighter ? ShadowColorClass::FalseLit : ShadowColorClass::FalseShadow;
    }
    auto all = [&](float v) { return reference.x == v && reference.y == v && reference.z == v; };
    return all(1.0f) ? ShadowColorClass::AgreeLit
           : all(0.0f) ? ShadowColorClass::AgreeShadow
                       : ShadowColorClass::AgreeTranslucent;
}

ShadowColorMetrics compareShadowColor(std::span<const glm::vec3> player, std::span<const glm::vec3> reference,
                                      std::span<const float> weights) {
    assert(player.size() == reference.size());
    assert(weights.empty() || weights.size() == player.size());
    size_t n = std::min(player.size(), reference.size());
    ShadowColorMetrics m;
    m.weighted = !weights.empty();
    if (m.weighted) n = std::min(n, weights.size());
    uint64_t falseLit = 0, falseShadow = 0;
    double absSum = 0;
    glm::dvec3 brighter(0.0), darker(0.0);
    for (size_t i = 0; i < n; ++i) {
        const glm::vec3 p = player[i], r = reference[i];
        if (playerValid(p) != referenceValid(r)) ++m.coverageMismatch;
        const ShadowColorClass k = classifyShadowColor(p, r);
        if (k == ShadowColorClass::Unclassified) continue;
        ++m.pixels;
        falseLit += k == ShadowColorClass::FalseLit;
        falseShadow += k == ShadowColorClass::FalseShadow;
        m.translucentPixels += !(r == glm::vec3(1.0f) || r == glm::vec3(0.0f));
        const double w = m.weighted && std::isfinite(weights[i]) && weights[i] > 0 ? weights[i] : 0.0;
        for (int c = 0; c < 3; ++c) {
            absSum += std::fabs(double(p[c]) - double(r[c]));
            if (!m.weighted) continue;
            // Per channel exactly compareShadow's arithmetic, so a grey pixel adds the same bits.
            const double d = std::clamp(double(p[c]), 0.0, 1.0) - double(r[c]);
            m.litIrradiance[c] += w * double(r[c]);
            (d > 0 ? brighter[c] : darker[c]) += w * std::fabs(d);
        }
    }
    m.falseLitPercent = percentOf(falseLit, m.pixels);
    m.falseShadowPercent = percentOf(falseShadow, m.pixels);
    m.misclassifiedPercent = percentOf(falseLit + falseShadow, m.pixels);
    m.meanAbsError = m.pixels ? absSum / (3.0 * double(m.pixels)) : 0.0;
    if (m.weighted)
        for (int c = 0; c < 3; ++c) {
            auto share = [&](double part) {
                return m.litIrradiance[c] > 0 ? 100.0 * part / m.litIrradiance[c] : part > 0 ? 100.0 : 0.0;
            };
            m.weightedFalseLitPercent[c] = share(brighter[c]);
            m.weightedFalseShadowPercent[c] = share(darker[c]);
            m.weightedErrorPercent[c] = share(brighter[c] + darker[c]);
        }
    return m;
}

} // namespace pnb::reference
