// Player indirect irradiance against the one-bounce truth (indirect_metrics.h).
#include "pnb_reference/indirect_metrics.h"

#include <algorithm>
#include <cmath>

namespace pnb::reference {

bool comparedPixel(const glm::vec3& player, const glm::vec3& reference, const glm::vec3& standardError) {
    auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    return finite(player) && finite(reference) && finite(standardError);
}

IndirectErrorMetrics compareIndirect(std::span<const glm::vec3> player, std::span<const glm::vec3> reference,
                                     std::span<const glm::vec3> standardError) {
    IndirectErrorMetrics m;
    if (player.size() != reference.size() || standardError.size() != reference.size()) return m;
    double sumP = 0, sumR = 0, sq = 0, noise = 0, channelP[3] = {0, 0, 0}, channelR[3] = {0, 0, 0};
    for (size_t i = 0; i < reference.size(); ++i) {
        if (!comparedPixel(player[i], reference[i], standardError[i])) continue;
        ++m.pixels;
        double p = luminance(player[i]), r = luminance(reference[i]), se = luminance(standardError[i]);
        sumP += p;
        sumR += r;
        sq += (p - r) * (p - r);
        noise += se * se;
        for (int c = 0; c < 3; ++c) {
            channelP[c] += player[i][c];
            channelR[c] += reference[i][c];
        }
    }
    if (m.pixels == 0) return m;
    const double n = double(m.pixels);
    m.referenceMean = sumR / n;
    m.playerMean = sumP / n;
    if (m.referenceMean > 0) {
        m.relativeRmsePercent = 100.0 * std::sqrt(sq / n) / m.referenceMean;
        m.referenceNoisePercent = 100.0 * std::sqrt(noise / n) / m.referenceMean;
        m.correctedRmsePercent = 100.0 * std::sqrt(std::max(0.0, (sq - noise) / n)) / m.referenceMean;
    }
    m.energyRatio = sumR > 0 ? sumP / sumR : 0.0;
    for (int c = 0; c < 3; ++c) m.channelRatio[c] = channelR[c] > 0 ? channelP[c] / channelR[c] : 0.0;
    double leak = 0;
    for (size_t i = 0; i < reference.size(); ++i) {
        if (!comparedPixel(player[i], reference[i], standardError[i])) continue;
        double r = luminance(reference[i]), se = luminance(standardError[i]);
        if (r < 3.0 * se + 1e-30 && r < 0.01 * m.referenceMean) leak += luminance(player[i]);
    }
    m.leakPercent = sumP > 0 ? 100.0 * leak / sumP : 0.0;

    // The scorecard's baselines (second pass: they need the means).
    double zero = 0, constant = 0, pp = 0, pr = 0, varP = 0, cov = 0;
    for (size_t i = 0; i < reference.size(); ++i) {
        if (!comparedPixel(player[i], reference[i], standardError[i])) continue;
        double p = luminance(player[i]), r = luminance(reference[i]);
        zero += r * r;
        constant += (r - m.referenceMean) * (r - m.referenceMean);
        pp += p * p;
        pr += p * r;
        varP += (p - m.playerMean) * (p - m.playerMean);
        cov += (p - m.playerMean) * (r - m.referenceMean);
    }
    m.bestScale = pp > 0 ? pr / pp : 0.0;
    // sum (s p - r)^2 = s^2 pp - 2 s pr + rr, with rr = zero.
    const double scaled = m.bestScale * m.bestScale * pp - 2.0 * m.bestScale * pr + zero;
    auto corrected = [&](double sumSquares) {
        return m.referenceMean > 0 ? 100.0 * std::sqrt(std::max(0.0, (sumSquares - noise) / n)) / m.referenceMean
                                   : 0.0;
    };
    m.zeroRmsePercent = corrected(zero);
    m.bestConstantRmsePercent = corrected(constant);
    m.scaledRmsePercent = corrected(std::max(0.0, scaled));
    const double varR = constant - noise; // the truth's own variance, its noise taken out
    m.correlation = varP > 0 && varR > 0 ? std::clamp(cov / std::sqrt(varP * varR), -1.0, 1.0) : 0.0;
    m.rmseOverBestConstant =
        m.bestConstantRmsePercent > 0 ? m.correctedRmsePercent / m.bestConstantRmsePercent : 0.0;
    return m;
}

} // namespace pnb::reference
