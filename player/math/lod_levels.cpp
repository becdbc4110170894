// Level-of-detail chains of a mesh's submeshes (the pairing rule is in lod_levels.h).
#include "lod_levels.h"

#include <map>

namespace pnb::player {

std::vector<SubmeshChain> buildLevelChains(std::span<const Submesh> submeshes) {
    std::vector<SubmeshChain> chains;
    // Per material: its chains (indices into `chains`) and, per level, its submeshes in order.
    std::map<uint32_t, std::vector<size_t>> chainsOf;
    std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> byLevel; // (material, lod)
    for (uint32_t s = 0; s < submeshes.size(); ++s) {
        const Submesh& sm = submeshes[s];
        if (sm.material == kNone) continue;
        if (sm.lod == 0) {
            chainsOf[sm.material].push_back(chains.size());
            chains.push_back({sm.material, {s}});
        } else {
            byLevel[{sm.material, sm.lod}].push_back(s);
        }
    }
    for (const auto& [material, own] : chainsOf) {
        for (uint32_t level = 1; level <= 255; ++level) {
            auto it = byLevel.find({material, level});
            if (it == byLevel.end() || it->second.size() != own.size()) break;
            for (size_t j = 0; j < own.size(); ++j) chains[own[j]].levels.push_back(it->second[j]);
        }
    }
    return chains;
}

} // namespace pnb::player
