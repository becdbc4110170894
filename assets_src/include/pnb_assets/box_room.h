// pnb_assets/box_room.h — the bundled default scene: a Cornell-style box room.
//
// A closed room with a red left wall, a green right wall and white floor/ceiling/back, two boxes,
// and a translucent forward-shaded pane in front of them; a sun through the open front, one
// point light, one camera and a fly-through path; one checker texture with its full mip chain.
// It holds every v1 chunk kind, so it doubles as the format's test sample. Deterministic: the
// same options give the same Scene.
#pragma once

#include <cstdint>

#include "pnb/scene_builder.h"

namespace pnb::assets {

struct BoxRoomOptions {
    float roomSize = 10.0f;       // metres, edge of the cubic room. Default 10.
    uint32_t textureSize = 64;    // checker texture edge, texels (power of two). Default 64.
    uint32_t boxSubdivisions = 1; // quads per box face edge; raises the triangle count. Default 1.
    // A tiny environment (ENVM with a 4x2 radiance image, a 2x2 two-level cube and a 2x2 BRDF
    // table of constant values): a format sample, not a lighting one (the converter bakes real
    // ones). Default off.
    bool environment = false;
};

// Fills `builder.scene` (which must be empty).
void buildBoxRoom(SceneBuilder& builder, const BoxRoomOptions& options = {});

} // namespace pnb::assets
