// Per-frame level-of-detail choice for every item with levels (rule: player/math/lod_select.h;
// which passes use it and why: frame_context.h LodState).
#include <algorithm>
#include <array>

#include "frame/frame_context.h"
#include "lod_select.h"

namespace pnb::player {

void selectLevels(const GpuScene& scene, const ViewMatrices& view, uint32_t viewportHeight,
                  const RenderSettings& settings, LodState& lod, FrameStats& stats) {
    if (scene.lodItems.empty()) return; // a scene without LODs: nothing to choose
    if (lod.selected.size() != scene.items.size()) {
        lod.selected.assign(scene.items.size(), 0);
        lod.drawn.assign(scene.items.size(), 0);
    }
    const LodRule rule{settings.lodThresholdPx, settings.lodHysteresis};
    const double pixelScale = view.orthographic ? lodPixelScaleOrthographic(double(view.ymag), viewportHeight)
                                                : lodPixelScale(double(view.yfov), viewportHeight);
    const bool forced = settings.lodForce >= 0;
    std::array<float, 256> errors{};
    uint32_t switches = 0;
    for (uint32_t i : scene.lodItems) {
        const DrawItem& item = scene.items[i];
        const uint32_t count = std::min(item.levelCount, 256u);
        uint32_t selected = lod.selected[i];
        if (!forced) {
            for (uint32_t l = 0; l < count; ++l) errors[l] = scene.levels[item.firstLevel + l].error;
            const double distance = lodDistance(view.orthographic, view.position, item.boundsMin, item.boundsMax);
            selected = selectLod(std::span(errors.data(), count), item.worldScale, distance, pixelScale, rule,
                                 selected);
            lod.selected[i] = uint8_t(selected);
        }
        const uint8_t drawn = uint8_t(applyLodOverrides(selected, count, settings.lodBias, settings.lodForce));
        switches += drawn != lod.drawn[i];
        lod.drawn[i] = drawn;
    }
    stats.lodSwitches = switches;
}

} // namespace pnb::player
