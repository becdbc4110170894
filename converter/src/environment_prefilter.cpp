// converter/src/environment_prefilter.cpp — the specular cube of the split-sum approximation
// (Karis 2013, "Real Shading in Unreal Engine 4"): level m holds the radiance convolved with the
// GGX lobe of perceptual roughness r = m / (levels - 1) under the assumption N = V = R, i.e.
//   P(R) = sum_k L(l_k) (n.l_k) / sum_k (n.l_k),  h_k ~ GGX(alpha = r^2) around R,
//   l_k = reflect(-R, h_k), samples with n.l <= 0 skipped,
// with the same Hammersley points and half-vector sampler as the BRDF table (split_sum.h), so
// the two halves of the split sum use one lobe.
//
// Filtered importance sampling (Krivanek & Colbert 2008, "Real-time Shading with Filtered
// Importance Sampling", eq. 10-13): each sample reads the radiance's mip chain at
//   lod = 0.5 log2(Omega_s / Omega_p),  Omega_s = 1 / (N pdf(l)),  pdf(l) = D(h) / 4 (N = V)
// where Omega_p is the solid angle of a level-0 texel: a sample stands for the solid angle
// 1 / (N pdf) around it, so it reads the radiance averaged over about that much of the sphere.
// Without it a 1e5-nit sun texel is either missed by all samples of a texel or hit by one and
// worth 1e5 / N, so the rough levels fill with bright speckles (fireflies) that move as the
// roughness changes; with it, the sun is spread over the samples that fall near it.
// Omega_p is the mean texel solid angle 4 pi / (W H): an equirect texel near a pole covers less
// (sin theta), but the box mips shrink both directions alike, so the mean is the honest match.
//
// Level 0 is the radiance resampled (bilinear, trilinear between the two mips whose texels are
// closest in solid angle to the cube texel's exact solid angle), so magnification stays sharp and
// minification does not alias.
#include <algorithm>
#include <cmath>

#include "environment_internal.h"
#include "parallel_for.h"
#include "pnb_converter/environment.h"
#include "pnb_lighting/split_sum.h" // hammersley, ggxSampleHalfVector, ggxD, ggxAlpha

namespace pnb::converter {

void cubeTexelDirection(uint32_t face, uint32_t i, uint32_t j, uint32_t size, double out[3]) {
    // OpenGL 4.5 table 8.19 inverted: (sc, tc) = (2s - 1, 2t - 1) at the texel centre.
    const double a = 2.0 * (i + 0.5) / size - 1.0, b = 2.0 * (j + 0.5) / size - 1.0;
    double x = 0, y = 0, z = 0;
    switch (face) {
    case 0: x = 1, y = -b, z = -a; break;  // +X: sc = -z, tc = -y
    case 1: x = -1, y = -b, z = a; break;  // -X: sc = +z, tc = -y
    case 2: x = a, y = 1, z = b; break;    // +Y: sc = +x, tc = +z
    case 3: x = a, y = -1, z = -b; break;  // -Y: sc = +x, tc = -z
    case 4: x = a, y = -b, z = 1; break;   // +Z: sc = +x, tc = -y
    default: x = -a, y = -b, z = -1; break; // -Z: sc = -x, tc = -y
    }
    const double n = std::sqrt(x * x + y * y + z * z);
    out[0] = x / n;
    out[1] = y / n;
    out[2] = z / n;
}

namespace environment_detail {

namespace {

constexpr double kPi = 3.14159265358979323846;
// GPU Gems 3 ch. 20 (Colbert & Krivanek) biases the lod by +1: the Hammersley pattern then sees a
// small bright source through about four times the texels. Measured on a 64x32 image with 2x2
// 1e5-nit suns, 256 samples, roughness 1 (tests/converter/environment_test.cpp), worst texel error
// against the exact convolution, as a fraction of the peak: 0.76 without filtering, 0.33
// unbiased, 0.23 with the bias; it converges to the exact result as samples grow either way.
constexpr double kLodBias = 1.0;

void bilinear(const ImageF& img, double u, double v, double w, double rgb[3]) {
    const double x = u * img.width - 0.5, y = v * img.height - 0.5;
    const double fx0 = std::floor(x), fy0 = std::floor(y);
    const double fx = x - fx0, fy = y - fy0;
    // u in [0, 1] makes floor(x) one of -1 .. W: a wrap needs no division (this is the hot loop).
    const int64_t W = img.width, H = img.height;
    int64_t xi0 = int64_t(fx0), xi1 = xi0 + 1;
    if (xi0 < 0) xi0 += W;
    if (xi0 >= W) xi0 -= W;
    if (xi1 >= W) xi1 -= W;
    const size_t x0 = size_t(std::clamp<int64_t>(xi0, 0, W - 1)), x1 = size_t(std::clamp<int64_t>(xi1, 0, W - 1));
    const size_t y0 = size_t(std::clamp<int64_t>(int64_t(fy0), 0, H - 1));
    const size_t y1 = size_t(std::clamp<int64_t>(int64_t(fy0) + 1, 0, H - 1));
    const float* t = img.texels.data();
    auto at = [&](size_t xx, size_t yy, int c) { return double(t[(yy * img.width + xx) * 4 + c]); };
    for (int c = 0; c < 3; ++c) {
        const double top = at(x0, y0, c) * (1 - fx) + at(x1, y0, c) * fx;
        const double bottom = at(x0, y1, c) * (1 - fx) + at(x1, y1, c) * fx;
        rgb[c] += w * (top * (1 - fy) + bottom * fy);
    }
}

// Solid angle of the part of the cube face [-1, 1]^2 at distance 1 between the origin corner
// and (x, y): the integral of 1 / (1 + x^2 + y^2)^(3/2).
double areaElement(double x, double y) {
    return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0));
}

double cubeTexelSolidAngle(uint32_t i, uint32_t j, uint32_t size) {
    const double x0 = 2.0 * i / size - 1.0, x1 = 2.0 * (i + 1) / size - 1.0;
    const double y0 = 2.0 * j / size - 1.0, y1 = 2.0 * (j + 1) / size - 1.0;
    return areaElement(x0, y0) - areaElement(x0, y1) - areaElement(x1, y0) + areaElement(x1, y1);
}

// An orthonormal frame around unit n without a branch on its direction (Duff et al. 2017,
// "Building an Orthonormal Basis, Revisited"): continuous everywhere but at n.z = -0.
void frameAround(const double n[3], double t[3], double b[3]) {
    const double sign = std::copysign(1.0, n[2]);
    const double a = -1.0 / (sign + n[2]);
    const double c = n[0] * n[1] * a;
    t[0] = 1.0 + sign * n[0] * n[0] * a;
    t[1] = sign * c;
    t[2] = -sign * n[0];
    b[0] = c;
    b[1] = sign + n[1] * n[1] * a;
    b[2] = -n[1];
}

// One GGX sample in the tangent frame (+Z = N = V = R): l and its weight n.l, and the mip it reads.
struct LobeSample {
    double l[3];
    double nDotL;
    double lod;
};

std::vector<LobeSample> lobeSamples(double roughness, uint32_t count, double texelSolidAngle) {
    std::vector<LobeSample> out;
    const double alpha = lighting::ggxAlpha(roughness);
    for (uint32_t k = 0; k < count; ++k) {
        const glm::dvec3 h = lighting::ggxSampleHalfVector(lighting::hammersley(k, count), alpha);
        const double nDotH = h.z;
        // l = reflect(-v, h) with v = n = +Z: 2 (v.h) h - v.
        LobeSample s{{2 * nDotH * h.x, 2 * nDotH * h.y, 2 * nDotH * nDotH - 1}, 0, 0};
        s.nDotL = s.l[2];
        if (!(s.nDotL > 0)) continue;
        // pdf(l) = D (n.h) / (4 v.h) = D / 4, since n = v makes n.h = v.h.
        const double pdf = lighting::ggxD(nDotH, alpha) / 4.0;
        const double sampleSolidAngle = 1.0 / (double(count) * pdf);
        s.lod = std::max(0.0, 0.5 * std::log2(sampleSolidAngle / texelSolidAngle) + kLodBias);
        out.push_back(s);
    }
    return out;
}

} // namespace

void equirectUvOfUnit(const double dir[3], double uv[2]) {
    // phi = atan2(z, x) from +X towards +Z, u = phi / (2 pi) + 1/2; theta = acos(y), v = theta / pi.
    double u = std::atan2(dir[2], dir[0]) * (0.5 / kPi) + 0.5;
    uv[0] = u >= 1.0 ? u - 1.0 : u;
    uv[1] = std::acos(std::clamp(dir[1], -1.0, 1.0)) * (1.0 / kPi);
}

void sampleEquirect(const std::vector<ImageF>& mips, const double dir[3], double lod,
                    double rgb[3]) {
    rgb[0] = rgb[1] = rgb[2] = 0;
    if (mips.empty()) return;
    double uv[2];
    equirectUvOfUnit(dir, uv);
    lod = std::clamp(lod, 0.0, double(mips.size() - 1));
    const size_t l0 = size_t(lod);
    const double f = lod - double(l0);
    bilinear(mips[l0], uv[0], uv[1], 1.0 - f, rgb);
    if (f > 0 && l0 + 1 < mips.size()) bilinear(mips[l0 + 1], uv[0], uv[1], f, rgb);
}

std::vector<ImageF> prefilterSpecularCube(const std::vector<ImageF>& mips, uint32_t size,
                                          uint32_t levels, uint32_t samples, uint32_t jobs) {
    std::vector<ImageF> out(levels);
    const double sourceTexel = 4.0 * kPi / (double(mips[0].width) * mips[0].height);
    for (uint32_t m = 0; m < levels; ++m) {
        const uint32_t n = std::max(1u, size >> m);
        ImageF& level = out[m];
        level.width = n;
        level.height = n * 6; // the six faces one after another, as TMIP stores them
        level.texels.assign(level.texelCount() * 4, 1.0f);
        const double roughness = levels > 1 ? double(m) / double(levels - 1) : 0.0;
        const std::vector<LobeSample> lobe =
            m == 0 ? std::vector<LobeSample>{} : lobeSamples(roughness, samples, sourceTexel);
        // One task per row of a face: enough rows for both cores even at the 4x4 level, and the
        // result of a texel never depends on which thread computed it.
        parallelFor(size_t(6) * n, jobs, [&](size_t row) {
            const uint32_t face = uint32_t(row / n), j = uint32_t(row % n);
            for (uint32_t i = 0; i < n; ++i) {
                double r[3], rgb[3] = {0, 0, 0};
                cubeTexelDirection(face, i, j, n, r);
                if (m == 0) {
                    const double lod = std::max(
                        0.0, 0.5 * std::log2(cubeTexelSolidAngle(i, j, n) / sourceTexel));
                    sampleEquirect(mips, r, lod, rgb);
                } else {
                    double t[3], b[3], acc[3] = {0, 0, 0}, weight = 0;
                    frameAround(r, t, b);
                    for (const LobeSample& s : lobe) {
                        double l[3], L[3];
                        for (int k = 0; k < 3; ++k) l[k] = t[k] * s.l[0] + b[k] * s.l[1] + r[k] * s.l[2];
                        sampleEquirect(mips, l, s.lod, L);
                        for (int k = 0; k < 3; ++k) acc[k] += L[k] * s.nDotL;
                        weight += s.nDotL;
                    }
                    // The mirror direction itself always has n.l = 1 > 0, so the lobe is never
                    // empty; the guard is for a degenerate sample count.
                    for (int k = 0; k < 3; ++k) rgb[k] = weight > 0 ? acc[k] / weight : 0.0;
                }
                float* p = &level.texels[(size_t(face) * n * n + size_t(j) * n + i) * 4];
                for (int k = 0; k < 3; ++k) p[k] = float(rgb[k]);
                p[3] = 1.0f;
            }
        });
    }
    return out;
}

} // namespace environment_detail

} // namespace pnb::converter
