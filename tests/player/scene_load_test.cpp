// Loading real containers: every procedural scene loads, compiles and renders; damaged files and
// broken shaders give errors that name what and where; golden images; culling; debug views;
// the benchmark harness.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "pnb/scene.h"
#include "pnb/writer.h"
#include "pnb_player/benchmark.h"
#include "pnb_player/gpu_scene.h"
#include "gl/gl_allocation.h"
#include "render_fixture.h"

namespace pnb::player::test {

namespace {

std::string scenePath(const std::string& name) { return std::string(PNB_SCENE_DIR) + "/" + name + ".pnb"; }

std::vector<std::byte> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
    std::vector<std::byte> out(bytes.size());
    std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
}

std::string writeTemp(const std::string& name, std::span<const std::byte> bytes) {
    auto path = std::filesystem::temp_directory_path() / ("pnb-load-test-" + std::to_string(::getpid()) + "-" + name);
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return path.string();
}

struct Loaded { // a scene and a renderer for it
    std::unique_ptr<GpuScene> scene;
    std::unique_ptr<Renderer> renderer;
};

Loaded load(const std::string& path, const RenderSettings& settings = {}) {
    Loaded l;
    auto s = loadScene(path);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    if (!s.ok()) return l;
    l.scene = std::move(*s);
    auto r = Renderer::create(*l.scene, settings);
    EXPECT_TRUE(r.ok());
    if (r.ok()) l.renderer = std::move(*r);
    return l;
}

} // namespace

TEST(SceneLoad, EveryProceduralSceneLoadsCompilesAndRendersFinite) {
    for (const char* name : {"box-room", "street-canyon", "flat-city", "terrain", "grazing-plane"}) {
        SCOPED_TRACE(name);
        LoadStats stats;
        auto scene = loadScene(scenePath(name), {}, &stats);
        ASSERT_TRUE(scene.ok()) << scene.error().message;
        EXPECT_GT((*scene)->items.size(), 0u);
        EXPECT_GT(stats.zeroCopyBytes, 0u);
        EXPECT_LE(stats.readMs + stats.decodeMs + stats.uploadMs + stats.openMs, stats.totalMs + 0.01);
        // Every program a material uses was compiled; nothing else that the frame does not need.
        for (const GpuMaterial& m : (*scene)->materials) EXPECT_TRUE(bool((*scene)->programs[m.program]));
        auto renderer = Renderer::create(**scene, {});
        ASSERT_TRUE(renderer.ok());
        ASSERT_TRUE((*renderer)->render(initialCamera(**scene, ""), 128, 96).ok());
        auto hdr = (*renderer)->capture(CaptureBuffer::Hdr);
        ASSERT_TRUE(hdr.ok());
        EXPECT_TRUE(allFinite(*hdr));
        EXPECT_GT((*renderer)->lastFrame().drawCalls, 0u);
    }
}

TEST(SceneLoad, DamagedContainersAreRejectedWithWhatAndWhere) {
    std::vector<std::byte> bytes = readFile(scenePath("street-canyon"));
    ASSERT_FALSE(bytes.empty());
    auto container = Container::fromMemory(bytes);
    ASSERT_TRUE(container.ok());
    const ChunkInfo* mesh = container->findFirst(tags::kMesh);
    ASSERT_NE(mesh, nullptr);
    uint64_t where = mesh->payloadOffset + mesh->header.storedSize / 2;
    std::vector<std::byte> flipped = bytes;
    flipped[where] ^= std::byte{0x40};
    auto r = loadScene(writeTemp("flipped.pnb", flipped));
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, PlayErrorKind::Input);
    EXPECT_NE(r.error().message.find("checksum"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("MESH"), std::string::npos) << r.error().message;

    std::vector<std::byte> truncated(bytes.begin(), bytes.begin() + std::ptrdiff_t(bytes.size() / 2));
    auto t = loadScene(writeTemp("truncated.pnb", truncated));
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().kind, PlayErrorKind::Input);
    auto missing = loadScene("/nonexistent/scene.pnb");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("/nonexistent/scene.pnb"), std::string::npos);
}

// Another program truncates the file between open and read (pnb-play used to die of SIGBUS):
// a clean Input error naming the file.
TEST(SceneLoad, FileTruncatedWhileMappedIsAnErrorNamingItNotASignal) {
    const std::string path = writeTemp("shrinking.pnb", readFile(scenePath("street-canyon")));
    LoadOptions options;
    options.afterOpen = [&] { ASSERT_EQ(::truncate(path.c_str(), 8192), 0); };
    auto r = loadScene(path, options);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, PlayErrorKind::Input);
    EXPECT_NE(r.error().message.find(path), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("shrank while it was being read"), std::string::npos)
        << r.error().message;
    std::filesystem::remove(path);
}

TEST(SceneLoad, ShaderCompileErrorNamesProgramPermutationFileAndLine) {
    std::vector<std::byte> bytes = readFile(scenePath("box-room"));
    auto container = Container::fromMemory(bytes);
    ASSERT_TRUE(container.ok());
    auto scene = readScene(*container);
    ASSERT_TRUE(scene.ok());
    // Break the gbuffer fragment stage at a known line of gbuffer.frag.
    std::string broken;
    size_t brokenLine = 0;
    for (ShaderSource& s : scene->shaders) {
        if (scene->str(s.name) != "gbuffer.frag") continue;
        std::string text(reinterpret_cast<const char*>(s.source.data()), s.source.size());
        size_t at = text.find("    outEmissive = s.emissive;");
        ASSERT_NE(at, std::string::npos);
        text.insert(at, "    this is not glsl;\n");
        // Its line in gbuffer.frag: the last "#line N 0" before it, plus the lines since.
        size_t directive = text.rfind("\n#line ", at);
        ASSERT_NE(directive, std::string::npos);
        size_t after = text.find('\n', directive + 1) + 1;
        brokenLine = std::stoul(text.substr(directive + 7)) +
                     size_t(std::count(text.begin() + std::ptrdiff_t(after),
                                       text.begin() + std::ptrdiff_t(at), '\n'));
        broken = text;
        s.source = {reinterpret_cast<const std::byte*>(broken.data()), broken.size()};
    }
    ASSERT_FALSE(broken.empty());
    std::vector<std::byte> out;
    Writer w = Writer::toMemory(&out);
    ASSERT_TRUE(isOk(writeScene(w, *scene)));
    ASSERT_TRUE(isOk(w.commit()));
    auto r = loadScene(writeTemp("broken-shader.pnb", out));
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, PlayErrorKind::Gl);
    const std::string& m = r.error().message;
    EXPECT_NE(m.find("program gbuffer["), std::string::npos) << m;
    EXPECT_NE(m.find("(PROG "), std::string::npos) << m;
    EXPECT_NE(m.find("fragment stage"), std::string::npos) << m;
    EXPECT_NE(m.find("gbuffer.frag:" + std::to_string(brokenLine) + "("), std::string::npos)
        << m; // the inserted line
}

TEST(SceneLoad, FrustumCullingChangesDrawsNotPixels) {
    Loaded culled = load(scenePath("street-canyon"));
    RenderSettings noCull;
    noCull.frustumCulling = false;
    Loaded all = load(scenePath("street-canyon"), noCull);
    ASSERT_TRUE(culled.renderer && all.renderer);
    // Looking down the street from its start: the far end is out of view.
    CameraState cam = initialCamera(*culled.scene, "");
    ASSERT_TRUE(culled.renderer->render(cam, 128, 96).ok());
    ASSERT_TRUE(all.renderer->render(cam, 128, 96).ok());
    EXPECT_EQ(all.renderer->lastFrame().culledItems, 0u);
    EXPECT_LE(culled.renderer->lastFrame().drawCalls, all.renderer->lastFrame().drawCalls);
    auto a = culled.renderer->capture(CaptureBuffer::Color), b = all.renderer->capture(CaptureBuffer::Color);
    ImageDiff d = compareRgba8(*a, *b);
    EXPECT_EQ(d.maxAbs, 0);
    // And from above the scene, looking away from it, everything is culled.
    CameraState away = lookAt({0, 500, 0}, {0, 1000, 1});
    ASSERT_TRUE(culled.renderer->render(away, 64, 48).ok());
    EXPECT_EQ(culled.renderer->lastFrame().drawCalls, 0u);
}

TEST(SceneLoad, DebugViewsShowTheirBuffers) {
    Loaded l = load(scenePath("box-room"));
    ASSERT_TRUE(l.renderer);
    CameraState cam = initialCamera(*l.scene, "");
    ASSERT_TRUE(l.renderer->render(cam, 96, 64).ok());
    auto lit = l.renderer->capture(CaptureBuffer::Color);
    for (int v = 1; v < int(DebugView::Count); ++v) {
        SCOPED_TRACE(std::string(toString(DebugView(v))));
        // GI's views need a container with GI (tests/player/gi_test.cpp).
        if (DebugView(v) >= DebugView::GiIndirect && DebugView(v) <= DebugView::GiVolume) continue;
        RenderSettings s;
        s.debugView = DebugView(v);
        l.renderer->setSettings(s);
        ASSERT_TRUE(l.renderer->render(cam, 96, 64).ok());
        auto img = l.renderer->capture(CaptureBuffer::Color);
        ASSERT_TRUE(img.ok());
        EXPECT_GT(compareRgba8(*lit, *img).meanAbs, 1.0); // it shows something else
        // box-room has no metals and no emitters: those two views are black, the rest not.
        if (DebugView(v) == DebugView::Metallic || DebugView(v) == DebugView::Emissive) continue;
        size_t nonBlack = 0;
        for (size_t i = 0; i < img->u8.size(); i += 4) nonBlack += img->u8[i] + img->u8[i + 1] + img->u8[i + 2] > 0;
        EXPECT_GT(nonBlack, img->u8.size() / 4 / 10);
    }
    RenderSettings off;
    l.renderer->setSettings(off);
    ASSERT_TRUE(l.renderer->render(cam, 96, 64).ok());
    EXPECT_EQ(l.renderer->targetMemory().debugBytes, 0u); // debug targets released
}

TEST(SceneLoad, GoldenImages) {
    // Tolerance stable on llvmpipe: at most 0.5 % of pixels off by more than 8/255 and a mean
    // error below 0.5/255. PNB_UPDATE_GOLDEN=1 rewrites the files in the source tree.
    for (const char* name : {"box-room", "street-canyon", "grazing-plane"}) {
        SCOPED_TRACE(name);
        Loaded l = load(scenePath(name));
        ASSERT_TRUE(l.renderer);
        ASSERT_FALSE(l.scene->cameras.empty());
        // The scenes' own first camera (street level in street-canyon), not the generated orbit.
        ASSERT_TRUE(l.renderer->render(sceneCamera(*l.scene, 0), 160, 120).ok());
        auto img = l.renderer->capture(CaptureBuffer::Color);
        ASSERT_TRUE(img.ok());
        std::string golden = std::string(PNB_GOLDEN_DIR) + "/" + name + ".png";
        if (std::getenv("PNB_UPDATE_GOLDEN")) {
            ASSERT_TRUE(saveCapture(golden, *img).ok());
            continue;
        }
        auto in = OIIO::ImageInput::open(golden);
        ASSERT_TRUE(in) << "missing " << golden << " (run with PNB_UPDATE_GOLDEN=1)";
        const OIIO::ImageSpec& spec = in->spec();
        ASSERT_EQ(spec.width, 160);
        ASSERT_EQ(spec.height, 120);
        ASSERT_EQ(spec.nchannels, 4);
        std::vector<uint8_t> pixels(160 * 120 * 4);
        ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, pixels.data()));
        // The capture is bottom-up; the PNG top-down.
        CapturedImage expected = *img;
        for (uint32_t y = 0; y < 120; ++y)
            std::memcpy(expected.u8.data() + size_t(119 - y) * 160 * 4, pixels.data() + size_t(y) * 160 * 4, 160 * 4);
        ImageDiff d = compareRgba8(expected, *img);
        EXPECT_LE(d.fractionOver(8), 0.005) << "mean " << d.meanAbs;
        EXPECT_LT(d.meanAbs, 0.5);
    }
}

TEST(Benchmark, FixedStepRunsAreDeterministicAndWriteTheirFiles) {
    Loaded l = load(scenePath("street-canyon"));
    ASSERT_TRUE(l.renderer);
    auto dir = std::filesystem::temp_directory_path() / ("pnb-bench-test-" + std::to_string(::getpid()));
    BenchOptions o;
    o.frames = 8;
    o.fixedDt = true;
    o.width = 96;
    o.height = 64;
    o.plot = false;
    o.outDir = (dir / "a").string();
    o.captures = {{CaptureBuffer::Color, 5, (dir / "a5.png").string()},
                  {CaptureBuffer::Depth, 5, (dir / "a5_depth.exr").string()}};
    LoadStats load;
    GlInfo gl;
    auto a = runBenchmark(*l.scene, *l.renderer, o, load, gl);
    ASSERT_TRUE(a.ok()) << a.error().message;
    EXPECT_EQ(a->frames, 8u);
    o.outDir = (dir / "b").string();
    o.captures = {{CaptureBuffer::Color, 5, (dir / "b5.png").string()}};
    auto b = runBenchmark(*l.scene, *l.renderer, o, load, gl);
    ASSERT_TRUE(b.ok());
    auto bytesA = readFile((dir / "a5.png").string()), bytesB = readFile((dir / "b5.png").string());
    EXPECT_FALSE(bytesA.empty());
    EXPECT_EQ(bytesA, bytesB); // same frame, same image
    EXPECT_TRUE(std::filesystem::exists(dir / "a5_depth.exr"));

    std::ifstream csv(dir / "a" / "frames.csv");
    std::string header, line;
    std::getline(csv, header);
    EXPECT_EQ(header.rfind("frame,time_s,cpu_ms,gpu_total_ms,", 0), 0u);
    int rows = 0;
    while (std::getline(csv, line)) {
        ++rows;
        EXPECT_EQ(std::count(line.begin(), line.end(), ','), std::count(header.begin(), header.end(), ','));
    }
    EXPECT_EQ(rows, 8);
    auto summary = nlohmann::json::parse(std::ifstream(dir / "a" / "summary.json"));
    EXPECT_EQ(summary["run"]["frames"], 8);
    EXPECT_GT(summary["gpu_ms"]["total"]["median_ms"].get<double>(), 0.0);
    EXPECT_GE(summary["gpu_ms"]["total"]["p95_ms"].get<double>(), summary["gpu_ms"]["total"]["median_ms"].get<double>());
    EXPECT_TRUE(summary["settings"].contains("lighting.exposure"));
    EXPECT_GT(summary["gpu_memory_bytes"]["meshes"].get<uint64_t>(), 0u);
    EXPECT_EQ(summary["run"]["timer_stalls"], 0);
    std::filesystem::remove_all(dir);
}

} // namespace pnb::player::test

namespace pnb::player::test {

TEST(SceneLoad, FxaaSoftensEdgesOnly) {
    Loaded plain = load(scenePath("box-room"));
    RenderSettings s;
    s.fxaa = true;
    Loaded fxaa = load(scenePath("box-room"), s);
    ASSERT_TRUE(plain.renderer && fxaa.renderer);
    CameraState cam = sceneCamera(*plain.scene, 0);
    ASSERT_TRUE(plain.renderer->render(cam, 160, 120).ok());
    ASSERT_TRUE(fxaa.renderer->render(cam, 160, 120).ok());
    ImageDiff d = compareRgba8(*plain.renderer->capture(CaptureBuffer::Color),
                               *fxaa.renderer->capture(CaptureBuffer::Color));
    EXPECT_GT(d.fractionOver(4), 0.002); // edges changed
    EXPECT_LT(d.fractionOver(4), 0.15);  // flat regions did not
    EXPECT_EQ(fxaa.renderer->targetMemory().outputBytes, 2u * 4 * 160 * 120);
    EXPECT_EQ(plain.renderer->targetMemory().outputBytes, 1u * 4 * 160 * 120);
}

// gl_allocation.h: storage the GL refuses (GL_OUT_OF_MEMORY, which llvmpipe sets for a 64 TiB
// buffer) is an error naming what was being made, not a buffer without storage written later.
TEST(GlAllocation, AnAllocationTheGlRefusesIsAnErrorNamingIt) {
    GlHandle refused = createBuffer();
    clearGlErrors();
    glNamedBufferStorage(refused.id(), GLsizeiptr(1) << 46, nullptr, 0);
    auto r = checkGlAllocation("a test buffer", uint64_t(1) << 46);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, PlayErrorKind::Gl);
    EXPECT_NE(r.error().message.find("could not allocate a test buffer (67108864 MiB)"),
              std::string::npos)
        << r.error().message;
    GlHandle fine = createBuffer();
    clearGlErrors();
    glNamedBufferStorage(fine.id(), 1 << 20, nullptr, 0);
    EXPECT_TRUE(checkGlAllocation("a 1 MiB buffer", 1 << 20).ok());
}

} // namespace pnb::player::test
