// post/ — after shading: the tone map (with FXAA) into the output, and the debug views over it.
#pragma once

#include <string>

#include "frame/frame_context.h"

namespace pnb::player {

struct ShadowContext;
struct GiContext;

// HDR -> the sRGB output (pass_tonemap.cpp).
void runTonemap(FrameContext& ctx);

// The chosen debug view over the output (pass_debug_view.cpp); nothing without one.
void runDebugView(FrameContext& ctx, const ShadowContext& shadows, const GiContext& gi);

// Why the chosen debug view shows nothing this frame ("" when it shows something): a shadow
// view without shadows, a GI view without GI, the LOD view without levels.
std::string debugViewNote(const FrameContext& ctx, const ShadowContext& shadows, const GiContext& gi);

} // namespace pnb::player
