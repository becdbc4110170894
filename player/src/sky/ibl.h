// ibl.h — light from the container's environment (ENVM) and the background it is seen against.
// Per frame, when the lighting programs were built with IBL (shaders/include/ibl.glsl):
//   prepareIbl     writes the IblBlock into the ring (the irradiance SH turned by
//                  ibl.rotation_deg and scaled by ibl.intensity on the CPU — nine multiply-adds
//                  per colour, so the shaders never rotate SH) and binds it with the specular
//                  cube and the BRDF table; with ibl.enabled off the block says so and nothing
//                  else is bound;
//   renderSkyHeightMap (ibl.visibility = height) draws the scene from above into a height map
//                  when it is missing or the geometry changed (pass_sky_height.cpp);
//   runBackground  draws the environment where the depth buffer is still clear (after the
//                  deferred layers, before forward materials, so blended surfaces cover it).
// A container without an environment has no IBL programs: nothing here runs or is allocated.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "pnb_player/gl_handles.h"
#include "pnb_player/settings.h"
#include "shared/ibl_block.h" // IblBlock (GLSL and C++)

namespace pnb::player {

struct FrameContext;
struct FrameView;
struct GiContext;

struct IblContext {
    bool active = false;   // this frame lights with the environment
    bool capture = false;  // lighting writes the sky irradiance (CaptureBuffer::Sky)
    bool warned = false;   // "ibl.enabled, but ..." said once
    bool warnedVisibility = false; // "ibl.visibility=volume|probes needs GI ..." said once
    SkyVisibility visibility = SkyVisibility::None; // this frame's term (what its inputs allow)
    bool specular = false;         // this frame reads the prefiltered cube
    // The height map (pass_sky_height.cpp): world box it covers, for which scene version.
    GlHandle heightMap, heightFb;
    uint32_t heightResolution = 0;
    uint64_t heightVersion = ~0ull, heightBytes = 0;
    glm::dvec3 heightMin{0.0}, heightMax{0.0};
};

// Whether the frame draws the sky's height map (ibl.visibility = height with an environment).
bool wantsSkyHeightMap(const FrameView& in);
// The CPU step, without GL: whether the environment lights this frame, the IblBlock, the
// visibility term the frame's inputs allow (after the height map, after GI's prepare step).
void planIbl(const FrameView& in, IblContext& ibl, const GiContext& gi, IblBlock& block);
void prepareIbl(FrameContext& ctx, IblContext& ibl, const GiContext& gi);    // ibl_setup.cpp
void renderSkyHeightMap(FrameContext& ctx, IblContext& ibl); // pass_sky_height.cpp
void runBackground(FrameContext& ctx, const IblContext& ibl); // pass_background.cpp

} // namespace pnb::player
