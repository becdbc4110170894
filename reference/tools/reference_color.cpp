// pnb-reference's colour shadow judgement (reference_color.h).
#include "reference_color.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include "diff_palette.h"

namespace pnb::reference_tool {

namespace {

using pnb::reference::ShadowColorClass;

Rgb8 colourOf(ShadowColorClass k) {
    switch (k) {
    case ShadowColorClass::AgreeLit: return kAgreeLit;
    case ShadowColorClass::AgreeShadow: return kAgreeShadow;
    case ShadowColorClass::AgreeTranslucent: return kAgreeTranslucent;
    case ShadowColorClass::FalseLit: return kFalseLit;
    case ShadowColorClass::FalseShadow: return kFalseShadow;
    case ShadowColorClass::Unclassified: break;
    }
    return kNoGeometry;
}

nlohmann::ordered_json rgb(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

} // namespace

Expected<pnb::reference::ShadowColorMetrics> judgeShadowColor(const std::string& outDir, const Frame& frame,
                                                              const FloatImage& player,
                                                              std::span<const glm::vec3> truth,
                                                              const pnb::reference::LocalLightWeights* reach,
                                                              std::span<const float> sunWeights) {
    const size_t pixels = truth.size();
    std::vector<glm::vec3> playerRgb(pixels);
    for (size_t p = 0; p < pixels; ++p) playerRgb[p] = {player.at(p, 0), player.at(p, 1), player.at(p, 2)};
    const pnb::reference::ShadowColorMetrics m =
        reach ? pnb::reference::compareLocalShadowColor(playerRgb, truth, *reach)
              : pnb::reference::compareShadowColor(playerRgb, truth, sunWeights);

    auto exr = writeImage(outDir + "/shadow_color_reference.exr", frame.width, frame.height, 3, OIIO::TypeDesc::FLOAT,
                          truth.data());
    if (!exr) return exr.error();
    // The error map paints each pixel as compareShadowColor counts it (classifyShadowColor), with
    // shadow_diff.png's colours; pale blue where both see the same light through glass.
    std::vector<uint8_t> map(pixels * 3);
    for (size_t p = 0; p < pixels; ++p) {
        const glm::vec3 pv = playerRgb[p], rv = truth[p];
        const bool playerGeometry = std::isfinite(pv.x + pv.y + pv.z) && pv.x >= 0 && pv.y >= 0 && pv.z >= 0;
        const bool referenceGeometry = std::isfinite(rv.x + rv.y + rv.z);
        Rgb8 colour = kNoGeometry;
        if (reach && !reach->reached[p] && (playerGeometry || referenceGeometry))
            colour = kNotReached;
        else if (playerGeometry != referenceGeometry)
            colour = kCoverage;
        else
            colour = colourOf(pnb::reference::classifyShadowColor(pv, rv));
        put(map, p, colour);
    }
    auto png = writeImage(outDir + "/shadow_color_diff.png", frame.width, frame.height, 3, OIIO::TypeDesc::UINT8,
                          map.data());
    if (!png) return png.error();
    return m;
}

nlohmann::ordered_json shadowColorJson(const pnb::reference::ShadowColorMetrics& m) {
    nlohmann::ordered_json j = {{"pixels", m.pixels},
                                {"translucent_pixels", m.translucentPixels},
                                {"misclassified_percent", m.misclassifiedPercent},
                                {"false_lit_percent", m.falseLitPercent},
                                {"false_shadow_percent", m.falseShadowPercent},
                                {"mean_abs_error", m.meanAbsError},
                                {"coverage_mismatch_pixels", m.coverageMismatch}};
    if (m.weighted) {
        j["weighted_error_percent"] = rgb(m.weightedErrorPercent);
        j["weighted_false_lit_percent"] = rgb(m.weightedFalseLitPercent);
        j["weighted_false_shadow_percent"] = rgb(m.weightedFalseShadowPercent);
    }
    return j;
}

void printShadowColorSummary(const pnb::reference::ShadowColorMetrics& m) {
    std::printf("  colour visibility over %llu pixels (%llu through glass): misclassified %.3f%% (false lit "
                "%.3f%%, false shadow %.3f%%), mean abs error %.4f; irradiance-weighted error r %.3f%% "
                "g %.3f%% b %.3f%%\n",
                (unsigned long long)m.pixels, (unsigned long long)m.translucentPixels, m.misclassifiedPercent,
                m.falseLitPercent, m.falseShadowPercent, m.meanAbsError, m.weightedErrorPercent.x,
                m.weightedErrorPercent.y, m.weightedErrorPercent.z);
}

} // namespace pnb::reference_tool
