// pnb-reference's irradiance truths: --indirect (one bounce of diffuse light) and --sky (the
// sky light with what hides it), each traced at the frame's pixels, written as images and, where
// the player dumped its own (indirect.exr, sky.exr), compared with it.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "pnb/scene.h"
#include "pnb_reference/shadow_tracer.h"
#include "reference_cli.h"
#include "reference_io.h"

namespace pnb::reference_tool {

// A tracer's build error as an exit code and a sentence naming the scene.
Failure tracerFailure(const std::string& scenePath, const pnb::reference::TracerError& e);

// --indirect: the one-bounce truth at the frame's pixels, its images, and (with the player's
// indirect.exr) the comparison. Returns the "indirect" object of metrics.json.
Expected<nlohmann::ordered_json> runIndirect(const Settings& settings, const pnb::Scene& scene, const Frame& frame,
                                             const std::vector<glm::vec3>& positions,
                                             const std::vector<glm::vec3>& shadingNormals,
                                             const std::string& in, const std::string& outDir);

// --sky: the sky-light truth at the frame's pixels, its images, and (with the player's sky.exr)
// the comparison. Returns the "sky" object of metrics.json.
Expected<nlohmann::ordered_json> runSky(const Settings& settings, const pnb::Scene& scene, const Frame& frame,
                                        const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::vec3>& shadingNormals, const std::string& in,
                                        const std::string& outDir);

} // namespace pnb::reference_tool
