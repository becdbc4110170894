// Global illumination's propagation shader alone, on hand-made volumes: flux kept for any lobe,
// a single VPL against the inverse-square law, symmetry, one wall and a wall behind a wall. Apart
// from the pipeline tests (gi_test.cpp) because it drives the compute shaders directly, with no
// scene, converter or renderer.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <span>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "lpv_math.h"
#include "gl/program_compile.h"
#include "render_fixture.h"

namespace pnb::player::test {
namespace {

// --- the propagation shader alone -------------------------------------------------------------

constexpr int kN = 16;

GlHandle volume(int side, int depth, const std::vector<float>* data = nullptr, GLenum format = GL_RGBA16F) {
    GlHandle t = createTexture(GL_TEXTURE_3D);
    glTextureStorage3D(t.id(), 1, format, side, side, depth);
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum w : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glTextureParameteri(t.id(), w, GL_CLAMP_TO_EDGE);
    std::vector<float> zero(size_t(side) * side * depth * 4, 0.0f);
    glTextureSubImage3D(t.id(), 0, 0, 0, 0, side, side, depth, GL_RGBA, GL_FLOAT, data ? data->data() : zero.data());
    return t;
}

std::vector<float> read(const GlHandle& t, int side, int depth) {
    std::vector<float> v(size_t(side) * side * depth * 4);
    glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(v.size() * 4), v.data());
    return v;
}

size_t cell(int x, int y, int z) { return ((size_t(z) * kN + size_t(y)) * kN + size_t(x)) * 4; }

// Band-0 sum: the volume's total flux up to the constant 2 sqrt(pi).
double flux(const std::vector<float>& v) {
    double s = 0;
    for (size_t i = 0; i < v.size(); i += 4) s += v[i];
    return s;
}

// A step stores its result scaled for the next step (lpv_propagate.comp's conservingSource:
// by 4ab / (a + b)^2 when b = sqrt(3) |band 1| > a = band 0); the scale leaves b / a as it was,
// so the stored values say what to divide by to get the step's own light back.
std::vector<float> unscaled(std::vector<float> v) {
    for (size_t i = 0; i < v.size(); i += 4) {
        double a = v[i], b = std::sqrt(3.0) *
                             std::sqrt(double(v[i + 1]) * v[i + 1] + double(v[i + 2]) * v[i + 2] +
                                       double(v[i + 3]) * v[i + 3]);
        if (b <= a) continue;
        double scale = 4 * a * b / ((a + b) * (a + b));
        for (size_t k = 0; k < 4; ++k)
            v[i + k] = float(v[i + k] / scale);
    }
    return v;
}

struct Propagation {
    std::vector<std::vector<float>> steps; // each step's light (red channel), as it was summed
    std::vector<float> sum;
};

// A source `initial` (L1 SH; default isotropic, band 0 only) in cell `at`, `iterations` steps, the
// geometry volume `geometry` ((kN+1)^3 corners) if given, turned into face transmittance first.
// Mirrors pass_gi_inject.cpp's runGiResolve (transmittance) and pass_gi_propagate.cpp's dispatch.
Propagation propagate(glm::ivec3 at, int iterations, const std::vector<float>* geometry,
                      const Sh4& initial = {1, 0, 0, 0}) {
    std::vector<float> src(size_t(kN) * kN * kN * 4, 0.0f);
    for (size_t k = 0; k < 4; ++k)
        src[cell(at.x, at.y, at.z) + k] = float(initial[k]);
    std::array<GlHandle, 3> source, next, sum;
    for (int ch = 0; ch < 3; ++ch) {
        source[ch] = volume(kN, kN, &src);
        next[ch] = volume(kN, kN);
        sum[ch] = volume(kN, kN, &src);
    }
    GlHandle gv = volume(kN + 1, kN + 1, geometry);
    GlHandle transmit[2] = {volume(kN, kN, nullptr, GL_RGBA8), volume(kN, kN, nullptr, GL_RGBA8)};
    if (geometry) {
        std::string_view mode = "RESOLVE_TRANSMITTANCE";
        auto resolve = compileEmbeddedCompute("lpv_resolve.comp", std::span(&mode, 1));
        EXPECT_TRUE(resolve.ok()) << (resolve.ok() ? "" : resolve.error().message);
        if (!resolve) return {};
        glProgramUniform3i(resolve->id(), 0, kN, kN, 1);
        glBindTextureUnit(0, gv.id());
        glBindImageTexture(0, transmit[0].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glBindImageTexture(1, transmit[1].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glUseProgram(resolve->id());
        glDispatchCompute(kN / 4, kN / 4, kN / 4);
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
    }
    std::string_view define = geometry ? "OCCLUSION" : "PLAIN";
    auto program = compileEmbeddedCompute("lpv_propagate.comp", std::span(&define, 1));
    EXPECT_TRUE(program.ok()) << (program.ok() ? "" : program.error().message);
    Propagation out;
    if (!program) return out;
    GLuint p = program->id();
    glProgramUniform2i(p, 0, kN, 1);
    glUseProgram(p);
    glBindTextureUnit(3, transmit[0].id());
    glBindTextureUnit(4, transmit[1].id());
    for (GLuint ch = 0; ch < 3; ++ch)
        glBindImageTexture(3 + ch, sum[ch].id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA16F);
    auto* from = &source;
    auto* to = &next;
    for (int i = 0; i <= iterations; ++i) { // dispatch 0 scales the source, then the steps
        for (GLuint ch = 0; ch < 3; ++ch) {
            glBindTextureUnit(ch, (*from)[ch].id());
            glBindImageTexture(ch, (*to)[ch].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        }
        glProgramUniform1i(p, 1, i == 0);
        glDispatchCompute(kN / 4, kN / 4, kN / 4);
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        if (i > 0) out.steps.push_back(unscaled(read((*to)[0], kN, kN)));
        std::swap(from, to);
    }
    out.sum = read(sum[0], kN, kN);
    glUseProgram(0);
    return out;
}

TEST(GiPropagation, KeepsTheFluxStepToStepWithoutOccluders) {
    // 6 steps from the centre never reach the border of a 16^3 grid: nothing leaves it.
    Propagation r = propagate({8, 8, 8}, 6, nullptr);
    ASSERT_EQ(r.steps.size(), 6u);
    double previous = 1.0;
    for (size_t i = 0; i < r.steps.size(); ++i) {
        double f = flux(r.steps[i]);
        // The first step from an isotropic source is exact; later ones re-emit beams and
        // evaluate them at face centres (Kaplanyan's approximation) and the flux-keeping scale
        // follows the continuous integral, not the 30 faces: within 2 %.
        EXPECT_NEAR(f / previous, 1.0, i == 0 ? 2e-3 : 0.02) << "step " << i + 1;
        previous = f;
    }
}

TEST(GiPropagation, APointSpreadsSymmetricallyAlongTheSixAxes) {
    Propagation r = propagate({8, 8, 8}, 4, nullptr);
    for (int k = 1; k <= 4; ++k) {
        double px = r.sum[cell(8 + k, 8, 8)], nx = r.sum[cell(8 - k, 8, 8)];
        double py = r.sum[cell(8, 8 + k, 8)], ny = r.sum[cell(8, 8 - k, 8)];
        double pz = r.sum[cell(8, 8, 8 + k)], nz = r.sum[cell(8, 8, 8 - k)];
        EXPECT_GT(px, 0.0) << k;
        for (double v : {nx, py, ny, pz, nz}) EXPECT_NEAR(v, px, 2e-3 * px) << "distance " << k;
        // Each step moves light one cell: nothing beyond the step count.
        EXPECT_EQ(r.sum[cell(8 + k, 8, 8)] > 0, k <= 4);
    }
    EXPECT_EQ(r.sum[cell(8 + 5, 8, 8)], 0.0f);
}

// Blocking surfels facing a source on -x on the planes of corners x = each of `planes` (x = 10:
// between cells 9 and 10): one full cell of area per corner, B = lobe(-x).
std::vector<float> walls(std::initializer_list<int> planes) {
    const int corners = kN + 1;
    std::vector<float> v(size_t(corners) * corners * corners * 4, 0.0f);
    Sh4 lobe = cosineLobe({-1, 0, 0});
    for (int x : planes)
        for (int z = 0; z < corners; ++z)
            for (int y = 0; y < corners; ++y)
                for (int k = 0; k < 4; ++k)
                    v[((size_t(z) * corners + size_t(y)) * corners + size_t(x)) * 4 + size_t(k)] =
                        float(lobe[size_t(k)]);
    return v;
}

// The light summed over every cell from x = `from` on.
double beyond(const std::vector<float>& v, int from) {
    double s = 0;
    for (int z = 0; z < kN; ++z)
        for (int y = 0; y < kN; ++y)
            for (int x = from; x < kN; ++x)
                s += v[cell(x, y, z)];
    return s;
}

TEST(GiPropagation, AThinWallCutsTheLightThatReachesTheFarSide) {
    const std::vector<float> one = walls({10});
    double open = beyond(propagate({6, 8, 8}, 8, nullptr).sum, 10);
    double walled = beyond(propagate({6, 8, 8}, 8, &one).sum, 10);
    EXPECT_GT(open, 0.0);
    // One full-cell wall evaluates to a blocking probability of 0.75 (L1's smoothing of the
    // cosine) times the 4/3 scale: about a quarter of the light gets through.
    EXPECT_LT(walled, 0.3 * open);
    EXPECT_GT(walled, 0.15 * open);
}

TEST(GiPropagation, AWallBehindAWallPassesLessThanEitherAlone) {
    // Walls at x = 10 and x = 12: beyond the second, the light that crossed both. Each crossing
    // has its own transmittance, so the pair passes about the product of what each passes:
    // measured 0.232, 0.228 and 0.053 (0.232 x 0.228 = 0.053).
    const std::vector<float> first = walls({10}), second = walls({12}), both = walls({10, 12});
    double open = beyond(propagate({6, 8, 8}, 10, nullptr).sum, 12);
    double a = beyond(propagate({6, 8, 8}, 10, &first).sum, 12) / open;
    double b = beyond(propagate({6, 8, 8}, 10, &second).sum, 12) / open;
    double ab = beyond(propagate({6, 8, 8}, 10, &both).sum, 12) / open;
    std::printf("  passed: first wall %.3f, second %.3f, both %.3f\n", a, b, ab);
    EXPECT_LT(ab, 0.5 * std::min(a, b));
    EXPECT_GT(ab, 0.25 * a * b);
    EXPECT_LT(ab, 2.0 * a * b);
}

// A virtual point light: a clamped-cosine emitter of unit flux along n (what injection writes).
Sh4 vpl(const glm::dvec3& n) {
    Sh4 l = cosineLobe(n);
    for (double& c : l)
        c /= M_PI;
    return l;
}

TEST(GiPropagation, KeepsTheFluxOfAnyLobe) {
    // The clamped evaluation of a directional lobe adds light (Kaplanyan-Dachsbacher: +13.8 % on
    // the first step from a cosine lobe, more from a beam); the propagation scales its sources
    // back. One step from a VPL along an axis, along a diagonal, and from the sharpest L1 lobe.
    Sh4 beam = vpl(glm::normalize(glm::dvec3(1, 1, 1)));
    for (size_t k = 1; k < 4; ++k)
        beam[k] *= 1.5;
    for (const Sh4& source : {vpl({0, 1, 0}), vpl(glm::normalize(glm::dvec3(1, 1, 1))), beam}) {
        Propagation r = propagate({8, 8, 8}, 1, nullptr, source);
        ASSERT_EQ(r.steps.size(), 1u);
        EXPECT_NEAR(flux(r.steps[0]) / source[0], 1.0, 0.02)
            << source[1] << " " << source[2] << " " << source[3];
    }
}

// Irradiance, in units of the VPL's flux over a cell's area, on a receiver `offset` cells from a
// unit-flux VPL along +y facing it, from the summed volume; and the truth, cos / (pi r^2).
struct Received {
    double lpv, truth;
};
Received received(const Propagation& r, glm::ivec3 at, glm::ivec3 offset) {
    glm::dvec3 w = glm::normalize(glm::dvec3(offset));
    double d2 = glm::dot(glm::dvec3(offset), glm::dvec3(offset));
    Sh4 lobe = cosineLobe(w); // a receiver facing the VPL integrates light travelling along w
    glm::ivec3 p = at + offset;
    double e = 0;
    for (size_t k = 0; k < 4; ++k)
        e += r.sum[cell(p.x, p.y, p.z) + k] * lobe[k];
    return {e, w.y / (M_PI * d2)};
}

TEST(GiPropagation, OneVplInEmptySpaceLightsItsSurroundingsAsTheInverseSquareLaw) {
    // A VPL facing +y near the bottom of an empty 16^3 volume, 12 steps; receivers 2-8 cells
    // away, head on and at 45 degrees. Kaplanyan-Dachsbacher's propagation (cosine lobes along
    // the face normals) gives 0.84 / 0.68 / 0.48 / 0.16 of the truth at 2 / 3 / 4 / 6 cells
    // after 16 steps: a diffusion, light reaching ~sqrt(steps) cells. Measured here (12 steps):
    // head on 1.37, 1.41, 1.23, 0.79, 0.40 at 2, 3, 4, 6, 8 cells; at 45 degrees 0.63, 0.60,
    // 0.52 at 2.8, 4.2, 5.7 cells (L1 cannot hold a lobe narrower than its own: the head-on
    // excess is the 45-degree deficit); and nothing beyond the steps taken.
    const glm::ivec3 at{8, 2, 8};
    Propagation r = propagate(at, 12, nullptr, vpl({0, 1, 0}));
    auto ratio = [&](glm::ivec3 o) {
        Received v = received(r, at, o);
        return v.lpv / v.truth;
    };
    for (int d : {2, 3, 4}) {
        EXPECT_GT(ratio({0, d, 0}), 0.9) << d;
        EXPECT_LT(ratio({0, d, 0}), 1.6) << d;
    }
    EXPECT_GT(ratio({0, 6, 0}), 0.6);
    EXPECT_GT(ratio({0, 8, 0}), 0.3);
    for (int d : {2, 3}) {
        EXPECT_GT(ratio({d, d, 0}), 0.5) << d;
        EXPECT_LT(ratio({d, d, 0}), 1.0) << d;
    }
    EXPECT_GT(ratio({4, 4, 0}), 0.4);
    EXPECT_EQ(r.sum[cell(8, 2 + 13, 8)], 0.0f); // 13 cells away: not reached in 12 steps
}

} // namespace
} // namespace pnb::player::test
