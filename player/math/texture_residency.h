// player/math/texture_residency.h — which texture levels stay resident under a memory budget
// (pure CPU, no GL): the streaming player's bookkeeping and its plan for one frame.
//
// A texture holds storage for a contiguous chain of levels `allocated`..mipCount-1 (a GL texture
// cannot have holes), of which `valid`..mipCount-1 hold texels (valid >= allocated; levels
// arrive coarse to fine). Growing the chain or cutting it back means new storage and a GPU copy
// of the levels kept, so for that moment both exist: the plan counts that peak, and never lets
// it exceed the budget. The coarsest level is never given up (the first frame drew with it).
//
// Each frame: the textures that want finer levels than they hold, most levels short first, get
// storage down to the level they want if it fits; to make room, textures holding levels finer
// than they want give those up, least recently needed first. What does not fit waits (the image
// stays coarser there: the overlay shows needed > resident). When every need is met and room is
// left, textures take one level more than they need (nearest to being needed first): the
// budget works as a cache, and a scene that fits in it ends up wholly resident.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace pnb::player {

struct TextureResidency {
    std::vector<uint64_t> levelBytes; // per level, level 0 first (mipCount entries)
    uint32_t allocated = 0;           // finest level with storage (mipCount: none)
    uint32_t valid = 0;               // finest level with texels, >= allocated (mipCount: none)
    uint32_t wanted = 0;              // finest level the view needs (this frame's estimate)
    uint64_t lastNeededFrame = 0;     // last frame `wanted` was <= `allocated`

    uint32_t mipCount() const { return uint32_t(levelBytes.size()); }
    uint64_t bytesFrom(uint32_t level) const; // levels level..mipCount-1
};

struct ResidencyChange {
    uint32_t texture = 0;
    uint32_t allocated = 0; // the new finest level with storage
};

struct ResidencyPlan {
    std::vector<ResidencyChange> evictions; // applied first, in order
    std::vector<ResidencyChange> growths;   // then these
    uint64_t peakBytes = 0;                 // the most storage alive at once while applying
};

// The plan for this frame. `budget` 0: no limit (every wanted level gets storage). `maxGrowth`
// (0: no limit) bounds the storage added this frame — new storage is only worth what the frame's
// uploads can fill, and creating it costs frame time — though a frame always grows one chain by
// one level at least. Updates lastNeededFrame from `wanted`. Does not change `allocated` (the caller
// applies the plan); residentBytes() after it is at most `budget` if it was before.
ResidencyPlan planResidency(std::span<TextureResidency> textures, uint64_t budget, uint64_t frame,
                            uint64_t maxGrowth = 0);

uint64_t residentBytes(std::span<const TextureResidency> textures); // storage of every chain
uint64_t neededBytes(std::span<const TextureResidency> textures);   // storage of the wanted chains

} // namespace pnb::player
