// pnb-judge --error-maps: the truth metrics' last measured frame as heat-maps (truth_error_maps.h).
#include "truth_error_maps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pnb_reference/indirect_metrics.h"
#include "pnb_reference/shadow_color_metrics.h"
#include "pnb_reference/shadow_metrics.h"

namespace pnb::player {

Rgb8 falseLitColour(double absError) {
    const uint8_t v = toByte(64.0 + 191.0 * std::min(absError, 1.0));
    return {v, 0, 0};
}

Rgb8 falseShadowColour(double absError) {
    const uint8_t v = toByte(64.0 + 191.0 * std::min(absError, 1.0));
    return {0, toByte(0.35 * v), v};
}

namespace {

// A colour frame's pixel (light through glass) as the grey classes, or AgreeGlass; `d` the
// largest channel's |player - truth|.
enum class PixelClass { Unclassified, AgreeLit, AgreeShadow, AgreeGlass, FalseLit, FalseShadow };

PixelClass classifyPixel(const ShadowQuality::Frame& frame, size_t i, double& d) {
    if (frame.playerColor.empty()) {
        const float p = frame.player[i], t = frame.truth[i];
        d = std::fabs(std::clamp(double(p), 0.0, 1.0) - double(t));
        switch (reference::classifyShadow(p, t)) {
        case reference::ShadowClass::Unclassified: return PixelClass::Unclassified;
        case reference::ShadowClass::AgreeLit: return PixelClass::AgreeLit;
        case reference::ShadowClass::AgreeShadow: return PixelClass::AgreeShadow;
        case reference::ShadowClass::FalseLit: return PixelClass::FalseLit;
        case reference::ShadowClass::FalseShadow: return PixelClass::FalseShadow;
        }
        return PixelClass::Unclassified;
    }
    const glm::vec3 p = frame.playerColor[i], t = frame.truthColor[i];
    d = 0;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::fabs(std::clamp(double(p[k]), 0.0, 1.0) - double(t[k])));
    switch (reference::classifyShadowColor(p, t)) {
    case reference::ShadowColorClass::Unclassified: return PixelClass::Unclassified;
    case reference::ShadowColorClass::AgreeLit: return PixelClass::AgreeLit;
    case reference::ShadowColorClass::AgreeShadow: return PixelClass::AgreeShadow;
    case reference::ShadowColorClass::AgreeTranslucent: return PixelClass::AgreeGlass;
    case reference::ShadowColorClass::FalseLit: return PixelClass::FalseLit;
    case reference::ShadowColorClass::FalseShadow: return PixelClass::FalseShadow;
    }
    return PixelClass::Unclassified;
}

} // namespace

ErrorMap shadowErrorMap(const ShadowQuality::Frame& frame) {
    const size_t pixels = size_t(frame.width) * frame.height;
    if (pixels == 0 || frame.player.size() != pixels || frame.truth.size() != pixels) return {};
    const bool color = !frame.playerColor.empty();
    if (color && (frame.playerColor.size() != pixels || frame.truthColor.size() != pixels)) return {};
    ErrorMap m = blankErrorMap("shadow", frame.width, frame.height);
    uint64_t classified = 0, falseLit = 0, falseShadow = 0;
    for (size_t i = 0; i < pixels; ++i) {
        double d = 0;
        const PixelClass k = classifyPixel(frame, i, d);
        Rgb8 c = kMapOutside;
        switch (k) {
        case PixelClass::Unclassified: break;
        case PixelClass::AgreeLit: c = kShadowAgreeLit; break;
        case PixelClass::AgreeShadow: c = kShadowAgreeDark; break;
        case PixelClass::AgreeGlass: c = kShadowAgreeGlass; break;
        case PixelClass::FalseLit:
            c = falseLitColour(d);
            ++falseLit;
            break;
        case PixelClass::FalseShadow:
            c = falseShadowColour(d);
            ++falseShadow;
            break;
        }
        classified += k != PixelClass::Unclassified;
        putCapturedPixel(m, i, c);
    }
    char threshold[16];
    std::snprintf(threshold, sizeof threshold, "%g", double(reference::kLitThreshold));
    m.encoding = color ? std::string("per pixel, the light of each colour the player let through (glass in the "
                                     "scene) against the ray-traced truth's, classified as misclassified_pct "
                                     "counts it (per channel, the nearest of blocked, the truth's transmittance "
                                     "and unblocked); red + blue pixels over all but the dark grey ones = "
                                     "misclassified_pct")
                       : std::string("per pixel, the sun visibility the player applied against the ray-traced "
                                     "truth, classified as misclassified_pct counts it (lit when >= ") +
                             threshold + "); red + blue pixels over all but the dark grey ones = misclassified_pct";
    m.legend = {{colourName(kMapOutside), "not classified: no geometry, or a surface facing away from the sun"},
                {colourName(kShadowAgreeLit), "correct: lit in both"},
                {colourName(kShadowAgreeDark), "correct: shadowed in both"},
                {"rgb(v, 0, 0) red", "false lit (player lit, truth shadowed: a light leak)"},
                {"rgb(0, 0.35 v, v) blue", "false shadow (player shadowed, truth lit: acne, overdarkening)"},
                {"v", "64 + 191 * |clamp(player, 0, 1) - truth| (160..255 for a misclassified pixel; "
                      "the largest channel's with glass)"}};
    if (color) m.legend.insert(m.legend.begin() + 3, {colourName(kShadowAgreeGlass), "correct: through glass in both"});
    m.stats = {{"classified_pixels", double(classified)},
               {"false_lit_pixels", double(falseLit)},
               {"false_shadow_pixels", double(falseShadow)},
               {"misclassified_pct", classified ? 100.0 * double(falseLit + falseShadow) / double(classified) : 0.0}};
    return m;
}

ErrorMap irradianceErrorMap(const std::string& metric, const IrradianceQuality::Frame& frame) {
    const size_t pixels = size_t(frame.width) * frame.height;
    if (pixels == 0 || frame.player.size() != pixels || frame.truth.size() != pixels ||
        frame.standardError.size() != pixels)
        return {};
    ErrorMap m = blankErrorMap(metric, frame.width, frame.height);
    uint64_t measured = 0, clamped = 0;
    double sum = 0;
    for (size_t i = 0; i < pixels; ++i) {
        if (!reference::comparedPixel(frame.player[i], frame.truth[i], frame.standardError[i])) {
            putCapturedPixel(m, i, kMapOutside);
            continue;
        }
        const double diff = std::fabs(reference::luminance(frame.player[i]) - reference::luminance(frame.truth[i]));
        // No light in the truth at all (mean 0): any difference is drawn as the clamp.
        const double relative = frame.referenceMean > 0 ? diff / frame.referenceMean : diff > 0 ? 1.0 : 0.0;
        ++measured;
        sum += relative;
        clamped += relative >= 1.0;
        putCapturedPixel(m, i, rampColour(relative));
    }
    const std::string what = metric == "gi" ? "indirect (GI) irradiance" : "sky irradiance";
    m.encoding = "per pixel, |player - truth| of the " + what +
                 " (Rec. 709 luminance) over the frame's mean truth luminance, through the ramp";
    m.legend = {{colourName(kMapOutside), "not measured (no geometry)"},
                {"ramp", kRampName},
                {colourName(rampColour(0.0)), "no error"},
                {colourName(rampColour(0.5)), "50 % of the mean truth luminance"},
                {colourName(rampColour(1.0)), "100 % of the mean truth luminance or more"}};
    m.clamp = 1.0;
    m.clampMeaning = "relative error 1.0 = 100 % of the mean truth luminance";
    m.stats = {{"measured_pixels", double(measured)},
               {"reference_mean_luminance", frame.referenceMean},
               {"mean_relative_error_pct", measured ? 100.0 * sum / double(measured) : 0.0},
               {"clamped_pct", measured ? 100.0 * double(clamped) / double(measured) : 0.0}};
    return m;
}

Rgb8 divergingColour(double t) {
    if (!(std::fabs(t) <= 1.0)) t = std::isnan(t) ? 0.0 : (t > 0 ? 1.0 : -1.0);
    // White at 0, to (33, 102, 172) at -1 and (178, 24, 43) at +1 (ColorBrewer RdBu's ends).
    const Rgb8 end = t < 0 ? Rgb8{33, 102, 172} : Rgb8{178, 24, 43};
    const double f = std::fabs(t);
    return {toByte(255.0 + f * (end.r - 255.0)), toByte(255.0 + f * (end.g - 255.0)),
            toByte(255.0 + f * (end.b - 255.0))};
}

ErrorMap irradianceSideBySide(const std::string& metric, const IrradianceQuality::Frame& frame) {
    const size_t pixels = size_t(frame.width) * frame.height;
    if (pixels == 0 || frame.player.size() != pixels || frame.truth.size() != pixels ||
        frame.standardError.size() != pixels)
        return {};
    const uint32_t w = frame.width, h = frame.height;
    ErrorMap m = blankErrorMap(metric, 3 * w, h);
    m.file = "compare_" + metric + ".png";
    const double mean = frame.referenceMean > 0 ? frame.referenceMean : 1.0;
    auto at = [&](size_t i, uint32_t panel, Rgb8 c) {
        const size_t x = i % w, y = i / w;
        const size_t o = ((h - 1 - y) * size_t(3 * w) + panel * w + x) * 3;
        m.rgb[o] = c.r;
        m.rgb[o + 1] = c.g;
        m.rgb[o + 2] = c.b;
    };
    for (size_t i = 0; i < pixels; ++i) {
        if (!reference::comparedPixel(frame.player[i], frame.truth[i], frame.standardError[i])) {
            for (uint32_t panel = 0; panel < 3; ++panel) at(i, panel, kMapOutside);
            continue;
        }
        const double p = reference::luminance(frame.player[i]), t = reference::luminance(frame.truth[i]);
        at(i, 0, rampColour(p / (2.0 * mean)));
        at(i, 1, rampColour(t / (2.0 * mean)));
        at(i, 2, divergingColour((p - t) / mean));
    }
    const std::string what = metric == "gi" ? "indirect (GI) irradiance" : "sky irradiance";
    m.encoding = "three panels: the player's " + what + " | the truth's | (player - truth) / mean truth "
                 "(Rec. 709 luminance); the first two on one ramp from 0 to twice the mean truth";
    m.legend = {{colourName(kMapOutside), "not measured (no geometry)"},
                {"panels 1-2", kRampName + " (clamp = 2 x the frame's mean truth luminance)"},
                {colourName(divergingColour(-1.0)), "panel 3: player darker by the mean truth or more"},
                {colourName(divergingColour(0.0)), "panel 3: player = truth"},
                {colourName(divergingColour(1.0)), "panel 3: player brighter by the mean truth or more"}};
    m.clamp = 2.0;
    m.clampMeaning = "panels 1-2: 2 x the mean truth luminance; panel 3: +-1 x the mean truth luminance";
    m.stats = {{"reference_mean_luminance", frame.referenceMean}};
    return m;
}

} // namespace pnb::player
