// converter/src/environment_internal.h — private interface between environment.cpp (mips,
// formats, assembly) and environment_prefilter.cpp (the GGX cube). Not installed.
#pragma once

#include <cstdint>
#include <vector>

#include "texture_internal.h"

namespace pnb::converter::environment_detail {

using texture_detail::ImageF;

// sh9.h's equirectUv for a direction known to be unit and finite, without its checks: the
// prefilter calls it ~10^7 times (tests/converter/environment_test.cpp checks that they agree).
void equirectUvOfUnit(const double dir[3], double uv[2]);

// Trilinear lookup of an equirect mip chain (RGBA, level 0 first) in unit direction `dir` at
// level-of-detail `lod` (clamped to the chain): bilinear within a level, wrapping in u (the
// image is periodic in azimuth) and clamping in v (the poles), linear between levels.
void sampleEquirect(const std::vector<ImageF>& mips, const double dir[3], double lod,
                    double rgb[3]);

// The specular cube: `levels` levels of `size` >> m faces, each level RGBA float, faces
// +X -X +Y -Y +Z -Z consecutively, rows t = 0 first. Level 0 resamples the radiance; level m > 0
// is the GGX prefilter at roughness m / (levels - 1) with `samples` samples per texel
// (environment_prefilter.cpp explains the filtered importance sampling). Deterministic for any
// `jobs`.
std::vector<ImageF> prefilterSpecularCube(const std::vector<ImageF>& mips, uint32_t size,
                                          uint32_t levels, uint32_t samples, uint32_t jobs);

} // namespace pnb::converter::environment_detail
