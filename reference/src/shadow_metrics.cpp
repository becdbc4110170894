// Shadow error metrics (see shadow_metrics.h). Pure arithmetic; no Embree.
#include "pnb_reference/shadow_metrics.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>

namespace pnb::reference {

namespace {

bool playerValid(float v) { return std::isfinite(v) && v >= 0.0f; }
bool referenceValid(float v) { return std::isfinite(v); }
bool lit(float v) { return v >= kLitThreshold; }

double percentOf(uint64_t part, uint64_t whole) {
    return whole ? 100.0 * double(part) / double(whole) : 0.0;
}

} // namespace

ShadowErrorMetrics compareShadow(std::span<const float> player, std::span<const float> reference) {
    assert(player.size() == reference.size());
    const size_t n = std::min(player.size(), reference.size());
    ShadowErrorMetrics m;
    uint64_t falseLit = 0, falseShadow = 0;
    double absSum = 0;
    for (size_t i = 0; i < n; ++i) {
        const bool pv = playerValid(player[i]), rv = referenceValid(reference[i]);
        if (pv != rv) ++m.coverageMismatch;
        if (!pv || !rv) continue;
        ++m.pixels;
        const bool pl = lit(player[i]), rl = lit(reference[i]);
        if (pl && !rl) ++falseLit;
        if (!pl && rl) ++falseShadow;
        absSum += std::fabs(double(player[i]) - double(reference[i]));
    }
    m.falseLitPercent = percentOf(falseLit, m.pixels);
    m.falseShadowPercent = percentOf(falseShadow, m.pixels);
    m.misclassifiedPercent = percentOf(falseLit + falseShadow, m.pixels);
    m.meanAbsError = m.pixels ? absSum / double(m.pixels) : 0.0;
    return m;
}

double flickerPercent(std::span<const float> previous, std::span<const float> current) {
    assert(previous.size() == current.size());
    const size_t n = std::min(previous.size(), current.size());
    uint64_t valid = 0, changed = 0;
    for (size_t i = 0; i < n; ++i) {
        if (!playerValid(previous[i]) || !playerValid(current[i])) continue;
        ++valid;
        if (lit(previous[i]) != lit(current[i])) ++changed;
    }
    return percentOf(changed, valid);
}

double percentile(std::span<double> values, double p) {
    if (values.empty()) return 0.0;
    const double h = double(values.size() - 1) * std::clamp(p, 0.0, 100.0) / 100.0;
    const auto lo = size_t(std::floor(h));
    auto loIt = values.begin() + std::ptrdiff_t(lo);
    std::nth_element(values.begin(), loIt, values.end());
    const double a = *loIt;
    if (lo + 1 >= values.size()) return a;
    // The next order statistic is the minimum of the part after lo.
    const double b = *std::min_element(loIt + 1, values.end());
    return a + (h - double(lo)) * (b - a);
}

std::vector<RatioStats> texelRatioByCascade(std::span<const float> cascade,
                                            std::span<const float> ratio) {
    assert(cascade.size() == ratio.size());
    const size_t n = std::min(cascade.size(), ratio.size());
    std::map<int, std::vector<double>> groups;
    for (size_t i = 0; i < n; ++i) {
        const float c = cascade[i], r = ratio[i];
        // Indices beyond any plausible cascade count are garbage, not cascades.
        if (!std::isfinite(c) || c < 0.0f || c > 1024.0f) continue;
        if (!std::isfinite(r) || !(r > 0.0f)) continue;
        groups[int(std::lround(c))].push_back(double(r));
    }
    std::vector<RatioStats> out;
    for (auto& [index, values] : groups) {
        RatioStats s;
        s.cascade = index;
        s.pixels = values.size();
        s.median = percentile(values, 50.0);
        s.p95 = percentile(values, 95.0);
        out.push_back(s);
    }
    return out;
}

} // namespace pnb::reference
