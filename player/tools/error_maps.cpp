// pnb-play --error-maps: the metrics' last measured frame as heat-maps (error_maps.h).
#include "error_maps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "pnb_player/image_write.h"

namespace pnb::player {

namespace {

// matplotlib's magma at t = 0, 1/8, ..., 1.
constexpr Rgb8 kMagma[9] = {{0, 0, 4},       {28, 16, 68},    {79, 18, 123},   {129, 37, 129}, {181, 54, 122},
                            {229, 80, 100},  {251, 135, 97},  {254, 194, 135}, {252, 253, 191}};

} // namespace

uint8_t toByte(double v) { return uint8_t(std::clamp(std::lround(v), 0l, 255l)); }

std::string colourName(Rgb8 c) {
    char s[32];
    std::snprintf(s, sizeof s, "rgb(%u, %u, %u)", unsigned(c.r), unsigned(c.g), unsigned(c.b));
    return s;
}

ErrorMap blankErrorMap(const std::string& metric, uint32_t width, uint32_t height) {
    ErrorMap m;
    m.metric = metric;
    m.file = "error_" + metric + ".png";
    m.width = width;
    m.height = height;
    m.rgb.assign(size_t(width) * height * 3, 0);
    return m;
}

void putCapturedPixel(ErrorMap& m, size_t i, Rgb8 c) {
    const size_t x = i % m.width, y = i / m.width;
    const size_t o = ((m.height - 1 - y) * m.width + x) * 3;
    m.rgb[o] = c.r;
    m.rgb[o + 1] = c.g;
    m.rgb[o + 2] = c.b;
}

const std::string kRampName = "magma (9 stops, linear between): black-purple = 0, pale yellow = clamp or more";

Rgb8 rampColour(double t) {
    if (!(t > 0)) return kMagma[0];
    if (t >= 1) return kMagma[8];
    const double s = t * 8.0;
    const int i = std::min(int(s), 7);
    const double f = s - i;
    const Rgb8 a = kMagma[i], b = kMagma[i + 1];
    return {toByte(a.r + f * (b.r - a.r)), toByte(a.g + f * (b.g - a.g)), toByte(a.b + f * (b.b - a.b))};
}

ErrorMap lodErrorMap(const LodFrame& frame) {
    const size_t pixels = size_t(frame.width) * frame.height;
    if (pixels == 0 || frame.worst.size() != pixels) return {};
    ErrorMap m = blankErrorMap("lod", frame.width, frame.height);
    uint64_t over = 0;
    for (size_t i = 0; i < pixels; ++i) {
        over += frame.worst[i] > 8;
        putCapturedPixel(m, i, rampColour(double(frame.worst[i]) / 32.0));
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
