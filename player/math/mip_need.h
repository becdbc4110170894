// player/math/mip_need.h — which mip level of a texture a view needs (pure CPU, no GL): the
// streaming player's conservative estimate of the texels worth keeping resident.
//
// A surface at distance d covers pixelScale / d pixels per world unit (pixelScale as in
// lod_select.h). Its texture has `texelsPerUnit` texels per world unit at level 0:
//
//     texelsPerUnit = max(width, height) * uvDensity * slotScale / worldScale
//
// where uvDensity is the mesh's UV units per mesh unit (uvDensity below) and slotScale the
// material's texture-transform scale. The level whose texels are no smaller than a pixel is
// floor(log2(texelsPerUnit * d / pixelScale)); taken at the *nearest* point of the item's bounds,
// facing the eye, so no visible point needs a finer level than this estimate says (a surface
// seen at a grazing angle needs a coarser one; the estimate keeps the finer). Items outside the
// view count too: turning around must not wait for texels.
//
// Every function is total: zero, negative, infinite or NaN inputs give a level in range (level 0
// whenever the need cannot be bounded), never NaN.
#pragma once

#include <cstdint>

#include "pnb/chunks.h"

namespace pnb::player {

// Mean UV (TEXCOORD_0) units per mesh unit over the triangles of `submesh`:
// sqrt(sum of UV areas / sum of areas). 0 when the mesh has no TEXCOORD_0 or no area, or when
// its position or UV encoding is one this estimate does not decode (then callers assume the
// texture spans the submesh's bounds once, uvDensityFromBounds).
double uvDensity(const Mesh& mesh, const Submesh& submesh);
// 1 / the largest edge of the submesh's bounds (mesh units): a texture spanning the submesh once.
double uvDensityFromBounds(const Submesh& submesh);

// The finest level a surface needs: texelsPerUnit at level 0 (per world unit), seen at
// `distance` with `pixelScale` pixels per unit at distance 1. Clamped to [0, mipCount - 1].
uint32_t neededMipLevel(double texelsPerUnit, double distance, double pixelScale, uint32_t mipCount);

} // namespace pnb::player
