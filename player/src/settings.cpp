// The render-setting table: one row per key; parsing and printing are derived from the row.
#include "pnb_player/settings.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <variant>

namespace pnb::player {

namespace {

struct FloatField {
    float RenderSettings::*member;
    float min, max;
};
struct BoolField {
    bool RenderSettings::*member;
};
struct DebugViewField {};
using Field = std::variant<FloatField, BoolField, DebugViewField>;

struct Row {
    SettingInfo info;
    Field field;
};

constexpr std::string_view kDebugViewNames[] = {"none", "basecolor", "alpha", "normal",
                                                "roughness", "metallic", "occlusion", "emissive",
                                                "depth", "layer", "overdraw"};
static_assert(std::size(kDebugViewNames) == size_t(DebugView::Count));

const std::vector<Row>& rows() {
    static const std::vector<Row> table = {
        {{"lighting.exposure", "float > 0", "HDR scale applied before tone mapping"},
         FloatField{&RenderSettings::exposure, 1e-6f, 1e6f}},
        {{"lighting.ambient", "float >= 0",
          "uniform ambient radiance, multiplied by base colour and occlusion"},
         FloatField{&RenderSettings::ambient, 0.0f, 1e6f}},
        {{"post.fxaa", "bool", "FXAA edge anti-aliasing after tone mapping"},
         BoolField{&RenderSettings::fxaa}},
        {{"cull.frustum", "bool", "skip draws whose world bounds are outside the view frustum"},
         BoolField{&RenderSettings::frustumCulling}},
        {{"camera.near", "float >= 0", "near plane in scene units; 0 = the container camera's"},
         FloatField{&RenderSettings::nearPlane, 0.0f, 1e9f}},
        {{"camera.far", "float >= -1",
          "far plane in scene units; 0 = infinite (reversed-Z), -1 = the container camera's"},
         FloatField{&RenderSettings::farPlane, -1.0f, 1e30f}},
        {{"debug.view",
          "none|basecolor|alpha|normal|roughness|metallic|occlusion|emissive|depth|layer|overdraw",
          "show one buffer instead of the lit image"},
         DebugViewField{}},
    };
    return table;
}

const Row* findRow(std::string_view key) {
    for (const Row& r : rows())
        if (r.info.key == key) return &r;
    return nullptr;
}

PlayError usage(std::string_view key, std::string_view value, std::string_view expected) {
    return {PlayErrorKind::Usage, "setting " + std::string(key) + ": '" + std::string(value) +
                                      "' is not " + std::string(expected)};
}

std::string formatFloat(float f) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", double(f));
    return buf;
}

} // namespace

const std::vector<SettingInfo>& settingInfos() {
    static const std::vector<SettingInfo> infos = [] {
        std::vector<SettingInfo> v;
        for (const Row& r : rows()) v.push_back(r.info);
        return v;
    }();
    return infos;
}

std::string_view toString(DebugView view) { return kDebugViewNames[size_t(view)]; }

PlayResult<Done> applySetting(RenderSettings& settings, std::string_view key,
                              std::string_view value) {
    const Row* row = findRow(key);
    if (!row) {
        std::string known;
        for (const Row& r : rows()) known += (known.empty() ? "" : ", ") + std::string(r.info.key);
        return PlayError{PlayErrorKind::Usage,
                         "unknown setting '" + std::string(key) + "' (known: " + known + ")"};
    }
    if (const auto* f = std::get_if<FloatField>(&row->field)) {
        float v = 0;
        auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
        if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(v) ||
            v < f->min || v > f->max)
            return usage(key, value, row->info.type);
        settings.*(f->member) = v;
    } else if (const auto* b = std::get_if<BoolField>(&row->field)) {
        if (value == "1" || value == "true" || value == "on") settings.*(b->member) = true;
        else if (value == "0" || value == "false" || value == "off") settings.*(b->member) = false;
        else return usage(key, value, "a bool (1/0, true/false, on/off)");
    } else {
        size_t i = 0;
        while (i < size_t(DebugView::Count) && kDebugViewNames[i] != value) ++i;
        if (i == size_t(DebugView::Count)) return usage(key, value, row->info.type);
        settings.debugView = DebugView(i);
    }
    return Done{};
}

PlayResult<Done> applySetting(RenderSettings& settings, std::string_view assignment) {
    size_t eq = assignment.find('=');
    if (eq == std::string_view::npos || eq == 0)
        return PlayError{PlayErrorKind::Usage,
                         "--set expects key=value, got '" + std::string(assignment) + "'"};
    return applySetting(settings, assignment.substr(0, eq), assignment.substr(eq + 1));
}

std::string settingValue(const RenderSettings& settings, std::string_view key) {
    const Row* row = findRow(key);
    if (!row) return {};
    if (const auto* f = std::get_if<FloatField>(&row->field))
        return formatFloat(settings.*(f->member));
    if (const auto* b = std::get_if<BoolField>(&row->field))
        return settings.*(b->member) ? "true" : "false";
    return std::string(toString(settings.debugView));
}

std::vector<std::pair<std::string, std::string>> settingValues(const RenderSettings& settings) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const Row& r : rows())
        out.emplace_back(std::string(r.info.key), settingValue(settings, r.info.key));
    return out;
}

PlayResult<RenderSettings> resolveSettings(
    const std::vector<std::pair<std::string, std::string>>& containerSettings,
    const std::vector<std::string>& commandLine, std::vector<std::string>* warnings) {
    RenderSettings s;
    for (const auto& [key, value] : containerSettings) {
        auto r = applySetting(s, key, value);
        if (!r && warnings) warnings->push_back("container setting ignored: " + r.error().message);
    }
    for (const std::string& assignment : commandLine)
        if (auto r = applySetting(s, assignment); !r) return r.error();
    return s;
}

} // namespace pnb::player
