// truth_judges.h — the truth metrics pnb-judge plugs into the player's command line
// (player/tools/play_app.h): the shadow, GI and sky comparisons with the Embree ray tracer
// (shadow_quality.h, irradiance_quality.h) behind the player's TruthJudge interface.
#pragma once

#include <memory>

#include "play_app.h"

namespace pnb::player {

// A judge of `metric` for `request`'s container (loads its geometry into the tracer).
PlayResult<std::unique_ptr<TruthJudge>> makeTruthJudge(TruthMetric metric, const TruthRequest& request);

} // namespace pnb::player
