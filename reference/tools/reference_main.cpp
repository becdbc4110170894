// pnb-reference: ray-traced ground truth for one frame the player dumped
// (`pnb-play --dump position,normal,shadow`), and how far the player's shadows are from it.
//
// Reads SCENE.pnb and DIR/{frame.json, position.exr, normal.exr, shadow.exr}; writes
// OUT/{visibility.exr, visibility.png, shadow_diff.png, metrics.json}; with --indirect and --sky
// also the one-bounce and sky-light irradiance truths (and their comparison with the player's
// indirect.exr, sky.exr). The work is the pnb_reference library (ShadowTracer, IndirectTracer,
// SkyTracer, compareShadow, compareIndirect, texelRatioByCascade); these files are the image and
// JSON I/O around it, by concern: the command line (reference_cli), the files (reference_io),
// the shadow run (reference_run) and the irradiance truths (reference_irradiance). The input
// contract is docs/REFERENCE.md. frame.json's optional "shadow_light_index" K makes the judged
// light LGHT light K, a point or spot light placed by its node (local_light.h), instead of the
// directional light of "toward_light".
//
// Exit codes: 0 ok, 1 usage, 2 input error (missing or malformed file; the message names it),
// 3 unsupported scene data, 4 output error, 5 Embree failure.

#include "reference_cli.h"
#include "reference_run.h"

int main(int argc, char** argv) {
    pnb::reference_tool::Settings settings;
    if (auto done = pnb::reference_tool::parseCommandLine(argc, argv, settings)) return *done;
    return pnb::reference_tool::run(settings);
}
