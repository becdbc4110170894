// pnb-play --error-maps: the metrics' last measured frame as heat-maps (error_maps.h).
#include "error_maps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "pnb_player/image_write.h"
#include "pnb_reference/indirect_metrics.h"
#include "pnb_reference/shadow_metrics.h"

namespace pnb::player {

namespace {

// matplotlib's magma at t = 0, 1/8, ..., 1.
constexpr Rgb8 kMagma[9] = {{0, 0, 4},       {28, 16, 68},    {79, 18, 123},   {129, 37, 129}, {181, 54, 122},
                            {229, 80, 100},  {251, 135, 97},  {254, 194, 135}, {252, 253, 191}};

uint8_t toByte(double v) { return uint8_t(std::clamp(std::lround(v), 0l, 255l)); }

std::string colourName(Rgb8 c) {
    char s[32];
    std::snprintf(s, sizeof s, "rgb(%u, %u, %u)", unsigned(c.r), unsigned(c.g), unsigned(c.b));
    return s;
}

// A black map of `metric`, filled by put().
ErrorMap blank(const std::string& metric, uint32_t width, uint32_t height) {
    ErrorMap m;
    m.metric = metric;
    m.file = "error_" + metric + ".png";
    m.width = width;
    m.height = height;
    m.rgb.assign(size_t(width) * height * 3, 0);
    return m;
}

// Captured pixel i (rows bottom-up) into the map (rows top-down).
void put(ErrorMap& m, size_t i, Rgb8 c) {
    const size_t x = i % m.width, y = i / m.width;
    const size_t o = ((m.height - 1 - y) * m.width + x) * 3;
    m.rgb[o] = c.r;
    m.rgb[o + 1] = c.g;
    m.rgb[o + 2] = c.b;
}

const std::string kRampName = "magma (9 stops, linear between): black-purple = 0, pale yellow = clamp or more";

} // namespace

Rgb8 rampColour(double t) {
    if (!(t > 0)) return kMagma[0];
    if (t >= 1) return kMagma[8];
    const double s = t * 8.0;
    const int i = std::min(int(s), 7);
    const double f = s - i;
    const Rgb8 a = kMagma[i], b = kMagma[i + 1];
    return {toByte(a.r + f * (b.r - a.r)), toByte(a.g + f * (b.g - a.g)), toByte(a.b + f * (b.b - a.b))};
}

Rgb8 falseLitColour(double absError) {
    const uint8_t v = toByte(64.0 + 191.0 * std::min(absError, 1.0));
    return {v, 0, 0};
}

Rgb8 falseShadowColour(double absError) {
    const uint8_t v = toByte(64.0 + 191.0 * std::min(absError, 1.0));
    return {0, toByte(0.35 * v), v};
}

ErrorMap shadowErrorMap(const ShadowQuality::Frame& frame) {
    const size_t pixels = size_t(frame.width) * frame.height;
    if (pixels == 0 || frame.player.size() != pixels || frame.truth.size() != pixels) return {};
    ErrorMap m = blank("shadow", frame.width, frame.height);
    uint64_t classified = 0, falseLit = 0, falseShadow = 0;
    for (size_t i = 0; i < pixels; ++i) {
        const float p = frame.player[i], t = frame.truth[i];
        const double d = std::fabs(std::clamp(double(p), 0.0, 1.0) - double(t));
        const reference::ShadowClass k = reference::classifyShadow(p, t);
        Rgb8 c = kMapOutside;
        switch (k) {
        case reference::ShadowClass::Unclassified: break;
        case reference::ShadowClass::AgreeLit: c = kShadowAgreeLit; break;
        case reference::ShadowClass::AgreeShadow: c = kShadowAgreeDark; break;
        case reference::ShadowClass::FalseLit:
            c = falseLitColour(d);
            ++falseLit;
            break;
        case reference::ShadowClass::FalseShadow:
            c = falseShadowColour(d);
            ++falseShadow;
            break;
        }
        classified += k != reference::ShadowClass::Unclassified;
        put(m, i, c);
    }
    char threshold[16];
    std::snprintf(threshold, sizeof threshold, "%g", double(reference::kLitThreshold));
    m.encoding = std::string("per pixel, the sun visibility the player applied against the ray-traced truth, "
                             "classified as misclassified_pct counts it (lit when >= ") + threshold +
                 "); red + blue pixels over all but the dark grey ones = misclassified_pct";
    m.legend = {{colourName(kMapOutside), "not classified: no geometry, or a surface facing away from the sun"},
                {colourName(kShadowAgreeLit), "correct: lit in both"},
                {colourName(kShadowAgreeDark), "correct: shadowed in both"},
                {"rgb(v, 0, 0) red", "false lit (player lit, truth shadowed: a light leak)"},
                {"rgb(0, 0.35 v, v) blue", "false shadow (player shadowed, truth lit: acne, overdarkening)"},
                {"v", "64 + 191 * |clamp(player, 0, 1) - truth| (160..255 for a misclassified pixel)"}};
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
    ErrorMap m = blank(metric, frame.width, frame.height);
    uint64_t measured = 0, clamped = 0;
    double sum = 0;
    for (size_t i = 0; i < pixels; ++i) {
        if (!reference::comparedPixel(frame.player[i], frame.truth[i], frame.standardError[i])) {
            put(m, i, kMapOutside);
            continue;
        }
        const double diff = std::fabs(reference::luminance(frame.player[i]) - reference::luminance(frame.truth[i]));
        // No light in the truth at all (mean 0): any difference is drawn as the clamp.
        const double relative = frame.referenceMean > 0 ? diff / frame.referenceMean : diff > 0 ? 1.0 : 0.0;
        ++measured;
        sum += relative;
        clamped += relative >= 1.0;
        put(m, i, rampColour(relative));
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
    ErrorMap m = blank(metric, 3 * w, h);
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

ErrorMap lodErrorMap(const LodFrame& frame) {
    const size_t pixels = size_t(frame.width) * frame.height;
    if (pixels == 0 || frame.worst.size() != pixels) return {};
    ErrorMap m = blank("lod", frame.width, frame.height);
    uint64_t over = 0;
    for (size_t i = 0; i < pixels; ++i) {
        over += frame.worst[i] > 8;
        put(m, i, rampColour(double(frame.worst[i]) / 32.0));
    }
    m.encoding = "per pixel, the largest |LOD image - full-detail image| over R, G, B in 8-bit units, through "
                 "the ramp (lod_pixels_over8_pct counts values > 8, from a quarter of the ramp up)";
    m.legend = {{"ramp", kRampName},
                {colourName(rampColour(0.0)), "identical"},
                {colourName(rampColour(8.0 / 32.0)), "8/255 (the metric counts pixels above this)"},
                {colourName(rampColour(1.0)), "32/255 or more"}};
    m.clamp = 32.0 / 255.0;
    m.clampMeaning = "32/255 (difference of 32 in 8-bit units)";
    m.stats = {{"pixels", double(pixels)},
               {"pixels_over8_pct", 100.0 * double(over) / double(pixels)}};
    return m;
}

PlayResult<std::vector<std::string>> writeErrorMaps(const std::string& outDir, uint32_t frame,
                                                    const std::vector<ErrorMap>& maps) {
    std::vector<std::string> written;
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const ErrorMap& m : maps) {
        if (m.width == 0) continue;
        const std::string path = outDir + "/" + m.file;
        ImageView view{m.width, m.height, 3, m.rgb, {}};
        if (Status s = writePng(path, view); !isOk(s)) return PlayError{PlayErrorKind::Io, s.describe()};
        written.push_back(path);
        nlohmann::ordered_json j;
        j["metric"] = m.metric;
        j["file"] = m.file;
        j["frame"] = frame;
        j["width"] = m.width;
        j["height"] = m.height;
        j["encoding"] = m.encoding;
        nlohmann::ordered_json legend = nlohmann::ordered_json::array();
        for (const auto& [colour, meaning] : m.legend) legend.push_back({{"colour", colour}, {"meaning", meaning}});
        j["legend"] = legend;
        if (m.clamp > 0) {
            j["clamp"] = m.clamp;
            j["clamp_meaning"] = m.clampMeaning;
        }
        nlohmann::ordered_json stats = nlohmann::ordered_json::object();
        for (const auto& [name, value] : m.stats) stats[name] = value;
        j["stats"] = stats;
        list.push_back(j);
    }
    nlohmann::ordered_json doc;
    doc["frame"] = frame;
    doc["note"] = "each map shows the last measured frame of its metric (quality.csv's row 'frame'), not the "
                  "follow-up frame 1/60 s later; rows top-down like --screenshot";
    doc["maps"] = list;
    const std::string text = doc.dump(2) + "\n";
    const std::string jsonPath = outDir + "/error_maps.json";
    if (Status s = writeFileAtomic(jsonPath, {reinterpret_cast<const uint8_t*>(text.data()), text.size()}); !isOk(s))
        return PlayError{PlayErrorKind::Io, s.describe()};
    written.push_back(jsonPath);
    return written;
}

} // namespace pnb::player
