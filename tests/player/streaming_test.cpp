// Streaming playback (pnb_player/scene_stream.h) against the full load: the finished stream draws
// the same image, frames drawn while streaming are finite, the texture budget is never exceeded
// and the image converges where it suffices, damage met mid-stream stops cleanly with the chunk
// and its offset, and a pipe streams like a file.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "gl/gl_debug.h"
#include "pnb/reader.h"
#include "pnb_player/scene_stream.h"
#include "render_fixture.h"

namespace pnb::player::test {

namespace {

constexpr uint32_t kW = 160, kH = 120;

// Eight 256^2 checker textures on eight 2x2 quads along -Z, alternating left and right.
const std::string& texturedStreet() {
    static const std::string path = [] {
        gltf::Document doc;
        doc.sceneName = "textured-street";
        for (uint8_t i = 0; i < 8; ++i) {
            doc.images.push_back({"checker" + std::to_string(i),
                                  pnb::test::checkerPng(256, {uint8_t(40 + 25 * i), 200, uint8_t(220 - 20 * i)},
                                                        {30, uint8_t(30 + 20 * i), 60})});
            gltf::Material m;
            m.name = "m" + std::to_string(i);
            m.baseColorImage = int32_t(i);
            doc.materials.push_back(m);
            addObject(doc, "panel" + std::to_string(i), quad(2, 2, i, true),
                      {(i % 2 ? 1.2f : -1.2f), 1.0f, -3.0f * float(i)});
        }
        addObject(doc, "ground", box(6, 0.1f, 30, 0), {0, -0.05f, -10});
        addLights(doc);
        return convert(doc, "textured-street");
    }();
    return path;
}

CameraState streetView(double z) { return lookAt({0, 1.2, z}, {0, 1.0, z - 6}); }

// Fails the test if GL reported an error while it was alive (a level out of range, a copy
// between mismatched chains: the driver would skip the call and the image would be wrong).
struct NoGlErrors {
    uint64_t before = glErrorsReported();
    ~NoGlErrors() { EXPECT_EQ(glErrorsReported(), before) << "GL errors (printed above)"; }
};

struct Streamed {
    std::unique_ptr<GpuScene> scene;
    std::unique_ptr<SceneStream> stream;
    std::unique_ptr<Renderer> renderer;
};

Streamed openStream(const std::string& path, const StreamOptions& options) {
    Streamed s;
    auto opened = SceneStream::open(path, options);
    EXPECT_TRUE(opened.ok()) << (opened.ok() ? "" : opened.error().message);
    if (!opened.ok()) return s;
    s.scene = std::move(opened->scene);
    s.stream = std::move(opened->stream);
    auto r = Renderer::create(*s.scene, {});
    EXPECT_TRUE(r.ok());
    if (r.ok()) s.renderer = std::move(*r);
    return s;
}

CapturedImage frame(Streamed& s, const CameraState& camera, CaptureBuffer buffer = CaptureBuffer::Color) {
    auto u = s.stream->update(camera, kW, kH);
    EXPECT_TRUE(u.ok()) << (u.ok() ? "" : u.error().message);
    EXPECT_TRUE(s.renderer->render(camera, kW, kH).ok());
    return std::move(*s.renderer->capture(buffer));
}

// Draws frames of `view` until the stream has what this view needs (at least one frame: the
// status is about the view last planned for). False if it never does.
bool settle(Streamed& s, const CameraState& view) {
    for (StreamTimeLimit limit; limit.left();) {
        frame(s, view);
        if (s.stream->status().complete) return true;
    }
    return false;
}

// Looking down the street from before its start: what it needs (the CPU estimate counts the
// panels behind and beside the camera too) fits in a quarter of the texture bytes.
const CameraState kBudgetView = streetView(10.0);

std::string copyTo(const std::string& from, const std::string& name) {
    auto to = std::filesystem::path(from).parent_path() / name;
    std::filesystem::copy_file(from, to, std::filesystem::copy_options::overwrite_existing);
    return to.string();
}

} // namespace

TEST(Streaming, FinishedStreamDrawsTheFullLoadsImageAndEveryFrameBeforeIsFinite) {
    NoGlErrors noGlErrors;
    const std::string path = texturedStreet();
    const CameraState view = streetView(2.0);
    const Rendered full = render(path, view, kW, kH);

    StreamOptions o;
    o.uploadBytesPerFrame = 48 << 10; // a 256^2 RGBA8 level 0 takes six frames
    Streamed s = openStream(path, o);
    ASSERT_TRUE(s.renderer);
    int streamingFrames = 0;
    bool differedWhileStreaming = false;
    StreamTimeLimit limit;
    for (int k = 0; limit.left() && !s.stream->status().complete; ++k) {
        CapturedImage hdr = frame(s, view, CaptureBuffer::Hdr);
        ASSERT_TRUE(allFinite(hdr)) << "frame " << k;
        if (!s.stream->status().complete) {
            ++streamingFrames;
            CapturedImage color = std::move(*s.renderer->capture(CaptureBuffer::Color));
            differedWhileStreaming |= compareRgba8(color, full.color).maxAbs > 0;
        }
        EXPECT_LE(s.stream->status().frame.uploadedBytes, o.uploadBytesPerFrame + 4 * 256 * 4);
    }
    ASSERT_TRUE(s.stream->status().complete);
    EXPECT_GT(streamingFrames, 10);       // it did stream, over many frames
    EXPECT_TRUE(differedWhileStreaming);  // with coarser mips than the final image
    EXPECT_EQ(s.stream->status().residentBytes, s.stream->status().fullBytes);
    const CapturedImage done = frame(s, view);
    EXPECT_EQ(compareRgba8(done, full.color).maxAbs, 0);
}

TEST(Streaming, LevelsSkippedWhileNotNeededAreReadAgainWhenTheViewNeedsThem) {
    NoGlErrors noGlErrors;
    // Under a budget of half the texture bytes, seen from far beyond the street's end, the
    // finest levels of the panels nearer its start are skipped as the forward pass brings them
    // (the spare budget caches levels of the panels nearest to the camera). Once the whole file
    // has been read and the cache has settled, what a view inside the street needs beyond it can
    // only come from re-reading the file (pread); the image ends at the full load's. A read-ahead
    // smaller than one level keeps the loader at most one level ahead.
    const std::string path = texturedStreet();
    StreamOptions o;
    Streamed probe = openStream(path, o);
    ASSERT_TRUE(probe.stream);
    o.budgetBytes = probe.stream->status().fullBytes / 2;
    probe = {};
    o.readAheadBytes = 4 << 10;
    o.uploadBytesPerFrame = 96 << 10;
    Streamed s = openStream(path, o);
    ASSERT_TRUE(s.renderer);
    const CameraState far = streetView(-80.0), near = streetView(-6.0);
    for (StreamTimeLimit limit; limit.left() && !s.stream->status().readDone;) frame(s, far);
    ASSERT_TRUE(s.stream->status().readDone);
    ASSERT_TRUE(settle(s, far));
    for (int k = 0; k < 30; ++k) frame(s, far); // the cache fills the spare budget
    const uint64_t uploadedBefore = s.stream->status().uploadedBytes;
    const uint32_t refetchesBefore = s.stream->status().refetches;
    ASSERT_TRUE(settle(s, near));
    EXPECT_LE(s.stream->status().neededBytes, o.budgetBytes);
    EXPECT_GT(s.stream->status().uploadedBytes - uploadedBefore, uint64_t(o.readAheadBytes));
    EXPECT_GT(s.stream->status().refetches, refetchesBefore);
    EXPECT_EQ(compareRgba8(frame(s, near), render(path, near, kW, kH).color).maxAbs, 0);
}

TEST(Streaming, BudgetIsNeverExceededAlongAPathAndTheImageConvergesWhereItSuffices) {
    NoGlErrors noGlErrors;
    const std::string path = texturedStreet();
    StreamOptions o;
    Streamed probe = openStream(path, o);
    ASSERT_TRUE(probe.stream);
    const uint64_t budget = probe.stream->status().fullBytes / 4;
    probe = {};

    o.budgetBytes = budget;
    o.uploadBytesPerFrame = 64 << 10;
    Streamed s = openStream(path, o);
    ASSERT_TRUE(s.renderer);
    // Down the street and back, three times.
    uint32_t evictions = 0;
    for (int k = 0; k < 360; ++k) {
        const double phase = double(k % 120) / 120.0;
        const double z = 3.0 - 24.0 * (phase < 0.5 ? 2 * phase : 2 - 2 * phase);
        frame(s, streetView(z));
        const StreamStatus& st = s.stream->status();
        ASSERT_LE(st.peakBytes, budget) << "frame " << k;
        ASSERT_LE(st.residentBytes, budget) << "frame " << k;
        evictions = st.evictions;
    }
    EXPECT_GT(evictions, 0u); // the budget was short somewhere along the path
    // Parked where the budget suffices for the view: the image becomes the full load's.
    const CameraState view = kBudgetView;
    ASSERT_TRUE(settle(s, view));
    EXPECT_LE(s.stream->status().neededBytes, budget);
    const CapturedImage converged = frame(s, view);
    const Rendered full = render(path, view, kW, kH);
    EXPECT_EQ(compareRgba8(converged, full.color).maxAbs, 0);
}

// The last texel chunk (a level 0, after the first frame's data): a byte of its payload
// flipped, or the file cut inside it.
struct LastTexels {
    uint32_t sequence = 0;
    uint64_t payloadOffset = 0, storedSize = 0;
};
LastTexels lastTexels(const std::string& path) {
    auto c = Container::open(path);
    EXPECT_TRUE(c.ok());
    LastTexels t;
    for (const ChunkInfo& info : c->chunks())
        if (info.header.tag == tags::kTextureMip)
            t = {info.header.sequence, info.payloadOffset, info.header.storedSize};
    return t;
}

void expectStopsWithError(const std::string& path, const std::string& what) {
    StreamOptions o;
    o.uploadBytesPerFrame = 48 << 10;
    Streamed s = openStream(path, o);
    ASSERT_TRUE(s.renderer);
    const CameraState view = streetView(2.0);
    StreamTimeLimit limit;
    for (int k = 0; limit.left(); ++k) {
        auto u = s.stream->update(view, kW, kH);
        if (!u.ok()) {
            EXPECT_EQ(u.error().kind, PlayErrorKind::Input);
            EXPECT_NE(u.error().message.find(what), std::string::npos) << u.error().message;
            EXPECT_FALSE(s.stream->status().complete);
            return;
        }
        ASSERT_TRUE(s.renderer->render(view, kW, kH).ok());
        ASSERT_TRUE(allFinite(*s.renderer->capture(CaptureBuffer::Hdr))) << "frame " << k;
    }
    ADD_FAILURE() << "the damage was never reported";
}

TEST(Streaming, ACorruptChunkMidStreamStopsWithTheChunkAndItsOffset) {
    NoGlErrors noGlErrors;
    const std::string path = copyTo(texturedStreet(), "stream-corrupt.pnb");
    const LastTexels t = lastTexels(path);
    ASSERT_GT(t.storedSize, 0u);
    {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(t.payloadOffset + t.storedSize / 2));
        f.put('\x5a');
    }
    expectStopsWithError(path, "chunk " + std::to_string(t.sequence) + " 'TMIP'");
    expectStopsWithError(path, "at byte " + std::to_string(t.payloadOffset));
}

TEST(Streaming, ATruncatedStreamStopsWithWhereItEnds) {
    NoGlErrors noGlErrors;
    const std::string path = copyTo(texturedStreet(), "stream-truncated.pnb");
    const LastTexels t = lastTexels(path);
    std::filesystem::resize_file(path, t.payloadOffset + t.storedSize / 2);
    expectStopsWithError(path, "stream ends inside a chunk payload");
}

TEST(Streaming, APipeStreamsLikeAFile) {
    NoGlErrors noGlErrors;
    const std::string path = texturedStreet();
    const std::string fifo = (std::filesystem::path(path).parent_path() / "stream.fifo").string();
    std::filesystem::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::thread writer([&] {
        std::ifstream in(path, std::ios::binary);
        std::ofstream out(fifo, std::ios::binary);
        out << in.rdbuf();
    });
    StreamOptions o;
    o.uploadBytesPerFrame = 48 << 10;
    Streamed s = openStream(fifo, o);
    const CameraState view = streetView(2.0);
    for (StreamTimeLimit limit; limit.left() && s.stream && !s.stream->status().complete;) frame(s, view);
    writer.join();
    ASSERT_TRUE(s.stream);
    EXPECT_TRUE(s.stream->status().complete);
    EXPECT_EQ(s.stream->status().fileBytes, 0u); // unknown: a pipe
    EXPECT_EQ(compareRgba8(frame(s, view), render(path, view, kW, kH).color).maxAbs, 0);
    std::filesystem::remove(fifo);
}

} // namespace pnb::player::test
