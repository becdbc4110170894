// shading/ — the scene's surfaces lit into the HDR target: layered deferred shading (G-buffer
// then lighting, one deferred layer at a time) and the forward materials after it.
#pragma once

#include <cstddef>
#include <vector>

#include "frame/frame_context.h"

namespace pnb::player {

// The deferred layers with visible items this frame, in ascending priority (indices into
// DrawLists::layers), into `layers` (reused frame to frame); none when the container has no
// deferred lighting program.
void deferredLayersToDraw(const FrameContext& ctx, std::vector<size_t>& layers);

// One layer's G-buffer: clears its colours, keeps the shared depth, draws the layer's items
// (pass_deferred_layers.cpp).
void runGBuffer(FrameContext& ctx, size_t layer);

// Composes the layer in the G-buffer into the HDR target with its lighting.
void runDeferredLighting(FrameContext& ctx);

// Forward materials against the deferred layers' depth (pass_forward.cpp).
void runForward(FrameContext& ctx);

} // namespace pnb::player
