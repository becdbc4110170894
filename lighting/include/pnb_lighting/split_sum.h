// pnb_lighting/split_sum.h — the specular half of image-based lighting: the GGX microfacet
// distribution, its visibility term, Hammersley points, GGX importance sampling (shared by the
// prefiltered radiance cube and the BRDF table) and the split-sum BRDF lookup table of Karis 2013
// ("Real Shading in Unreal Engine 4", SIGGRAPH course notes). Pure CPU (no GL): the converter or
// the player fills the table once; the shaders do F0 * A + B.
//
// Formulas (n = +Z in tangent space, h the half vector, alpha = roughness^2, the perceptual
// remapping of Burley 2012 / Karis 2013):
//   D(h)     = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2)          (Trowbridge-Reitz / GGX)
//   V(v, l)  = 0.5 / (n.l sqrt((n.v)^2 (1 - a2) + a2) + n.v sqrt((n.l)^2 (1 - a2) + a2)),
//              a2 = alpha^2:
//              Smith height-correlated visibility, G2 / (4 n.l n.v) (Heitz 2014, "Understanding the
//              Masking-Shadowing Function", eq. 99; the form Filament uses for lighting and its
//              DFG table). Chosen over Karis' separable Schlick-GGX (k = alpha / 2 for IBL) so the
//              table agrees with the analytic lights' term; the two differ by a few percent at
//              high roughness and grazing angles (separable masking darkens more).
//   Sampling h: cos(theta_h) = sqrt((1 - xi2) / (1 + (alpha^2 - 1) xi2)), phi_h = 2 pi xi1,
//              pdf(h) = D(h) (n.h), pdf(l) = D (n.h) / (4 v.h), l = reflect(-v, h).
//   Hammersley: point i of n is (i / n, radical inverse of i in base 2) (van der Corput).
//   Split sum: integral of f_spec (n.l) dl = F0 * A + B with Schlick's F = F0 + (1 - F0) Fc,
//              Fc = (1 - v.h)^5, estimated as (1/N) sum over GGX samples with n.l > 0 of
//              Gv = 4 V (n.l) (v.h) / (n.h):  A = (1/N) sum (1 - Fc) Gv,  B = (1/N) sum Fc Gv.
//              A + B is the directional albedo of the white (F0 = 1) lobe: <= 1 (single
//              scattering loses energy at high roughness; no multiple-scattering compensation).
//
// Every function is total: roughness is clamped to [0, 1] (NaN -> 1), n.v to [1e-4, 1] (NaN ->
// 1), a sample count of 0 counts as 1; at roughness 0 the sampler returns h = n exactly, so the
// table's roughness-0 column is A = 1 - Fc, B = Fc with no division by zero.
//
// Does NOT do: the prefiltered radiance cube itself (the converter/player: for each mip, roughness
// = mip / (mips - 1), weight samples by n.l, and PDF-based source-mip selection against aliasing,
// Karis 2013), multiple-scattering energy compensation (Kulla & Conty 2017), cloth/sheen tables.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace pnb::lighting {

// roughness^2 with roughness clamped to [0, 1] (NaN -> 1).
double ggxAlpha(double roughness);
// D(h) for cos(theta_h) = nDotH (clamped to [0, 1]); alpha is clamped to [1e-4, 1] here (the
// mirror's delta as its narrow limit) so D stays finite.
double ggxD(double nDotH, double alpha);
// Height-correlated Smith V (includes 1 / (4 n.l n.v)); 0 when either cosine is <= 0 or NaN;
// positive cosines below 1e-6 count as 1e-6 (finite at alpha = 0).
double smithGgxCorrelatedV(double nDotV, double nDotL, double alpha);

// Point i of an n-point Hammersley set in [0, 1)^2 (n = 0 counts as 1).
glm::dvec2 hammersley(uint32_t i, uint32_t n);
// A GGX-distributed half vector in tangent space (+Z = normal) for xi in [0, 1)^2 (clamped).
glm::dvec3 ggxSampleHalfVector(const glm::dvec2& xi, double alpha);
// The same, turned into the frame of the world-space unit normal n (any tangent; n zero or
// non-finite counts as +Z).
glm::dvec3 ggxSampleHalfVector(const glm::dvec2& xi, double alpha, const glm::dvec3& n);

// (A, B) for n.v and perceptual roughness by `samples` Hammersley-GGX samples (deterministic).
glm::dvec2 splitSumBrdf(double nDotV, double roughness, uint32_t samples);

// The W x H table, RG interleaved (2 floats per texel, row-major, row 0 first): texel (i, j) holds
// splitSumBrdf((i + 0.5) / W, (j + 0.5) / H, samples), so x is n.v and y is roughness, sampled
// with texture(lut, vec2(NdotV, roughness)) when row 0 is uploaded first. Zero size gives an
// empty vector.
std::vector<float> splitSumLut(uint32_t width, uint32_t height, uint32_t samples);

// Row j of that table (width × 2 floats into `out`): rows are independent, so a caller with
// threads (the converter's environment bake) fills them in parallel, bit for bit the same.
void splitSumLutRow(uint32_t width, uint32_t height, uint32_t samples, uint32_t j, float* out);

} // namespace pnb::lighting
