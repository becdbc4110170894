#include "texture_residency.h"

#include <algorithm>
#include <numeric>

namespace pnb::player {

uint64_t TextureResidency::bytesFrom(uint32_t level) const {
    uint64_t sum = 0;
    for (uint32_t l = level; l < mipCount(); ++l) sum += levelBytes[l];
    return sum;
}

uint64_t residentBytes(std::span<const TextureResidency> textures) {
    uint64_t sum = 0;
    for (const TextureResidency& t : textures) sum += t.bytesFrom(t.allocated);
    return sum;
}

uint64_t neededBytes(std::span<const TextureResidency> textures) {
    uint64_t sum = 0;
    for (const TextureResidency& t : textures) sum += t.bytesFrom(std::min(t.wanted, t.mipCount() - 1));
    return sum;
}

ResidencyPlan planResidency(std::span<TextureResidency> textures, uint64_t budget, uint64_t frame,
                            uint64_t maxGrowth) {
    ResidencyPlan plan;
    uint64_t grown = 0; // storage added this frame
    const uint64_t growthLimit = maxGrowth ? maxGrowth : UINT64_MAX;
    const uint64_t limit = budget ? budget : UINT64_MAX;
    std::vector<uint32_t> allocated(textures.size());
    for (size_t i = 0; i < textures.size(); ++i) {
        TextureResidency& t = textures[i];
        if (t.mipCount() > 0) t.wanted = std::min(t.wanted, t.mipCount() - 1);
        if (t.wanted <= t.allocated) t.lastNeededFrame = frame;
        allocated[i] = t.allocated;
    }
    uint64_t resident = 0;
    for (size_t i = 0; i < textures.size(); ++i) resident += textures[i].bytesFrom(allocated[i]);
    plan.peakBytes = resident;

    // Victims: chains longer than wanted, least recently needed first (then larger first).
    std::vector<uint32_t> victims;
    for (uint32_t i = 0; i < textures.size(); ++i)
        if (textures[i].mipCount() > 0 && allocated[i] < textures[i].wanted) victims.push_back(i);
    std::sort(victims.begin(), victims.end(), [&](uint32_t a, uint32_t b) {
        if (textures[a].lastNeededFrame != textures[b].lastNeededFrame)
            return textures[a].lastNeededFrame < textures[b].lastNeededFrame;
        return a < b;
    });
    size_t nextVictim = 0;
    // Cuts `i` back to its wanted level: the new, shorter chain exists beside the old one during
    // the copy.
    auto evict = [&](uint32_t i) {
        const TextureResidency& t = textures[i];
        const uint64_t before = t.bytesFrom(allocated[i]), after = t.bytesFrom(t.wanted);
        // (Over the budget already, when it was lowered: cutting back is the only way down.)
        if (resident + after > limit && resident <= limit) return false;
        plan.peakBytes = std::max(plan.peakBytes, resident + after);
        resident = resident - before + after;
        allocated[i] = t.wanted;
        plan.evictions.push_back({i, t.wanted});
        return true;
    };
    // Over budget already (the budget was lowered): cut back until under it.
    while (resident > limit && nextVictim < victims.size()) evict(victims[nextVictim++]);

    std::vector<uint32_t> growers;
    for (uint32_t i = 0; i < textures.size(); ++i)
        if (textures[i].mipCount() > 0 && textures[i].wanted < allocated[i]) growers.push_back(i);
    std::stable_sort(growers.begin(), growers.end(), [&](uint32_t a, uint32_t b) {
        return allocated[a] - textures[a].wanted > allocated[b] - textures[b].wanted;
    });
    bool allMet = true;
    auto grow = [&](uint32_t i, uint32_t target) {
        const TextureResidency& t = textures[i];
        const uint64_t before = t.bytesFrom(allocated[i]), after = t.bytesFrom(target);
        grown += after - before;
        plan.peakBytes = std::max(plan.peakBytes, resident + after);
        resident = resident - before + after;
        allocated[i] = target;
        plan.growths.push_back({i, target});
    };
    // Within this frame's allowance; or the frame's first growth, by one level (progress even
    // when one level is larger than the allowance).
    auto mayGrow = [&](uint32_t i, uint32_t target) {
        const uint64_t added = textures[i].bytesFrom(target) - textures[i].bytesFrom(allocated[i]);
        return grown + added <= growthLimit || (grown == 0 && target + 1 == allocated[i]);
    };
    for (uint32_t i : growers) {
        const TextureResidency& t = textures[i];
        // All the way to the wanted level if it fits, else as far as it does (one level at least).
        bool done = false;
        for (uint32_t target = t.wanted; target < allocated[i] && !done; ++target) {
            if (!mayGrow(i, target)) continue; // this frame's new storage is spent: less
            while (resident + t.bytesFrom(target) > limit && nextVictim < victims.size())
                if (uint32_t v = victims[nextVictim++]; v != i) evict(v);
            if (resident + t.bytesFrom(target) > limit) continue; // try a shorter growth
            allMet &= target == t.wanted;
            grow(i, target);
            done = true;
        }
        allMet &= done;
    }
    // Room left once every need is met: one level more for the textures whose need is nearest
    // to their chain (the next to be needed), so that a budget the scene fits in ends with all
    // of it resident. These levels are the first given up when a need wants the room.
    if (allMet && budget) {
        std::vector<uint32_t> spare;
        for (uint32_t i = 0; i < textures.size(); ++i)
            if (allocated[i] > 0 && allocated[i] < textures[i].mipCount()) spare.push_back(i);
        std::stable_sort(spare.begin(), spare.end(), [&](uint32_t a, uint32_t b) {
            return int64_t(allocated[a]) - textures[a].wanted > int64_t(allocated[b]) - textures[b].wanted;
        });
        for (uint32_t i : spare)
            if (resident + textures[i].bytesFrom(allocated[i] - 1) <= limit && mayGrow(i, allocated[i] - 1))
                grow(i, allocated[i] - 1);
    }
    return plan;
}

} // namespace pnb::player
