// Shadow error metrics (see shadow_metrics.h). Pure arithmetic; no Embree.
#include "pnb_reference/shadow_metrics.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>

#include <glm/geometric.hpp>

namespace pnb::reference {

namespace {

bool playerValid(float v) { return std::isfinite(v) && v >= 0.0f; }
bool referenceValid(float v) { return std::isfinite(v); }
bool lit(float v) { return v >= kLitThreshold; }

double percentOf(uint64_t part, uint64_t whole) {
    return whole ? 100.0 * double(part) / double(whole) : 0.0;
}

} // namespace

ShadowClass classifyShadow(float player, float reference) {
    if (!playerValid(player) || !referenceValid(reference)) return ShadowClass::Unclassified;
    const bool pl = lit(player), rl = lit(reference);
    if (pl == rl) return pl ? ShadowClass::AgreeLit : ShadowClass::AgreeShadow;
    return pl ? ShadowClass::FalseLit : ShadowClass::FalseShadow;
}

ShadowErrorMetrics compareShadow(std::span<const float> player, std::span<const float> reference,
                                 std::span<const float> weights) {
    assert(player.size() == reference.size());
    assert(weights.empty() || weights.size() == player.size());
    size_t n = std::min(player.size(), reference.size());
    ShadowErrorMetrics m;
    m.weighted = !weights.empty();
    if (m.weighted) n = std::min(n, weights.size());
    uint64_t falseLit = 0, falseShadow = 0;
    double absSum = 0, brighter = 0, darker = 0;
    for (size_t i = 0; i < n; ++i) {
        const bool pv = playerValid(player[i]), rv = referenceValid(reference[i]);
        if (pv != rv) ++m.coverageMismatch;
        const ShadowClass c = classifyShadow(player[i], reference[i]);
        if (c == ShadowClass::Unclassified) continue;
        ++m.pixels;
        falseLit += c == ShadowClass::FalseLit;
        falseShadow += c == ShadowClass::FalseShadow;
        absSum += std::fabs(double(player[i]) - double(reference[i]));
        if (m.weighted) {
            const double w = std::isfinite(weights[i]) && weights[i] > 0 ? weights[i] : 0.0;
            const double d = std::clamp(double(player[i]), 0.0, 1.0) - double(reference[i]);
            m.litIrradiance += w * double(reference[i]);
            (d > 0 ? brighter : darker) += w * std::fabs(d);
        }
    }
    m.falseLitPercent = percentOf(falseLit, m.pixels);
    m.falseShadowPercent = percentOf(falseShadow, m.pixels);
    m.misclassifiedPercent = percentOf(falseLit + falseShadow, m.pixels);
    m.meanAbsError = m.pixels ? absSum / double(m.pixels) : 0.0;
    if (m.weighted) {
        auto share = [&](double part) {
            return m.litIrradiance > 0 ? 100.0 * part / m.litIrradiance : part > 0 ? 100.0 : 0.0;
        };
        m.weightedFalseLitPercent = share(brighter);
        m.weightedFalseShadowPercent = share(darker);
        m.weightedErrorPercent = share(brighter + darker);
    }
    return m;
}

std::vector<glm::vec3> normalsFromPositions(std::span<const glm::vec3> positions, int width,
                                            int height, glm::vec3 eye) {
    assert(width >= 0 && height >= 0 && positions.size() == size_t(width) * size_t(height));
    std::vector<glm::vec3> out(positions.size(), glm::vec3(0.0f));
    if (positions.size() != size_t(width) * size_t(height)) return out;
    auto valid = [](glm::vec3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); };
    // The difference towards the spatially closer valid neighbour (forward minus backward order
    // kept, so the cross product's sign is consistent); zero when neither is valid.
    auto along = [&](glm::vec3 p, const glm::vec3* back, const glm::vec3* forward) {
        const bool b = back && valid(*back), f = forward && valid(*forward);
        if (b && f) {
            glm::vec3 db = p - *back, df = *forward - p;
            return glm::dot(db, db) < glm::dot(df, df) ? db : df;
        }
        return f ? *forward - p : b ? p - *back : glm::vec3(0.0f);
    };
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t i = size_t(y) * size_t(width) + size_t(x);
            const glm::vec3 p = positions[i];
            if (!valid(p)) continue;
            glm::vec3 dx = along(p, x > 0 ? &positions[i - 1] : nullptr,
                                 x + 1 < width ? &positions[i + 1] : nullptr);
            glm::vec3 dy = along(p, y > 0 ? &positions[i - size_t(width)] : nullptr,
                                 y + 1 < height ? &positions[i + size_t(width)] : nullptr);
            glm::dvec3 n = glm::cross(glm::dvec3(dx), glm::dvec3(dy));
            const double length = glm::length(n);
            if (!(length > 0) || !std::isfinite(length)) continue;
            n /= length;
            if (glm::dot(n, glm::dvec3(eye) - glm::dvec3(p)) < 0) n = -n;
            out[i] = glm::vec3(n);
        }
    return out;
}

std::vector<glm::vec3> weightNormals(std::span<const glm::vec3> normals,
                                     std::span<const glm::vec3> fallback) {
    const size_t n = std::max(normals.size(), fallback.size());
    auto usable = [](glm::vec3 v) {
        const float length = glm::length(v);
        return std::isfinite(length) && length > 0.0f;
    };
    std::vector<glm::vec3> out(n, glm::vec3(0.0f));
    for (size_t i = 0; i < n; ++i) {
        if (i < normals.size() && usable(normals[i]))
            out[i] = glm::normalize(normals[i]);
        else if (i < fallback.size() && usable(fallback[i]))
            out[i] = glm::normalize(fallback[i]);
    }
    return out;
}

std::vector<float> lambertWeights(std::span<const glm::vec3> normals,
                                  std::span<const glm::vec3> fallback, glm::vec3 towardLight) {
    const glm::vec3 l = glm::normalize(towardLight);
    std::vector<glm::vec3> chosen = weightNormals(normals, fallback);
    std::vector<float> out(chosen.size(), 0.0f);
    for (size_t i = 0; i < chosen.size(); ++i)
        out[i] = std::max(0.0f, glm::dot(chosen[i], l));
    return out;
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
