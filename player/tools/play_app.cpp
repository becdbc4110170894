// pnb-play's command line (play_app.h) — loads a .pnb container and renders it: interactively in
// a window, or headless for benchmarks, screenshots and buffer dumps. A thin shell over the
// pnb_player library; pnb-judge runs the same with the ray-traced truth metrics plugged in.
#include "play_app.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "error_maps.h"
#include "lod_quality.h"
#include "input_actions.h"
#include "play_options.h"
#include "window_session.h"
#include "pnb_player/benchmark.h"
#include "pnb_player/gl_context.h"
#include "pnb_player/path_json.h"
#include "pnb_player/program_cache_files.h"
#include "pnb_player/renderer.h"
#include "pnb_player/scene_stream.h"
#include "pnb_player/startup_times.h"

using namespace pnb::player;

namespace {

// Which player runs (pnb-play or pnb-judge): messages and usage name it.
const char* gProgram = "pnb-play";

int exitCode(const PlayError& e) {
    switch (e.kind) {
    case PlayErrorKind::Usage: return 1;
    case PlayErrorKind::Input: return 2;
    default: return 3;
    }
}

int fail(const PlayError& e) {
    std::fprintf(stderr, "%s: %s\n", gProgram, e.message.c_str());
    return exitCode(e);
}

PlayResult<CaptureRequest> dumpRequest(const std::string& kind, const Args& a) {
    struct Kind { const char* name; CaptureBuffer buffer; const char* ext; };
    static const Kind kinds[] = {{"color", CaptureBuffer::Color, "png"},
                                 {"hdr", CaptureBuffer::Hdr, "exr"},
                                 {"depth", CaptureBuffer::Depth, "exr"},
                                 {"lineardepth", CaptureBuffer::LinearDepth, "exr"},
                                 {"normal", CaptureBuffer::Normal, "exr"},
                                 {"position", CaptureBuffer::Position, "exr"},
                                 {"shadow", CaptureBuffer::Shadow, "exr"},
                                 {"shadow_color", CaptureBuffer::ShadowColor, "exr"},
                                 {"indirect", CaptureBuffer::Indirect, "exr"},
                                 {"sky", CaptureBuffer::Sky, "exr"}};
    for (const Kind& k : kinds)
        if (kind == k.name)
            return CaptureRequest{k.buffer, a.frame,
                                  a.outDir + "/frame" + std::to_string(a.frame) + "_" + k.name + "." + k.ext};
    return PlayError{PlayErrorKind::Usage,
                     "--dump: unknown buffer '" + kind +
                         "' (color, hdr, depth, lineardepth, normal, position, shadow, shadow_color, indirect, sky)"};
}

// `earlier` (when set) then `next`, their metrics in one list: the --*-metrics options measure
// the same replayed frames, each adding its columns to quality.csv.
using QualityMeasure = decltype(QualityHook::measure);
QualityMeasure chainQuality(QualityMeasure earlier, QualityMeasure next) {
    if (!earlier) return next;
    return [earlier, next](uint32_t k, Renderer& r, bool followUp)
               -> PlayResult<std::vector<std::pair<std::string, double>>> {
        auto out = earlier(k, r, followUp);
        if (!out) return out.error();
        auto more = next(k, r, followUp);
        if (!more) return more.error();
        out->insert(out->end(), more->begin(), more->end());
        return out;
    };
}

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// One run of the player, stage by stage (runPlayer below reads them in order). A stage that
// fails returns the error to report; the state it builds stays here for the next.
struct PlayRun {
    Args args;
    const TruthFactory& truth;
    Clock::time_point processStart = Clock::now();
    StartupTimes startup;
    std::string commandLine;
    std::vector<ScriptedEvent> script;
    bool window = false;
    std::unique_ptr<GlContext> context;
    GlInfo gl;
    LoadStats load;
    std::unique_ptr<GpuScene> scene;
    std::unique_ptr<SceneStream> stream; // after `scene`: it fills it, so it goes first
    RenderSettings settings;
    std::unique_ptr<Renderer> renderer;
    BenchOptions bo;
    CameraState first;
    std::vector<std::unique_ptr<TruthJudge>> judges; // the truth metrics (pnb-judge), one each
    LodFrame lodFrame; // --error-maps: the last measured frame's per-pixel LOD difference
    uint32_t errorMapFrame = 0; // --error-maps: the frame the modules' last measurement is of

    using Failure = std::optional<PlayError>;

    explicit PlayRun(const TruthFactory& t) : truth(t) {
        startup.processStartMs = std::max(0.0, processAgeMs(&startup.processStartSource));
    }

    void configure(int argc, char** argv) {
        ProgramCacheOptions cacheOptions;
        cacheOptions.enabled = args.programCache;
        cacheOptions.directory = args.programCacheDir;
        cacheOptions.notes = !args.quiet;
        configureProgramCacheOnDisk(cacheOptions);
        for (int i = 0; i < argc; ++i) commandLine += (i ? " " : "") + std::string(argv[i]);
    }

    // Before the window: a script that does not parse is a usage error, display or not.
    Failure readScript() {
        if (args.scriptInput.empty()) return std::nullopt;
        auto sc = readInputScript(args.scriptInput);
        if (!sc) return sc.error();
        script = std::move(*sc);
        return std::nullopt;
    }

    Failure openContext() {
        window = !args.headless;
        auto phase = Clock::now();
        if (window) {
            WindowOptions wo;
            wo.width = int(args.width ? args.width : 1280);
            wo.height = int(args.height ? args.height : 720);
            wo.title = std::string(gProgram) + " — " + args.scene;
            wo.vsync = !args.bench;
            wo.debug = args.glDebug;
            auto c = createWindowContext(wo);
            if (!c) return PlayError{c.error().kind, c.error().message + " (or run with --headless)"};
            context = std::move(*c);
        } else {
            auto c = createHeadlessContext(args.glDebug);
            if (!c) return c.error();
            context = std::move(*c);
        }
        gl = context->info();
        startup.contextMs = msSince(phase);
        return std::nullopt;
    }

    // Streaming or a full load (docs/PLAYER.md "Streaming"). The stream's limits come from the
    // command line now, and again from the resolved settings (the container's RSET too) later.
    Failure loadScene() {
        if (args.stream == 1 || (args.stream == -1 && (window || args.scene == "-"))) {
            StreamOptions so;
            so.verifyChecksums = args.checksums;
            if (auto early = resolveSettings({}, args.sets, nullptr)) so.applySettings(*early);
            auto opened = SceneStream::open(args.scene, so, &load);
            if (!opened) return opened.error();
            scene = std::move(opened->scene);
            stream = std::move(opened->stream);
        } else {
            LoadOptions lo;
            lo.verifyChecksums = args.checksums;
            auto loaded = pnb::player::loadScene(args.scene, lo, &load);
            if (!loaded) return loaded.error();
            scene = std::move(*loaded);
        }
        startup.loadMs = load.totalMs - load.compileMs;
        // --path FILE: a keyframe file rather than a name in the container. It goes first, so its
        // name wins over a container path of the same name.
        if (std::error_code ec; !args.pathName.empty() && (args.pathName.ends_with(".json") ||
                                                           std::filesystem::is_regular_file(args.pathName, ec))) {
            auto p = readPathJson(args.pathName);
            if (!p) return p.error();
            args.pathName = p->name;
            scene->paths.insert(scene->paths.begin(), std::move(*p));
        }
        return std::nullopt;
    }

    // The driver's defaults < the container's RSET < --set; then the renderer over them.
    Failure createRenderer() {
        std::vector<std::string> warnings;
        auto defaults = driverDefaults(gl.renderer);
        defaults.insert(defaults.end(), scene->settings.begin(), scene->settings.end());
        auto resolved = resolveSettings(defaults, args.sets, &warnings);
        if (!resolved) return resolved.error();
        settings = *resolved;
        if (!args.quiet)
            for (const std::string& w : warnings) std::fprintf(stderr, "%s: warning: %s\n", gProgram, w.c_str());
        // A setting given that changes nothing as the others stand is applied, but never silently.
        for (const std::string& assignment : args.sets) {
            const std::string key = assignment.substr(0, assignment.find('='));
            if (std::string why = settingNote(key, settings); !why.empty())
                std::fprintf(stderr, "%s: note: %s has no effect: %s\n", gProgram, key.c_str(), why.c_str());
        }
        auto created = Renderer::create(*scene, settings);
        if (!created) return created.error();
        renderer = std::move(*created);
        if (stream) stream->setLimits(settings);
        return std::nullopt;
    }

    void printLoadSummary() const {
        std::printf("%s: %zu draw items, %llu triangles, %zu materials (%zu deferred layers%s), %zu lights\n",
                    args.scene.c_str(), scene->items.size(), (unsigned long long)scene->triangles,
                    scene->materials.size(), scene->deferredLayers.size(), scene->hasForward ? " + forward" : "",
                    scene->lights.size());
        if (stream)
            std::printf("load (streaming): first frame's data in %.2f ms = open %.2f + structure %.2f + "
                        "upload %.2f + shaders %.2f; %.1f of %.1f MiB streamed storage resident now (budget %s)\n",
                        load.totalMs, load.openMs, load.decodeMs, load.uploadMs, load.compileMs,
                        double(stream->status().residentBytes) / 1048576.0,
                        double(stream->status().fullBytes) / 1048576.0,
                        settings.streamBudgetMib ? (std::to_string(settings.streamBudgetMib) + " MiB").c_str() : "none");
        else
            std::printf("load: %.2f ms total = open %.2f + read %.2f + decode %.2f + upload %.2f + "
                        "shaders %.2f (%.1f MiB, %.1f MiB zero-copy, upload heap: %s)\n",
                        load.totalMs, load.openMs, load.readMs, load.decodeMs, load.uploadMs, load.compileMs,
                        double(load.fileBytes) / 1048576.0, double(load.zeroCopyBytes) / 1048576.0,
                        load.uploadPages.empty() ? "none" : load.uploadPages.c_str());
        std::printf("GL: %s | %s\n", gl.renderer.c_str(), gl.version.c_str());
    }

    // What the frames are: the path, their number and size, the captures (--screenshot, --dump).
    Failure planFrames() {
        bo.pathName = args.pathName;
        bo.frames = args.frames;
        bo.seconds = args.seconds;
        bo.fixedDt = args.fixedDt || !args.bench; // screenshots and dumps are deterministic
        if (args.dt > 0) bo.dt = args.dt;
        bo.width = args.width ? args.width : 512;
        bo.height = args.height ? args.height : 288;
        bo.outDir = args.bench ? args.outDir : "";
        bo.plot = args.plot;
        bo.sceneFile = args.scene;
        bo.commandLine = commandLine;
        bo.stream = stream.get();
        if (!args.screenshot.empty()) bo.captures.push_back({CaptureBuffer::Color, args.frame, args.screenshot});
        for (const std::string& d : args.dumps) {
            auto r = dumpRequest(d, args);
            if (!r) return r.error();
            bo.captures.push_back(*r);
        }
        if (!args.dumps.empty()) {
            std::error_code ec;
            std::filesystem::create_directories(args.outDir, ec);
        }
        if (args.camera >= 0 && size_t(args.camera) >= scene->cameras.size())
            return PlayError{PlayErrorKind::Usage, "--camera " + std::to_string(args.camera) + ": the container has " +
                                                       std::to_string(scene->cameras.size()) + " camera(s)"};
        if (args.camera >= 0) bo.staticCamera = sceneCamera(*scene, size_t(args.camera));
        first = bo.staticCamera ? *bo.staticCamera : initialCamera(*scene, args.pathName);
        return std::nullopt;
    }

    // The first frame: everything the driver does lazily (shader variants, first-touch of
    // targets) lands here, so it is reported on its own and kept out of benchmark statistics.
    Failure drawFirstFrame() {
        // Warm-up: the driver's code generation for every state the scene is drawn in, now rather
        // than in whichever frame first shows each material (Renderer::warmUp).
        auto phase = Clock::now();
        double programsBefore = programCacheStats().ms;
        if (auto r = renderer->warmUp(first, bo.width, bo.height); !r) return r.error();
        startup.warmUp = settings.warmUp;
        startup.warmUpMs = msSince(phase) - (programCacheStats().ms - programsBefore);
        phase = Clock::now();
        // (Streaming: the first frame draws what open() uploaded; update() starts with the next.)
        if (auto r = renderer->render(first, bo.width, bo.height); !r) return r.error();
        glFinish();
        startup.firstFrameMs = msSince(phase);
        if (stream) stream->markFirstFrame();
        startup.firstFrameThreadCpuMs = renderer->lastFrame().threadCpuMs;
        startup.programs = programCacheStats();
        startup.programsMs = startup.programs.ms;
        startup.totalMs = startup.processStartMs + msSince(processStart);
        startup.otherMs = startup.totalMs - startup.processStartMs - startup.contextMs - startup.loadMs -
                          startup.programsMs - startup.warmUpMs - startup.firstFrameMs;
        load.firstFrameMs = startup.totalMs;
        bo.startup = startup;
        if (!args.quiet) std::printf("%s\n", startupSummary(startup).c_str());
        if (stream && !args.quiet) {
            const StreamStatus& ss = stream->status();
            if (ss.fileBytes)
                std::printf("streaming: first frame after reading %.1f of %.1f MiB (%.1f %%)\n",
                            double(ss.firstFrameBytesRead) / 1048576.0, double(ss.fileBytes) / 1048576.0,
                            100.0 * double(ss.firstFrameBytesRead) / double(ss.fileBytes));
            else
                std::printf("streaming: first frame after reading %.1f MiB\n",
                            double(ss.firstFrameBytesRead) / 1048576.0);
        }
        return std::nullopt;
    }

    // The truth metrics (pnb-judge): one judge each, measuring the same replayed frames.
    Failure attachTruthJudges() {
        if (settings.sunTurnDeg != 0.0f && (args.shadowMetrics > 0 || args.giMetrics > 0))
            return PlayError{PlayErrorKind::Usage, "--shadow-metrics and --gi-metrics trace the container's sun: "
                                                   "lighting.sun_turn_deg must be 0 with them"};
        TruthRequest request;
        request.scene = args.scene;
        request.origin = first.position;
        request.judgedLight = settings.shadowJudgedLight;
        request.towardSun = towardShadowingSun(*scene);
        request.giSamples = std::max(1u, args.giSamples);
        request.giAllLights = args.giAllLights;
        request.giBounces = args.giBounces;
        request.skySamples = std::max(1u, args.skySamples);
        request.skyFromSh = args.skyFromSh;
        request.frameTruthScene = args.frameTruthScene.empty() ? args.scene : args.frameTruthScene;
        request.frameTruthCache = args.frameTruthCache;
        request.frameBounces = args.frameBounces;
        request.frameMaxSamples = std::max(1u, args.frameMaxSamples);
        request.frameNoise = args.frameNoise;
        request.frameTimeLimit = args.frameTimeLimit;
        struct Wanted {
            TruthMetric metric;
            uint32_t every;
            const char* option;
        };
        for (const Wanted& w : {Wanted{TruthMetric::Shadow, args.shadowMetrics, "--shadow-metrics"},
                                Wanted{TruthMetric::Gi, args.giMetrics, "--gi-metrics"},
                                Wanted{TruthMetric::Sky, args.skyMetrics, "--sky-metrics"},
                                Wanted{TruthMetric::Frame, args.frameMetrics, "--frame-metrics"}}) {
            if (w.every == 0) continue;
            if (!truth)
                return PlayError{PlayErrorKind::Usage, std::string(w.option) +
                                                           " compares with the ray-traced truth, which " +
                                                           gProgram + " does not link: run pnb-judge (the same options)"};
            if (!args.bench) return PlayError{PlayErrorKind::Usage, std::string(w.option) + " needs --bench"};
            if (bo.quality.measure && bo.quality.every != w.every)
                return PlayError{PlayErrorKind::Usage,
                                 std::string(w.option) + " and the other metrics must measure the same frames"};
            if (w.metric == TruthMetric::Gi && !scene->giPrograms)
                return PlayError{PlayErrorKind::Usage, "--gi-metrics: the container has no GI (pnb-convert --gi)"};
            if (w.metric == TruthMetric::Sky && !scene->environment)
                return PlayError{PlayErrorKind::Usage,
                                 "--sky-metrics: the container has no environment (pnb-convert --sky or --environment)"};
            auto judge = truth(w.metric, request);
            if (!judge) return judge.error();
            TruthJudge* j = judges.emplace_back(std::move(*judge)).get();
            bo.quality.every = w.every;
            bo.quality.measure = chainQuality(bo.quality.measure, [j](uint32_t, Renderer& r, bool followUp) {
                return j->measure(r, followUp);
            });
        }
        return std::nullopt;
    }

    // --lod-metrics, and --error-maps' record of which frame the metrics measured last.
    Failure attachLodMetric() {
        if (args.lodMetrics > 0) {
            if (!args.bench) return PlayError{PlayErrorKind::Usage, "--lod-metrics needs --bench"};
            if (bo.quality.measure && bo.quality.every != args.lodMetrics)
                return PlayError{PlayErrorKind::Usage, "--lod-metrics and the other metrics must measure the same frames"};
            bo.quality.every = args.lodMetrics;
            bo.quality.measure = chainQuality(bo.quality.measure, [this](uint32_t, Renderer& r, bool followUp) {
                return measureLodQuality(r, followUp, args.errorMaps ? &lodFrame : nullptr);
            });
        }
        // --error-maps: the frame the modules' last measurement is of (they keep no follow-up).
        if (args.errorMaps && bo.quality.measure)
            bo.quality.measure = [inner = bo.quality.measure, this](uint32_t k, Renderer& r, bool followUp) {
                if (!followUp) errorMapFrame = k;
                return inner(k, r, followUp);
            };
        return std::nullopt;
    }

    // Headless screenshot/dump/smoke run or benchmark (in the window too with --bench).
    int runFrames();
    // Interactive window.
    int runWindow();
};

int PlayRun::runFrames() {
    // Frame times as a run of --frames would have them, but stop once the requested frame is done.
    if (!args.bench) {
        if (args.frames == 0) bo.frames = args.frame + 1;
        bo.lastFrame = args.frame;
    }
    std::function<bool()> present;
    if (window)
        present = [&] {
            int w = 0, h = 0;
            context->framebufferSize(w, h);
            renderer->presentToWindow(w, h);
            context->swapBuffers();
            context->pollEvents();
            return !context->shouldClose();
        };
    // A run past two seconds shows where it is on a terminal (gi.cells at its maximum on a
    // software GL takes minutes); redirected output stays clean.
    bool progressShown = false;
    if (!args.quiet && isatty(STDERR_FILENO))
        bo.progress = [&progressShown, last = 0.0](uint32_t done, uint32_t planned, double seconds) mutable {
            if (seconds < 2.0 || seconds - last < 0.25) return;
            last = seconds;
            progressShown = true;
            if (planned) std::fprintf(stderr, "\r%s: frame %u of %u, %.0f s", gProgram, done, planned, seconds);
            else std::fprintf(stderr, "\r%s: frame %u, %.0f s", gProgram, done, seconds);
        };
    auto result = runBenchmark(*scene, *renderer, bo, load, gl, present);
    if (progressShown) std::fprintf(stderr, "\n");
    if (!result) return fail(result.error());
    for (const std::string& w : result->warnings) // a wrong frame is never silent, even -q
        std::fprintf(stderr, "%s: warning: %s\n", gProgram, w.c_str());
    if (const std::string& note = renderer->debugViewNote(); !note.empty())
        std::fprintf(stderr, "%s: note: %s\n", gProgram, note.c_str());
    if (args.errorMaps) {
        std::vector<ErrorMap> maps;
        for (const auto& judge : judges)
            for (ErrorMap& m : judge->errorMaps()) maps.push_back(std::move(m));
        if (args.lodMetrics > 0) maps.push_back(lodErrorMap(lodFrame));
        auto written = writeErrorMaps(args.outDir, errorMapFrame, maps);
        if (!written) return fail(written.error());
        result->written.insert(result->written.end(), written->begin(), written->end());
    }
    if (!args.quiet) {
        std::printf("%u frames at %ux%u\n", result->frames, bo.width, bo.height);
        for (const PassSummary& p : result->gpu)
            std::printf("  gpu %-9s median %7.3f ms  p95 %7.3f ms  max %7.3f ms\n", p.pass.c_str(), p.median, p.p95,
                        p.max);
        std::printf("  cpu           median %7.3f ms  p95 %7.3f ms\n", result->cpu.median, result->cpu.p95);
        for (const std::string& f : result->written) std::printf("wrote %s\n", f.c_str());
    }
    return 0;
}

int PlayRun::runWindow() {
    WindowRunOptions wo;
    wo.sceneFile = args.scene;
    wo.glRenderer = gl.renderer;
    wo.sets = args.sets;
    wo.verifyChecksums = args.checksums;
    wo.quiet = args.quiet;
    wo.ui = args.ui;
    wo.frames = args.frames;
    wo.width = args.width;
    wo.height = args.height;
    wo.fixedDt = args.fixedDt ? (args.dt > 0 ? args.dt : 1.0 / 60.0) : 0.0;
    wo.captures = bo.captures;
    wo.screenshotDir = args.screenshotDir;
    wo.recordPath = args.recordPath;
    wo.recordEvery = args.recordEvery;
    wo.scripted = !args.scriptInput.empty();
    wo.script = std::move(script);
    return pnb::player::runWindow(*context, std::move(scene), std::move(stream), std::move(renderer), settings, first,
                                  wo);
}

} // namespace

int pnb::player::runPlayer(int argc, char** argv, const char* program, const TruthFactory& truth) {
    gProgram = program;
    PlayRun run(truth);
    // A write past RLIMIT_FSIZE (a cache entry, a screenshot) then fails with EFBIG and is
    // reported, instead of the default SIGXFSZ ending the process.
    std::signal(SIGXFSZ, SIG_IGN);
    if (auto done = parsePlayOptions(argc, argv, program, run.args)) return *done;
    run.configure(argc, argv);
    if (auto e = run.readScript()) return fail(*e);
    if (auto e = run.openContext()) return fail(*e);
    if (auto e = run.loadScene()) return fail(*e);
    if (auto e = run.createRenderer()) return fail(*e);
    if (!run.args.quiet) run.printLoadSummary();
    if (auto e = run.planFrames()) return fail(*e);
    if (auto e = run.drawFirstFrame()) return fail(*e);
    if (auto e = run.attachTruthJudges()) return fail(*e);
    if (auto e = run.attachLodMetric()) return fail(*e);
    return run.args.bench || !run.window ? run.runFrames() : run.runWindow();
}
