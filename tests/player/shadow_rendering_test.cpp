// Shadow maps on the GPU, checked against analytic ground truth: a ground plane and a box whose
// shadow footprint is known exactly (a ray from a ground point toward the sun hits the box or
// not). Pixels within a small band of the true shadow edge are not counted (filters soften it);
// every other ground pixel must be classified as the analysis says, within a stated fraction.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <epoxy/gl.h>
#include <epoxy/egl.h>

#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_player/gpu_scene.h"
#include "render_fixture.h"

namespace pnb::player::test {
namespace {

constexpr float kBoxHalf = 0.5f, kBoxHeight = 3.0f;

// Sun from `toward` (unit vector toward the light), a ground quad of `ground` half-size and a
// box [-0.5, 0.5] x [0, 3] x [-0.5, 0.5], all shifted by `offset`.
std::string shadowScene(glm::dvec3 toward, const std::string& name, gltf::Float3 offset = {0, 0, 0},
                        float ground = 20.0f) {
    gltf::Document doc;
    gltf::Material floor, boxMat;
    floor.name = "ground";
    floor.baseColorFactor = {0.8f, 0.8f, 0.8f, 1};
    boxMat.name = "box";
    boxMat.baseColorFactor = {0.8f, 0.3f, 0.2f, 1};
    doc.materials = {floor, boxMat};
    const gltf::Float4 flat{-0.70710678f, 0, 0, 0.70710678f};
    addObject(doc, "ground", quad(2 * ground, 2 * ground, 0), offset, flat);
    addObject(doc, "box", box(2 * kBoxHalf, kBoxHeight, 2 * kBoxHalf, 1),
              {offset[0], offset[1] + kBoxHeight / 2, offset[2]}, {0, 0, 0, 1});
    // Straight down is exactly a -90 degree turn about x (-Z onto -Y); lookRotation's helper
    // up vector would be parallel to it.
    addSun(doc, 3.0f,
           toward == glm::dvec3(0, 1, 0)
               ? gltf::Float4{-0.70710678f, 0, 0, 0.70710678f}
               : gltf::lookRotation({float(-toward.x), float(-toward.y), float(-toward.z)}));
    return convert(doc, name);
}

// Slab test: does the ray p + t d (t > 0) hit the box grown by `grow`?
bool rayHitsBox(glm::dvec3 p, glm::dvec3 d, double grow) {
    glm::dvec3 lo(-kBoxHalf - grow, -grow, -kBoxHalf - grow), hi(kBoxHalf + grow, kBoxHeight + grow, kBoxHalf + grow);
    double t0 = 1e-6, t1 = 1e30;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-12) {
            if (p[a] < lo[a] || p[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - p[a]) / d[a], tb = (hi[a] - p[a]) / d[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    return t0 <= t1;
}

struct ShadowCheck {
    uint64_t ground = 0, counted = 0, wrong = 0, shadowed = 0, trulyShadowed = 0;
    uint64_t uncovered = 0; // ground pixels beyond every cascade (capture: cascade -1)
    bool finite = true;
    double wrongFraction() const { return counted ? double(wrong) / double(counted) : 0.0; }
};

// Renders one frame and compares the sun visibility of every ground pixel with the analysis.
ShadowCheck checkShadows(const std::string& file, const CameraState& camera, RenderSettings settings,
                         glm::dvec3 toward, glm::dvec3 offset = glm::dvec3(0.0), double edgeBand = 0.08,
                         uint32_t w = 192, uint32_t h = 128) {
    ShadowCheck c;
    auto scene = loadScene(file);
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
    if (!scene.ok()) return c;
    auto renderer = Renderer::create(**scene, settings);
    EXPECT_TRUE(renderer.ok());
    if (!renderer.ok()) return c;
    EXPECT_TRUE((*renderer)->render(camera, w, h).ok());
    auto hdr = (*renderer)->capture(CaptureBuffer::Hdr);
    auto position = (*renderer)->capture(CaptureBuffer::Position);
    auto shadow = (*renderer)->capture(CaptureBuffer::Shadow);
    EXPECT_TRUE(hdr.ok() && position.ok() && shadow.ok());
    if (!hdr.ok() || !position.ok() || !shadow.ok()) return c;
    c.finite = allFinite(*hdr) && allFinite(*shadow);
    glm::dvec3 eye = (*renderer)->lastView().position;
    for (size_t i = 0; i < size_t(w) * h; ++i) {
        glm::dvec3 p(position->f32[i * 3], position->f32[i * 3 + 1], position->f32[i * 3 + 2]);
        if (!std::isfinite(p.x)) continue;
        p += eye - offset;
        if (std::abs(p.y) > 1e-3 * std::max(1.0, glm::length(p - (eye - offset)))) continue; // not ground
        float v = shadow->f32[i * 4];
        if (v < 0) continue; // facing away from the light
        ++c.ground;
        if (shadow->f32[i * 4 + 1] < 0) ++c.uncovered;
        bool inside = rayHitsBox(p, toward, -edgeBand), outside = !rayHitsBox(p, toward, edgeBand);
        if (v < 0.5f) ++c.shadowed;
        if (!inside && !outside) continue; // within the edge band
        ++c.counted;
        c.trulyShadowed += inside;
        if ((v < 0.5f) != inside) ++c.wrong;
    }
    return c;
}

const glm::dvec3 kSun = glm::normalize(glm::dvec3(-0.5, 0.8, 0.35));

CameraState overview(glm::dvec3 offset = glm::dvec3(0.0), float znear = 0.1f) {
    return lookAt(offset + glm::dvec3(5, 4, 7), offset + glm::dvec3(-1, 0, -0.5), znear);
}

RenderSettings shadowSettings(ShadowTechnique t, uint32_t cascades = 4, uint32_t resolution = 512) {
    RenderSettings s;
    s.shadowTechnique = t;
    s.shadowCascades = cascades;
    s.shadowResolution = resolution;
    return s;
}

TEST(ShadowRendering, EveryTechniqueCastsTheBoxShadowWhereItFalls) {
    std::string file = shadowScene(kSun, "box-sun");
    for (ShadowTechnique t : {ShadowTechnique::Single, ShadowTechnique::Lispsm, ShadowTechnique::Pssm,
                              ShadowTechnique::Sdsm}) {
        SCOPED_TRACE(int(t));
        ShadowCheck c = checkShadows(file, overview(), shadowSettings(t), kSun);
        EXPECT_TRUE(c.finite);
        EXPECT_GT(c.trulyShadowed, 150u) << "the camera sees the shadow";
        EXPECT_GT(c.shadowed, c.trulyShadowed / 2);
        EXPECT_LT(c.wrongFraction(), 0.01) << c.wrong << " of " << c.counted;
    }
}

// An orthographic camera: its view is a box, not a frustum. Every technique's cascades cover
// every ground pixel it sees (PSSM and SDSM split its depth range uniformly; LiSPSM falls back to
// the uniform fit, having no perspective to warp for), and the box's shadow falls where it does.
TEST(ShadowRendering, EveryTechniqueCoversAnOrthographicView) {
    std::string file = shadowScene(kSun, "box-ortho");
    CameraState ortho = lookAt({8, 10, 12}, {-1, 0, -0.5}, 0.5f, 60.0f);
    ortho.projection = Projection::Orthographic;
    ortho.ymag = 4.0f;
    for (ShadowTechnique t : {ShadowTechnique::Single, ShadowTechnique::Lispsm, ShadowTechnique::Pssm,
                              ShadowTechnique::Sdsm}) {
        SCOPED_TRACE(int(t));
        ShadowCheck c = checkShadows(file, ortho, shadowSettings(t), kSun);
        EXPECT_TRUE(c.finite);
        EXPECT_GT(c.ground, 5000u);
        EXPECT_EQ(c.uncovered, 0u) << "of " << c.ground;
        EXPECT_GT(c.trulyShadowed, 150u) << "the camera sees the shadow";
        EXPECT_GT(c.shadowed, c.trulyShadowed / 2);
        EXPECT_LT(c.wrongFraction(), 0.01) << c.wrong << " of " << c.counted;
    }
}

TEST(ShadowRendering, ShadowsOffMeansLitEverywhere) {
    std::string file = shadowScene(kSun, "box-off");
    ShadowCheck c = checkShadows(file, overview(), shadowSettings(ShadowTechnique::Off), kSun);
    EXPECT_EQ(c.shadowed, 0u);
    EXPECT_GT(c.ground, 1000u);
}

// receives_shadows = false on a deferred material (a flag bit in the G-buffer) lights it as if
// shadows were off, while the scene's shadows stay on for everything else.
TEST(ShadowRendering, DeferredMaterialThatDoesNotReceiveIsLitAsWithShadowsOff) {
    std::string file = shadowScene(kSun, "box-receive");
    auto container = Container::open(file);
    ASSERT_TRUE(container.ok());
    auto decoded = readScene(*container);
    ASSERT_TRUE(decoded.ok()) << decoded.error().describe();
    Scene edited = std::move(*decoded);
    bool found = false;
    for (Material& m : edited.materials)
        if (edited.str(m.name) == "ground") {
            ASSERT_EQ(m.shadingPath, ShadingPath::Deferred);
            m.receivesShadows = false;
            found = true;
        }
    ASSERT_TRUE(found);

    constexpr uint32_t w = 160, h = 112;
    struct Frame {
        CapturedImage hdr, position;
    };
    auto render = [&](GpuScene& scene, ShadowTechnique t) {
        Frame f;
        auto renderer = Renderer::create(scene, shadowSettings(t));
        EXPECT_TRUE(renderer.ok());
        if (!renderer.ok()) return f;
        EXPECT_TRUE((*renderer)->render(overview(), w, h).ok());
        auto hdr = (*renderer)->capture(CaptureBuffer::Hdr);
        auto position = (*renderer)->capture(CaptureBuffer::Position);
        EXPECT_TRUE(hdr.ok() && position.ok());
        if (hdr.ok() && position.ok()) f = {std::move(*hdr), std::move(*position)};
        return f;
    };
    auto original = loadScene(file);
    ASSERT_TRUE(original.ok());
    auto notReceiving = uploadScene(edited);
    ASSERT_TRUE(notReceiving.ok()) << notReceiving.error().message;
    Frame on = render(**original, ShadowTechnique::Pssm);
    Frame off = render(**original, ShadowTechnique::Off);
    Frame flagged = render(**notReceiving, ShadowTechnique::Pssm);
    ASSERT_FALSE(on.hdr.f32.empty() || off.hdr.f32.empty() || flagged.hdr.f32.empty());

    uint64_t ground = 0, shadowedOnGround = 0, flaggedDiffers = 0;
    for (size_t i = 0; i < size_t(w) * h; ++i) {
        float y = on.position.f32[i * 3 + 1] + float(overview().position.y);
        if (!std::isfinite(y) || std::abs(y) > 1e-3f) continue; // ground pixels only
        ++ground;
        float lOn = on.hdr.f32[i * 4], lOff = off.hdr.f32[i * 4], lFlag = flagged.hdr.f32[i * 4];
        shadowedOnGround += lOn < 0.8f * lOff;
        flaggedDiffers += std::abs(lFlag - lOff) > 1e-3f * std::max(1.0f, lOff);
    }
    EXPECT_GT(ground, 1000u);
    EXPECT_GT(shadowedOnGround, 150u) << "the box's shadow falls on the ground";
    EXPECT_EQ(flaggedDiffers, 0u) << "of " << ground << " ground pixels";
}

TEST(ShadowRendering, EveryFilterAndSelectionAgreesWithTheAnalysis) {
    std::string file = shadowScene(kSun, "box-filters");
    for (ShadowFilter filter : {ShadowFilter::Hardware, ShadowFilter::Poisson, ShadowFilter::Pcss}) {
        for (CascadeSelect select : {CascadeSelect::Depth, CascadeSelect::Bounds}) {
            for (CascadeFit fit : {CascadeFit::Sphere, CascadeFit::Tight}) {
                SCOPED_TRACE(std::to_string(int(filter)) + " " + std::to_string(int(select)) + " " +
                             std::to_string(int(fit)));
                RenderSettings s = shadowSettings(ShadowTechnique::Pssm);
                s.shadowFilter = filter;
                s.shadowSelect = select;
                s.shadowFit = fit;
                ShadowCheck c = checkShadows(file, overview(), s, kSun, glm::dvec3(0.0), 0.12);
                EXPECT_TRUE(c.finite);
                EXPECT_LT(c.wrongFraction(), 0.01) << c.wrong << " of " << c.counted;
            }
        }
    }
}

// Every combination of the extremes: shadows present, nothing NaN, error bounded.
TEST(ShadowRendering, ExtremesKeepShadowsFiniteAndRight) {
    struct Case {
        const char* name;
        glm::dvec3 toward;
        CameraState camera;
        RenderSettings settings;
        glm::dvec3 offset{0.0};
        double bound = 0.01;
    };
    const double grazing = 89.9 * M_PI / 180.0;
    glm::dvec3 lowSun = glm::normalize(glm::dvec3(std::sin(grazing) * 0.6, std::cos(grazing), std::sin(grazing) * 0.8));
    std::vector<Case> cases;
    for (ShadowTechnique t : {ShadowTechnique::Pssm, ShadowTechnique::Sdsm, ShadowTechnique::Lispsm}) {
        RenderSettings s = shadowSettings(t);
        // Straight down: the light's up vector is degenerate.
        cases.push_back({"straight down", {0, 1, 0}, lookAt({3, 4, 5}, {0, 0.5, 0}), s});
        // Looking along the light (down onto the box from above, sun behind the camera).
        cases.push_back({"view along light", {0, 1, 0}, lookAt({0.01, 9, 0.02}, {0, 0, 0}), s});
        // Looking into the light.
        cases.push_back({"view into light", kSun, lookAt(glm::dvec3(-4, 0.5, -3) - kSun * 2.0, glm::dvec3(-4, 0.5, -3) + kSun * 5.0), s});
        // Near/far ratio 1e-5 (near 1e-4, far 10).
        RenderSettings nearFar = s;
        nearFar.nearPlane = 1e-4f;
        nearFar.farPlane = 10.0f;
        cases.push_back({"near/far 1e-5", kSun, overview(), nearFar});
    }
    for (uint32_t m : {1u, 8u})
        for (float lambda : {0.0f, 1.0f}) {
            RenderSettings s = shadowSettings(ShadowTechnique::Pssm, m);
            s.shadowLambda = lambda;
            cases.push_back({"pssm m/lambda", kSun, overview(), s});
        }
    RenderSettings quantile = shadowSettings(ShadowTechnique::Sdsm, 8);
    quantile.sdsmPartition = SdsmPartition::Quantile;
    cases.push_back({"sdsm quantile 8", kSun, overview(), quantile});
    std::string file = shadowScene(kSun, "box-extremes");
    std::string down = shadowScene({0, 1, 0}, "box-down");
    for (const Case& k : cases) {
        SCOPED_TRACE(std::string(k.name) + " technique " + std::to_string(int(k.settings.shadowTechnique)) +
                     " m " + std::to_string(k.settings.shadowCascades));
        ShadowCheck c = checkShadows(k.toward.y == 1 ? down : file, k.camera, k.settings, k.toward);
        EXPECT_TRUE(c.finite);
        EXPECT_LT(c.wrongFraction(), k.bound) << c.wrong << " of " << c.counted;
        if (c.trulyShadowed > 50) {
            EXPECT_GT(c.shadowed, 0u) << "shadows disappeared";
        }
    }
    // The sun 89.9 degrees from the zenith: the ground is lit almost edge-on; it must not
    // shadow itself (acne) — every ground pixel outside the (very long) box shadow stays lit.
    std::string grazingFile = shadowScene(lowSun, "box-grazing", {0, 0, 0}, 60.0f);
    for (ShadowTechnique t : {ShadowTechnique::Pssm, ShadowTechnique::Sdsm}) {
        ShadowCheck c = checkShadows(grazingFile, lookAt({6, 2, 6}, {0, 0, 0}), shadowSettings(t), lowSun);
        EXPECT_TRUE(c.finite);
        EXPECT_GT(c.counted, 1000u);
        EXPECT_LT(c.wrongFraction(), 0.02) << c.wrong << " of " << c.counted;
    }
}

TEST(ShadowRendering, FarFromTheOriginMatchesTheOrigin) {
    const gltf::Float3 far{1.0e6f, 0, -1.0e6f};
    glm::dvec3 offset(far[0], far[1], far[2]);
    std::string file = shadowScene(kSun, "box-far", far);
    for (ShadowTechnique t : {ShadowTechnique::Pssm, ShadowTechnique::Sdsm}) {
        ShadowCheck c = checkShadows(file, overview(offset), shadowSettings(t), kSun, offset);
        EXPECT_TRUE(c.finite);
        EXPECT_GT(c.trulyShadowed, 150u);
        EXPECT_LT(c.wrongFraction(), 0.01) << c.wrong << " of " << c.counted;
    }
}

TEST(ShadowRendering, SdsmWithAnEmptyOrOnePixelDepthBufferStaysFinite) {
    std::string file = shadowScene(kSun, "box-sky");
    for (CameraState cam : {lookAt({0, 2, 0}, {0, 50, 1}),           // sky only
                            lookAt({0, 2, 400}, {0, 1.5, 0})}) {      // the box is a pixel or two
        ShadowCheck c = checkShadows(file, cam, shadowSettings(ShadowTechnique::Sdsm), kSun, glm::dvec3(0.0),
                                     0.08, 96, 64);
        EXPECT_TRUE(c.finite);
        EXPECT_EQ(c.wrong, 0u);
    }
}

TEST(ShadowRendering, SdsmBoundsContainEverySample) {
    // Selection by bounds takes the first cascade whose map contains the point: a sample outside
    // every SDSM cascade would report cascade -1.
    std::string file = shadowScene(kSun, "box-bounds");
    RenderSettings s = shadowSettings(ShadowTechnique::Sdsm);
    s.shadowSelect = CascadeSelect::Bounds;
    s.shadowBlend = 0;
    auto scene = loadScene(file);
    ASSERT_TRUE(scene.ok());
    auto renderer = Renderer::create(**scene, s);
    ASSERT_TRUE(renderer.ok());
    for (CameraState cam : {overview(), lookAt({1, 1.5, 9}, {0, 1, 0}), lookAt({12, 6, 2}, {0, 0, 0})}) {
        ASSERT_TRUE((*renderer)->render(cam, 128, 96).ok());
        auto shadow = (*renderer)->capture(CaptureBuffer::Shadow);
        ASSERT_TRUE(shadow.ok());
        size_t samples = 0, outside = 0;
        for (size_t i = 0; i < shadow->f32.size(); i += 4) {
            if (shadow->f32[i] < 0) continue;          // no geometry / facing away
            ++samples;
            outside += shadow->f32[i + 1] < 0;
        }
        EXPECT_GT(samples, 1000u);
        EXPECT_EQ(outside, 0u);
    }
}

TEST(ShadowRendering, GeometryShaderLayersDrawTheSameMaps) {
    // The fallback for drivers without ARB_shader_viewport_layer_array, forced here.
    std::string file = shadowScene(kSun, "box-geometry-layers");
    for (ShadowTechnique t : {ShadowTechnique::Pssm, ShadowTechnique::Sdsm}) {
        RenderSettings vertex = shadowSettings(t), geometry = vertex;
        geometry.shadowLayerSource = LayerSource::Geometry;
        Rendered a = render(file, overview(), 160, 120, vertex);
        Rendered b = render(file, overview(), 160, 120, geometry);
        EXPECT_EQ(compareRgba8(a.color, b.color).maxAbs, 0);
        EXPECT_EQ(a.stats.shadowDraws, b.stats.shadowDraws);
        ShadowCheck c = checkShadows(file, overview(), geometry, kSun);
        EXPECT_GT(c.trulyShadowed, 150u);
        EXPECT_LT(c.wrongFraction(), 0.01);
    }
}

TEST(ShadowRendering, LayeredDrawsTheSameMapsWithFewerDraws) {
    std::string file = shadowScene(kSun, "box-layered");
    for (ShadowTechnique t : {ShadowTechnique::Pssm, ShadowTechnique::Sdsm}) {
        RenderSettings layered = shadowSettings(t), multi = layered;
        multi.shadowRender = ShadowRender::MultiPass;
        Rendered a = render(file, overview(), 160, 120, layered);
        Rendered b = render(file, overview(), 160, 120, multi);
        EXPECT_EQ(compareRgba8(a.color, b.color).maxAbs, 0);
        EXPECT_GT(a.stats.shadowDraws, 0u);
        EXPECT_LT(a.stats.shadowDraws, b.stats.shadowDraws);
        if (t == ShadowTechnique::Pssm) {
            EXPECT_EQ(a.stats.shadowTriangles, b.stats.shadowTriangles);
        }
        EXPECT_EQ(a.memory.shadowMapBytes, 4ull * 512 * 512 * 4); // D32F x 4 cascades
    }
}

// --- No GPU->CPU read-back in the SDSM frame loop: every GL entry point that returns GPU data
// or waits for the GPU is wrapped (libepoxy dispatches through replaceable pointers) and counted.
int gReadbacks = 0;
PFNGLGETNAMEDBUFFERSUBDATAPROC gGetNamedBufferSubData;
PFNGLGETBUFFERSUBDATAPROC gGetBufferSubData;
PFNGLMAPNAMEDBUFFERRANGEPROC gMapNamedBufferRange;
PFNGLMAPBUFFERRANGEPROC gMapBufferRange;
PFNGLREADPIXELSPROC gReadPixels;
PFNGLGETTEXTUREIMAGEPROC gGetTextureImage;
PFNGLFINISHPROC gFinish;
void APIENTRY countGetNamedBufferSubData(GLuint a, GLintptr b, GLsizeiptr c, void* d) { ++gReadbacks; gGetNamedBufferSubData(a, b, c, d); }
void APIENTRY countGetBufferSubData(GLenum a, GLintptr b, GLsizeiptr c, void* d) { ++gReadbacks; gGetBufferSubData(a, b, c, d); }
void* APIENTRY countMapNamedBufferRange(GLuint a, GLintptr b, GLsizeiptr c, GLbitfield d) { if (d & GL_MAP_READ_BIT) ++gReadbacks; return gMapNamedBufferRange(a, b, c, d); }
void* APIENTRY countMapBufferRange(GLenum a, GLintptr b, GLsizeiptr c, GLbitfield d) { if (d & GL_MAP_READ_BIT) ++gReadbacks; return gMapBufferRange(a, b, c, d); }
void APIENTRY countReadPixels(GLint a, GLint b, GLsizei c, GLsizei d, GLenum e, GLenum f, void* g) { ++gReadbacks; gReadPixels(a, b, c, d, e, f, g); }
void APIENTRY countGetTextureImage(GLuint a, GLint b, GLenum c, GLenum d, GLsizei e, void* f) { ++gReadbacks; gGetTextureImage(a, b, c, d, e, f); }
void APIENTRY countFinish() { ++gReadbacks; gFinish(); }

TEST(ShadowRendering, SdsmFrameLoopReadsNothingBack) {
    std::string file = shadowScene(kSun, "box-readback");
    auto scene = loadScene(file);
    ASSERT_TRUE(scene.ok());
    auto renderer = Renderer::create(**scene, shadowSettings(ShadowTechnique::Sdsm));
    ASSERT_TRUE(renderer.ok());
    ASSERT_TRUE((*renderer)->render(overview(), 128, 96).ok()); // first frame: allocations
    // The driver's own entry points (epoxy's pointers may still be lazy-resolving stubs).
    auto real = [](const char* name) { return eglGetProcAddress(name); };
    gGetNamedBufferSubData = reinterpret_cast<PFNGLGETNAMEDBUFFERSUBDATAPROC>(real("glGetNamedBufferSubData"));
    gGetBufferSubData = reinterpret_cast<PFNGLGETBUFFERSUBDATAPROC>(real("glGetBufferSubData"));
    gMapNamedBufferRange = reinterpret_cast<PFNGLMAPNAMEDBUFFERRANGEPROC>(real("glMapNamedBufferRange"));
    gMapBufferRange = reinterpret_cast<PFNGLMAPBUFFERRANGEPROC>(real("glMapBufferRange"));
    gReadPixels = reinterpret_cast<PFNGLREADPIXELSPROC>(real("glReadPixels"));
    gGetTextureImage = reinterpret_cast<PFNGLGETTEXTUREIMAGEPROC>(real("glGetTextureImage"));
    gFinish = reinterpret_cast<PFNGLFINISHPROC>(real("glFinish"));
    ASSERT_TRUE(gGetNamedBufferSubData && gGetBufferSubData && gMapNamedBufferRange && gMapBufferRange &&
                gReadPixels && gGetTextureImage && gFinish);
    epoxy_glGetNamedBufferSubData = countGetNamedBufferSubData;
    epoxy_glGetBufferSubData = countGetBufferSubData;
    epoxy_glMapNamedBufferRange = countMapNamedBufferRange;
    epoxy_glMapBufferRange = countMapBufferRange;
    epoxy_glReadPixels = countReadPixels;
    epoxy_glGetTextureImage = countGetTextureImage;
    epoxy_glFinish = countFinish;
    gReadbacks = 0;
    for (int k = 0; k < 6; ++k) {
        CameraState cam = lookAt({5 - k * 0.3, 4, 7}, {-1, 0, -0.5});
        EXPECT_TRUE((*renderer)->render(cam, 128, 96).ok());
    }
    int inLoop = gReadbacks;
    auto shadow = (*renderer)->capture(CaptureBuffer::Shadow); // a capture does read back
    int withCapture = gReadbacks;
    epoxy_glGetNamedBufferSubData = gGetNamedBufferSubData;
    epoxy_glGetBufferSubData = gGetBufferSubData;
    epoxy_glMapNamedBufferRange = gMapNamedBufferRange;
    epoxy_glMapBufferRange = gMapBufferRange;
    epoxy_glReadPixels = gReadPixels;
    epoxy_glGetTextureImage = gGetTextureImage;
    epoxy_glFinish = gFinish;
    EXPECT_EQ(inLoop, 0);
    EXPECT_GT(withCapture, 0) << "the counting wrappers were not reached";
    ASSERT_TRUE(shadow.ok());
    size_t shadowed = 0;
    for (size_t i = 0; i < shadow->f32.size(); i += 4) shadowed += shadow->f32[i] >= 0 && shadow->f32[i] < 0.5f;
    EXPECT_GT(shadowed, 100u);
}

} // namespace
} // namespace pnb::player::test
