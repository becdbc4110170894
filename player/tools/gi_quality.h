// gi_quality.h — pnb-play's --gi-metrics: each measured frame's indirect irradiance (the GI's
// CaptureBuffer::Indirect) compared with the ray-traced one-bounce truth (pnb_reference's
// IndirectTracer) at the exact pixels the player drew; on the frame after it, flicker: how much
// the player's indirect light changed in 1/60 s of camera motion (the truth barely does).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "pnb_player/renderer.h"
#include "pnb_reference/indirect_tracer.h"

namespace pnb::player {

class GiQuality {
public:
    static PlayResult<std::unique_ptr<GiQuality>> create(const std::string& containerPath, glm::dvec3 origin,
                                                         const reference::IndirectSettings& settings);
    ~GiQuality();

    PlayResult<std::vector<std::pair<std::string, double>>> measure(Renderer& renderer, bool followUp);

private:
    GiQuality() = default;
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

} // namespace pnb::player
