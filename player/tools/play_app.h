// play_app.h — the command line of pnb-play, as a function both players run: pnb-play (lean: the
// renderer, its window and benchmark, the level-of-detail metric) and pnb-judge (the same, plus the
// metrics that compare a frame with the Embree ray-traced truth). pnb-play passes no truth, so it
// never links the ray tracer; the options that need one then name pnb-judge (docs/ARCHITECTURE.md).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "error_maps.h"
#include "pnb_player/renderer.h"

namespace pnb::player {

// What the truth metrics compare.
enum class TruthMetric {
    Shadow, // --shadow-metrics: the sun's (or shadows.judged_light's) visibility
    Gi,     // --gi-metrics: one bounce of indirect light
    Sky,    // --sky-metrics: the sky's irradiance with its visibility
    Frame,  // --frame-metrics: the whole HDR frame against its path-traced truth
};

// Everything a truth needs from the command line and the loaded scene.
struct TruthRequest {
    std::string scene;            // the container's path (the truth reads it itself)
    glm::dvec3 origin{0.0};       // near the camera path: the tracer works relative to it
    int judgedLight = -1;         // shadows.judged_light (-1: the sun)
    glm::vec3 towardSun{0, 1, 0}; // unit, toward the shadowing sun
    uint32_t giSamples = 64;      // --gi-samples
    bool giAllLights = false;     // --gi-lights all
    uint32_t giBounces = 1;       // --gi-bounces (0: converged)
    uint32_t skySamples = 64;     // --sky-samples
    bool skyFromSh = false;       // --sky-source sh
    // --frame-metrics' truth: traced from frameTruthScene (default: scene), kept in
    // frameTruthCache (empty: none)
    std::string frameTruthScene, frameTruthCache;
    uint32_t frameBounces = 16, frameMaxSamples = 4096;
    double frameNoise = 0.003, frameTimeLimit = 120;
};

// One metric's judge: measures replayed frames (BenchOptions::quality) and draws the last one.
class TruthJudge {
public:
    virtual ~TruthJudge() = default;
    // After renderer.render() of a measured frame (followUp: the frame 1/60 s after it).
    virtual PlayResult<std::vector<std::pair<std::string, double>>> measure(Renderer& renderer, bool followUp) = 0;
    // --error-maps of the last measured frame (not its follow-up), in the order they are written.
    virtual std::vector<ErrorMap> errorMaps() const = 0;
};

using TruthFactory = std::function<PlayResult<std::unique_ptr<TruthJudge>>(TruthMetric, const TruthRequest&)>;

// Runs the player's command line. `program` names it in messages and usage; `truth` is empty in
// pnb-play. Returns the process exit code (0 ok, 1 usage, 2 bad input, 3 GL or output failure).
int runPlayer(int argc, char** argv, const char* program, const TruthFactory& truth);

} // namespace pnb::player
