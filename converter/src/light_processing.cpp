// The lights as the container gets them: ranges, shadows, domains, the kMaxLights cap
// (pnb_converter/light_processing.h).
#include "pnb_converter/light_processing.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <numeric>

namespace pnb::converter {

namespace {

std::string strf(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string strf(const char* fmt, ...) {
    char buf[256];
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(buf, sizeof(buf), fmt, args);
    va_end(args);
    return buf;
}

// "light 'lamp-3'", or for an unnamed light "light 12 (unnamed, node 'Lamp')": the IR index
// alone would not find it in the source, its node's name usually does.
std::string lightLabel(const IrScene& scene, const std::vector<int>& nodeOf, size_t i) {
    const std::string& name = scene.lights[i].name;
    if (!name.empty()) return "light '" + name + "'";
    std::string label = "light " + std::to_string(i) + " (unnamed";
    if (nodeOf[i] >= 0 && !scene.nodes[size_t(nodeOf[i])].name.empty())
        label += ", node '" + scene.nodes[size_t(nodeOf[i])].name + "'";
    return label + ")";
}

// One kind of finding about lights, reported one line per light up to kLightWarningsOneByOne,
// else as one summary line.
struct Finding {
    struct Item {
        size_t light;
        float range; // the range written (0 for dark lights)
        std::string detail; // this light's own part of a one-by-one line
    };
    std::vector<Item> items;

    // The summary line: "lights: N <what><rangeLead> lo (light) to hi (light); the first: ...",
    // the range part only when rangeLead is not empty.
    void report(const IrScene& scene, const std::vector<int>& nodeOf, const std::string& what,
                const std::string& rangeLead, std::vector<std::string>& warnings) const {
        if (items.empty()) return;
        if (items.size() <= kLightWarningsOneByOne) {
            for (const Item& it : items)
                warnings.push_back(lightLabel(scene, nodeOf, it.light) + ": " + it.detail);
            return;
        }
        std::string line = "lights: " + std::to_string(items.size()) + " " + what;
        if (!rangeLead.empty()) {
            auto [lo, hi] = std::minmax_element(items.begin(), items.end(), [](const Item& a, const Item& b) {
                return a.range < b.range;
            });
            line += rangeLead + strf(" %.3g", double(lo->range)) + " (" + lightLabel(scene, nodeOf, lo->light) +
                    ") to" + strf(" %.3g", double(hi->range)) + " (" + lightLabel(scene, nodeOf, hi->light) + ")";
        }
        line += "; the first:";
        for (size_t k = 0; k < 3; ++k)
            line += std::string(k ? ", " : " ") + lightLabel(scene, nodeOf, items[k].light);
        warnings.push_back(line);
    }
};

bool finiteNonNegative(float v) { return std::isfinite(v) && v >= 0; }

} // namespace

void processLights(IrScene& scene, std::vector<bool>& generated, const LightSettings& settings,
                   std::vector<std::string>& warnings) {
    std::vector<IrLight>& lights = scene.lights;
    generated.resize(lights.size(), false);
    std::vector<int> nodeOf(lights.size(), -1); // the first node placing each light, for labels
    for (size_t n = 0; n < scene.nodes.size(); ++n) {
        const int l = scene.nodes[n].light;
        if (l >= 0 && size_t(l) < lights.size() && nodeOf[size_t(l)] < 0) nodeOf[size_t(l)] = int(n);
    }
    const float cutoff = settings.cutoffLux;
    const std::string cutoffText = strf("%g lux", double(cutoff));
    Finding noRange, badRange, dark;

    for (size_t i = 0; i < lights.size(); ++i) {
        IrLight& l = lights[i];
        // Domains the reader enforces, for whatever an importer let through.
        if (!finiteNonNegative(l.intensity)) {
            warnings.push_back(lightLabel(scene, nodeOf, i) + strf(": intensity %g is not a finite "
                                                                   "number >= 0; 0 (no light)",
                                                                   double(l.intensity)));
            l.intensity = 0;
        }
        if (!finiteNonNegative(l.color.x) || !finiteNonNegative(l.color.y) || !finiteNonNegative(l.color.z)) {
            warnings.push_back(lightLabel(scene, nodeOf, i) +
                               ": a colour channel is not a finite number >= 0; set to 0");
            for (float* c : {&l.color.x, &l.color.y, &l.color.z})
                if (!finiteNonNegative(*c)) *c = 0;
        }
        // The reader's bound on the light a light gives (kMaxLightOutput): beyond it the
        // renderer's sums overflow. The intensity is lowered to the bound, the colour kept.
        if (const double brightest = std::max({double(l.color.x), double(l.color.y), double(l.color.z)});
            double(l.intensity) * brightest > double(kMaxLightOutput)) {
            const float clamped = float(double(kMaxLightOutput) / brightest);
            warnings.push_back(lightLabel(scene, nodeOf, i) +
                               strf(": intensity %g x brightest colour channel %g exceeds %g, the "
                                    "most a light may give; intensity lowered to %g",
                                    double(l.intensity), brightest, double(kMaxLightOutput),
                                    double(clamped)));
            l.intensity = clamped;
        }
        if (l.type == LightType::Spot) {
            const float outer = std::isnan(l.outerConeRadians)
                                    ? 0.7853982f
                                    : std::clamp(l.outerConeRadians, 0.0f, kMaxSpotConeRadians);
            const float inner = std::isnan(l.innerConeRadians) ? 0.0f : std::clamp(l.innerConeRadians, 0.0f, outer);
            if (!(inner == l.innerConeRadians && outer == l.outerConeRadians)) {
                warnings.push_back(lightLabel(scene, nodeOf, i) +
                                   strf(": spot cone angles (inner %g, outer %g) outside 0 <= inner "
                                        "<= outer <= pi/2; clamped to inner %g, outer %g",
                                        double(l.innerConeRadians), double(l.outerConeRadians),
                                        double(inner), double(outer)));
                l.innerConeRadians = inner;
                l.outerConeRadians = outer;
            }
        }

        if (l.type == LightType::Directional) {
            l.range = 0;
            l.castsShadows = true;
            continue;
        }
        Light probe;
        probe.type = l.type;
        probe.color = l.color;
        probe.intensity = l.intensity;
        const float computed = lightCutoffRange(probe, cutoff);
        if (computed == 0) { // gives no light: reaches nothing, shadows nothing
            dark.items.push_back({i, 0, "gives no light (intensity 0 or a black colour); written "
                                        "with range 0, renderers skip it"});
            l.range = 0;
            l.castsShadows = false;
            continue;
        }
        l.castsShadows = true;
        if (l.range > 0 && std::isfinite(l.range)) continue; // the source's own
        if (l.range == 0) {
            noRange.items.push_back({i, computed,
                                     strf("no range in the source; computed %.3g", double(computed)) +
                                         ", where its illuminance falls to " + cutoffText +
                                         " (--light-cutoff)"});
        } else {
            badRange.items.push_back({i, computed,
                                      strf("range %g is not a positive finite number; replaced by %.3g",
                                           double(l.range), double(computed)) + ", where its illuminance falls to " +
                                          cutoffText + " (--light-cutoff)"});
        }
        l.range = computed;
    }
    const std::string where = "where their illuminance falls to " + cutoffText + " (--light-cutoff)";
    noRange.report(scene, nodeOf, "point/spot lights have no range in the source; computed " + where,
                   ":", warnings);
    badRange.report(scene, nodeOf,
                    "point/spot lights have a negative, NaN or infinite range; replaced by " + where,
                    ":", warnings);
    dark.report(scene, nodeOf,
                "point/spot lights give no light (intensity 0 or a black colour); written with "
                "range 0, renderers skip them",
                "", warnings);

    if (lights.size() <= kMaxLights) return;

    // [SECTION] the cap: keep the kMaxLights that light the most (header), in source order.
    std::vector<double> score(lights.size());
    for (size_t i = 0; i < lights.size(); ++i) {
        const IrLight& l = lights[i];
        const double brightest = std::max({l.color.x, l.color.y, l.color.z});
        score[i] = l.type == LightType::Directional ? std::numeric_limits<double>::infinity()
                                                    : double(l.range) * double(l.intensity) * brightest;
    }
    std::vector<size_t> order(lights.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::nth_element(order.begin(), order.begin() + kMaxLights, order.end(), [&](size_t a, size_t b) {
        return score[a] != score[b] ? score[a] > score[b] : a < b;
    });
    std::vector<bool> keep(lights.size(), false);
    for (size_t k = 0; k < kMaxLights; ++k) keep[order[k]] = true;
    std::vector<int> remap(lights.size(), -1);
    std::vector<IrLight> kept;
    std::vector<bool> keptGenerated;
    std::vector<size_t> dropped;
    kept.reserve(kMaxLights);
    keptGenerated.reserve(kMaxLights);
    for (size_t i = 0; i < lights.size(); ++i) {
        if (!keep[i]) {
            dropped.push_back(i);
            continue;
        }
        remap[i] = int(kept.size());
        kept.push_back(std::move(lights[i]));
        keptGenerated.push_back(generated[i]);
    }
    std::string line = "lights: " + std::to_string(lights.size()) + " lights, more than a container "
                       "holds (kMaxLights " + std::to_string(kMaxLights) + "): kept the " +
                       std::to_string(kMaxLights) + " that light the most (directional lights "
                       "first, then by range x intensity x brightest colour channel) and dropped " +
                       std::to_string(dropped.size()) + ", their nodes kept without a light; the first dropped:";
    // The dropped lights were not moved from: their labels still read them.
    for (size_t k = 0; k < std::min<size_t>(3, dropped.size()); ++k)
        line += std::string(k ? ", " : " ") + lightLabel(scene, nodeOf, dropped[k]);
    warnings.push_back(line);
    lights = std::move(kept);
    generated = std::move(keptGenerated);
    for (IrNode& n : scene.nodes)
        if (n.light >= 0) n.light = size_t(n.light) < remap.size() ? remap[size_t(n.light)] : -1;
}

} // namespace pnb::converter
