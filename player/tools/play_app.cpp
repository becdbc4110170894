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
#include "window_session.h"
#include "pnb/output_guard.h"
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

const char* kUsage = R"(usage: pnb-play SCENE.pnb [options]
       cat SCENE.pnb | pnb-play - [options]     (streams from standard input)

Modes (default: an interactive window):
  --headless              render offscreen through EGL (no display needed)
  --bench                 fly through a camera path, write timings (needs --out)
  --ui                    Dear ImGui overlay with timings and setting toggles (window mode)

Run:
  --path NAME|FILE        camera path: a name in the container (default: its first), or a
                          keyframe JSON file (what pnb-convert --path reads and F9 records)
  --camera N              stand still at the container's camera N (no path)
  --frames N              number of frames (window mode: quit after N)
  --seconds S             stop after S seconds of path time
  --fixed-dt [DT]         frame k at path time k*DT (default: path duration / frames, or 1/60 s);
                          in the window, every frame moves the camera by DT of time
  --size WxH              render size (default 512x288 headless, 1280x720 window)
  --out DIR               output directory for --bench and --dump
  --screenshot FILE       save the output image (PNG) of frame --frame
  --dump KIND[,KIND...]   save exact buffers of frame --frame into --out as EXR/PNG:
                          color, hdr, depth, lineardepth, normal, position (camera-relative),
                          shadow (sun visibility, cascade, texel/pixel ratio; with position
                          or shadow, frameK_frame.json holds the camera and light),
                          indirect (the irradiance GI adds, rgb; 0 with GI off),
                          sky (the sky irradiance lighting applies, rgb, lux; 0 without IBL)
  --frame K               frame for --screenshot and --dump (default 0)
  --no-plot               do not call the plot script
  --lod-metrics N         with --bench: replay every N-th frame and compare it with the same view
                          at full detail (lod.force=0): PSNR, pixels off by > 8/255, triangles
                          (quality.csv, "quality" in summary.json); with other metrics, the same N

Truth metrics (pnb-judge only: it links the Embree ray tracer, which pnb-play leaves out):
  --shadow-metrics N      with --bench: replay every N-th frame (and the view 1/60 s later) and compare
                          the sun's shadows with Embree ray-traced visibility: quality.csv and
                          "quality" in summary.json (misclassified %, mean abs error, texel/pixel
                          ratio per cascade, flicker)
  --gi-metrics N          with --bench, on a container with GI: replay every N-th frame (and the
                          view 1/60 s later) and compare the indirect light with the ray-traced
                          one-bounce truth (gi_rmse_pct, gi_energy_ratio, per-colour ratios,
                          gi_leak_pct, the reference's noise, gi_flicker_pct); with
                          --shadow-metrics, N must be the same
  --sky-metrics N         with --bench, on a container with an environment: every N-th frame (and
                          the view 1/60 s later), the sky irradiance the lighting applied (SH x
                          ibl.visibility) against the ray-traced sky light with Embree visibility
                          (sky_rmse_pct, sky_energy_ratio, ..., sky_flicker_pct); same N as the
                          other metrics
  --sky-samples S         rays per pixel of the sky truth (default 64)
  --sky-source image|sh   the truth's radiance: the environment image (default; the whole error)
                          or the radiance of the converter's SH (the visibility term's error alone)
  --gi-samples S          rays per pixel of that truth (default 64)
  --gi-lights sun|all     light the truth's bounce with the sun alone (default: what GI models)
                          or every light
  --error-maps            with --bench and a metric (--lod-metrics or a truth metric): heat-maps of the last measured frame
                          (not its follow-up) into --out, lined up with --screenshot images:
                          error_shadow.png (dark grey unclassified, light greys correct lit /
                          shadowed, red false lit, blue false shadow; brighter = larger
                          |player - truth|), error_gi.png and error_sky.png (|player - truth|
                          luminance / mean truth luminance, magma ramp black..pale yellow up to
                          100 %; dark grey unmeasured), error_lod.png (largest RGB difference to
                          full detail, same ramp up to 32/255); compare_gi.png, compare_sky.png
                          (player | truth | difference side by side); error_maps.json: legends

Window (see docs/PLAYER.md):
  WASD move, Q/E down/up, Shift faster, right-drag look, O orbit (left-drag, W/S in/out)
  wheel: fly speed (x1.25 a notch); Ctrl+wheel or right button+wheel: field of view (5..120 deg)
  F9 start/stop recording a camera path, K add a key now, F12 screenshot, Esc or close: quit
  drop a .pnb to open it, or a .gltf/.glb/.obj to convert it first (child pnb-convert:
  $PNB_CONVERT, else beside pnb-play, else on PATH); a file that fails to open changes nothing
  --record-path FILE      where F9 saves the path (default recorded_path.json; an existing file
                          is kept and NAME-2.json, NAME-3.json, ... used instead)
  --record-every S        while recording, also add a key every S seconds
  --screenshot-dir DIR    where F12 saves pnb-play-DATE-TIME-NNN.png (default: current directory)
  --script-input FILE     replay timed input events (keys, mouse, wheel, drops, close, iconify;
                          format in player/tools/input_actions.h); real input is then ignored

Settings (container RSET < command line):
  --set KEY=VALUE         e.g. --set lighting.exposure=1.5 (repeatable)
  --list-settings         print every key, its type and meaning

Start-up (docs/PLAYER.md "Time to first frame"):
  --program-cache DIR     keep linked program binaries in DIR (default: $PNB_PROGRAM_CACHE_DIR,
                          else $XDG_CACHE_HOME/penumbra/programs, else ~/.cache/penumbra/programs)
  --no-program-cache      compile and link every program from source, write no entries
  --set startup.warmup=false   no warm-up draws during load (code generation then lands in the
                          frames that first draw each state; for measuring)

Streaming (docs/PLAYER.md "Streaming"):
  --stream                draw the first frame once the scene's structure and each texture's
                          smallest mip are in; the texels stream in while frames are drawn
                          (the default in the window and for '-'; settings stream.budget_mib,
                          stream.upload_mib)
  --no-stream             load everything before the first frame (the default for --headless
                          and --bench, whose frames then do not depend on the loader's timing)

Other:
  --no-checksums          skip payload checksum verification when loading
  --gl-debug              report GL performance messages too
  -q, --quiet             print only errors

Exit codes: 0 ok, 1 usage, 2 bad input, 3 GL or output failure.
)";

struct Args {
    std::string scene, pathName, outDir, screenshot, recordPath = "recorded_path.json", screenshotDir = ".",
        scriptInput, programCacheDir;
    bool programCache = true;
    double recordEvery = 0;
    std::vector<std::string> sets, dumps;
    bool headless = false, bench = false, ui = false, fixedDt = false, plot = true,
         checksums = true, glDebug = false, quiet = false;
    double dt = 0, seconds = 0;
    int camera = -1;
    uint32_t frames = 0, frame = 0, width = 0, height = 0, shadowMetrics = 0, giMetrics = 0, giSamples = 64,
             lodMetrics = 0, skyMetrics = 0, skySamples = 64;
    bool giAllLights = false, skyFromSh = false, errorMaps = false;
    int stream = -1; // --stream 1, --no-stream 0, -1: by mode
};

[[noreturn]] void usageError(const std::string& message) {
    std::fprintf(stderr, "%s: %s\n(run %s --help for usage)\n", gProgram, message.c_str(), gProgram);
    std::exit(1);
}

uint32_t parseCount(const char* option, const std::string& v) {
    char* end = nullptr;
    unsigned long n = std::strtoul(v.c_str(), &end, 10);
    if (v.empty() || *end || n > 1000000000ul) usageError(std::string(option) + " expects a count, got '" + v + "'");
    return uint32_t(n);
}

double parsePositive(const char* option, const std::string& v) {
    char* end = nullptr;
    double d = std::strtod(v.c_str(), &end);
    if (v.empty() || *end || !(d > 0) || d > 1e9) usageError(std::string(option) + " expects a positive number, got '" + v + "'");
    return d;
}

Args parseArgs(int argc, char** argv) {
    Args a;
    auto next = [&](int& i) -> std::string {
        if (i + 1 >= argc) usageError(std::string(argv[i]) + " needs a value");
        return argv[++i];
    };
    for (int i = 1; i < argc; ++i) {
        std::string s = argv[i];
        if (s == "-h" || s == "--help") {
            // The usage lines name the player that runs (pnb-judge takes the same options).
            std::string usage = kUsage;
            for (const char* line : {"pnb-play SCENE", "pnb-play - "})
                if (size_t at = usage.find(line); at != std::string::npos) usage.replace(at, 8, gProgram);
            std::fputs(usage.c_str(), stdout);
            std::exit(0);
        } else if (s == "--list-settings") {
            for (const SettingInfo& info : settingInfos())
                std::printf("%-20s %-24s %s\n", std::string(info.key).c_str(),
                            std::string(info.type).c_str(), std::string(info.description).c_str());
            std::exit(0);
        } else if (s == "--headless") a.headless = true;
        else if (s == "--bench") a.bench = true;
        else if (s == "--ui") a.ui = true;
        else if (s == "--path") a.pathName = next(i);
        else if (s == "--camera") a.camera = int(parseCount("--camera", next(i)));
        else if (s == "--frames") a.frames = parseCount("--frames", next(i));
        else if (s == "--shadow-metrics") a.shadowMetrics = parseCount("--shadow-metrics", next(i));
        else if (s == "--gi-metrics") a.giMetrics = parseCount("--gi-metrics", next(i));
        else if (s == "--lod-metrics") a.lodMetrics = parseCount("--lod-metrics", next(i));
        else if (s == "--gi-samples") a.giSamples = parseCount("--gi-samples", next(i));
        else if (s == "--gi-lights") a.giAllLights = std::string(next(i)) == "all";
        else if (s == "--sky-metrics") a.skyMetrics = parseCount("--sky-metrics", next(i));
        else if (s == "--error-maps") a.errorMaps = true;
        else if (s == "--sky-samples") a.skySamples = parseCount("--sky-samples", next(i));
        else if (s == "--sky-source") {
            std::string v = next(i);
            if (v != "image" && v != "sh") usageError("--sky-source: image or sh, not '" + v + "'");
            a.skyFromSh = v == "sh";
        }
        else if (s == "--record-path") a.recordPath = next(i);
        else if (s == "--record-every") a.recordEvery = parsePositive("--record-every", next(i));
        else if (s == "--screenshot-dir") a.screenshotDir = next(i);
        else if (s == "--script-input") a.scriptInput = next(i);
        else if (s == "--seconds") a.seconds = parsePositive("--seconds", next(i));
        else if (s == "--fixed-dt") {
            a.fixedDt = true;
            if (i + 1 < argc && argv[i + 1][0] != '-') a.dt = parsePositive("--fixed-dt", next(i));
        } else if (s == "--size") {
            std::string v = next(i);
            unsigned w = 0, h = 0;
            char tail = 0;
            if (std::sscanf(v.c_str(), "%ux%u%c", &w, &h, &tail) != 2 || w == 0 || h == 0 || w > 16384 || h > 16384)
                usageError("--size expects WxH (1..16384), got '" + v + "'");
            a.width = w;
            a.height = h;
        } else if (s == "--out") a.outDir = next(i);
        else if (s == "--screenshot") a.screenshot = next(i);
        else if (s == "--dump") {
            std::string v = next(i);
            for (size_t p = 0; p <= v.size();) {
                size_t c = v.find(',', p);
                if (c == std::string::npos) c = v.size();
                a.dumps.push_back(v.substr(p, c - p));
                p = c + 1;
            }
        } else if (s == "--frame") a.frame = parseCount("--frame", next(i));
        else if (s == "--set") a.sets.push_back(next(i));
        else if (s == "--no-plot") a.plot = false;
        else if (s == "--stream") a.stream = 1;
        else if (s == "--no-stream") a.stream = 0;
        else if (s == "--no-checksums") a.checksums = false;
        else if (s == "--program-cache") {
            a.programCacheDir = next(i);
            if (a.programCacheDir.empty()) usageError("--program-cache needs a directory");
        } else if (s == "--no-program-cache") a.programCache = false;
        else if (s == "--gl-debug") a.glDebug = true;
        else if (s == "-q" || s == "--quiet") a.quiet = true;
        else if (s.size() > 1 && s[0] == '-') usageError("unknown option " + s);
        else if (a.scene.empty()) a.scene = s;
        else usageError("more than one scene given ('" + a.scene + "', '" + s + "')");
    }
    if (a.scene.empty()) usageError("no scene given");
    {
        // What the run reads (the scene, a path file) against what it writes: the screenshot and
        // the benchmark's fixed names in --out.
        const pnb::RoleFile inputs[] = {{a.scene == "-" ? "" : a.scene, "the scene"},
                                        {a.pathName, "the camera path (--path)"}};
        auto inOut = [&](const char* name) {
            return a.outDir.empty() ? std::string() : a.outDir + "/" + name;
        };
        const pnb::RoleFile outputs[] = {{a.screenshot, "the screenshot (--screenshot)"},
                                         {inOut("summary.json"), "the benchmark's summary.json"},
                                         {inOut("frames.csv"), "the benchmark's frames.csv"},
                                         {inOut("frame_times.png"), "the benchmark's frame_times.png"}};
        if (pnb::Status st = pnb::checkOutputs(inputs, outputs); !pnb::isOk(st))
            usageError(st.message);
    }
    if (a.bench && a.outDir.empty()) usageError("--bench needs --out DIR");
    if (!a.dumps.empty() && a.outDir.empty()) usageError("--dump needs --out DIR");
    if (a.errorMaps && (!a.bench || !(a.shadowMetrics || a.giMetrics || a.skyMetrics || a.lodMetrics)))
        usageError("--error-maps needs --bench and at least one of --shadow-metrics, --gi-metrics, "
                   "--sky-metrics, --lod-metrics (the maps show what those measure)");
    if (a.stream == 0 && a.scene == "-") usageError("'-' (standard input) is read by streaming: drop --no-stream");
    if (!a.scriptInput.empty() && (a.headless || a.bench))
        usageError("--script-input drives the window (not --headless or --bench)");
    return a;
}

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
                                 {"indirect", CaptureBuffer::Indirect, "exr"},
                                 {"sky", CaptureBuffer::Sky, "exr"}};
    for (const Kind& k : kinds)
        if (kind == k.name)
            return CaptureRequest{k.buffer, a.frame,
                                  a.outDir + "/frame" + std::to_string(a.frame) + "_" + k.name + "." + k.ext};
    return PlayError{PlayErrorKind::Usage,
                     "--dump: unknown buffer '" + kind +
                         "' (color, hdr, depth, lineardepth, normal, position, shadow, indirect, sky)"};
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

} // namespace

int pnb::player::runPlayer(int argc, char** argv, const char* program, const TruthFactory& truth) {
    gProgram = program;
    auto processStart = std::chrono::steady_clock::now();
    StartupTimes startup;
    startup.processStartMs = std::max(0.0, processAgeMs(&startup.processStartSource));
    auto msSince = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
    };
    // A write past RLIMIT_FSIZE (a cache entry, a screenshot) then fails with EFBIG and is
    // reported, instead of the default SIGXFSZ ending the process.
    std::signal(SIGXFSZ, SIG_IGN);
    Args args = parseArgs(argc, argv);
    ProgramCacheOptions cacheOptions;
    cacheOptions.enabled = args.programCache;
    cacheOptions.directory = args.programCacheDir;
    cacheOptions.notes = !args.quiet;
    configureProgramCacheOnDisk(cacheOptions);
    std::string commandLine;
    for (int i = 0; i < argc; ++i) commandLine += (i ? " " : "") + std::string(argv[i]);

    // Before the window: a script that does not parse is a usage error, display or not.
    std::vector<ScriptedEvent> script;
    if (!args.scriptInput.empty()) {
        auto sc = readInputScript(args.scriptInput);
        if (!sc) return fail(sc.error());
        script = std::move(*sc);
    }
    bool window = !args.headless;
    std::unique_ptr<GlContext> context;
    auto phase = std::chrono::steady_clock::now();
    if (window) {
        WindowOptions wo;
        wo.width = int(args.width ? args.width : 1280);
        wo.height = int(args.height ? args.height : 720);
        wo.title = std::string(gProgram) + " — " + args.scene;
        wo.vsync = !args.bench;
        wo.debug = args.glDebug;
        auto c = createWindowContext(wo);
        if (!c) return fail({c.error().kind, c.error().message + " (or run with --headless)"});
        context = std::move(*c);
    } else {
        auto c = createHeadlessContext(args.glDebug);
        if (!c) return fail(c.error());
        context = std::move(*c);
    }
    GlInfo gl = context->info();
    startup.contextMs = msSince(phase);

    // Streaming or a full load (docs/PLAYER.md "Streaming"). The stream's limits come from the
    // command line now, and again from the resolved settings (the container's RSET too) below.
    LoadStats load;
    std::unique_ptr<GpuScene> scene;
    std::unique_ptr<SceneStream> stream; // after `scene`: it fills it, so it goes first
    if (args.stream == 1 || (args.stream == -1 && (window || args.scene == "-"))) {
        StreamOptions so;
        so.verifyChecksums = args.checksums;
        if (auto early = resolveSettings({}, args.sets, nullptr)) so.applySettings(*early);
        auto opened = SceneStream::open(args.scene, so, &load);
        if (!opened) return fail(opened.error());
        scene = std::move(opened->scene);
        stream = std::move(opened->stream);
    } else {
        LoadOptions lo;
        lo.verifyChecksums = args.checksums;
        auto loaded = loadScene(args.scene, lo, &load);
        if (!loaded) return fail(loaded.error());
        scene = std::move(*loaded);
    }
    startup.loadMs = load.totalMs - load.compileMs;
    // --path FILE: a keyframe file rather than a name in the container. It goes first, so its
    // name wins over a container path of the same name.
    if (std::error_code ec; !args.pathName.empty() && (args.pathName.ends_with(".json") ||
                                                       std::filesystem::is_regular_file(args.pathName, ec))) {
        auto p = readPathJson(args.pathName);
        if (!p) return fail(p.error());
        args.pathName = p->name;
        scene->paths.insert(scene->paths.begin(), std::move(*p));
    }

    std::vector<std::string> warnings;
    auto defaults = driverDefaults(gl.renderer);
    defaults.insert(defaults.end(), scene->settings.begin(), scene->settings.end());
    auto resolved = resolveSettings(defaults, args.sets, &warnings);
    if (!resolved) return fail(resolved.error());
    RenderSettings settings = *resolved;
    if (!args.quiet)
        for (const std::string& w : warnings) std::fprintf(stderr, "%s: warning: %s\n", gProgram, w.c_str());
    // A setting given that changes nothing as the others stand is applied, but never silently.
    for (const std::string& assignment : args.sets) {
        const std::string key = assignment.substr(0, assignment.find('='));
        if (std::string why = settingNote(key, settings); !why.empty())
            std::fprintf(stderr, "%s: note: %s has no effect: %s\n", gProgram, key.c_str(), why.c_str());
    }
    auto renderer = Renderer::create(*scene, settings);
    if (!renderer) return fail(renderer.error());
    if (stream)
        stream->setLimits(settings);

    if (!args.quiet) {
        std::printf("%s: %zu draw items, %llu triangles, %zu materials (%zu deferred layers%s), %zu lights\n",
                    args.scene.c_str(), scene->items.size(), (unsigned long long)scene->triangles,
                    scene->materials.size(), scene->deferredLayers.size(),
                    scene->hasForward ? " + forward" : "", scene->lights.size());
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

    BenchOptions bo;
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
        if (!r) return fail(r.error());
        bo.captures.push_back(*r);
    }
    if (!args.dumps.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(args.outDir, ec);
    }

    // The first frame: everything the driver does lazily (shader variants, first-touch of
    // targets) lands here, so it is reported on its own and kept out of benchmark statistics.
    if (args.camera >= 0 && size_t(args.camera) >= scene->cameras.size())
        return fail({PlayErrorKind::Usage, "--camera " + std::to_string(args.camera) + ": the container has " +
                                               std::to_string(scene->cameras.size()) + " camera(s)"});
    if (args.camera >= 0) bo.staticCamera = sceneCamera(*scene, size_t(args.camera));
    CameraState first = bo.staticCamera ? *bo.staticCamera : initialCamera(*scene, args.pathName);
    // Warm-up: the driver's code generation for every state the scene is drawn in, now rather
    // than in whichever frame first shows each material (Renderer::warmUp).
    phase = std::chrono::steady_clock::now();
    double programsBefore = programCacheStats().ms;
    if (auto r = (*renderer)->warmUp(first, bo.width, bo.height); !r) return fail(r.error());
    startup.warmUp = settings.warmUp;
    startup.warmUpMs = msSince(phase) - (programCacheStats().ms - programsBefore);
    phase = std::chrono::steady_clock::now();
    // (Streaming: the first frame draws what open() uploaded; update() starts with the next.)
    if (auto r = (*renderer)->render(first, bo.width, bo.height); !r) return fail(r.error());
    glFinish();
    startup.firstFrameMs = msSince(phase);
    if (stream) stream->markFirstFrame();
    startup.firstFrameThreadCpuMs = (*renderer)->lastFrame().threadCpuMs;
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
            std::printf("streaming: first frame after reading %.1f MiB\n", double(ss.firstFrameBytesRead) / 1048576.0);
    }

    if (settings.sunTurnDeg != 0.0f && (args.shadowMetrics > 0 || args.giMetrics > 0))
        return fail({PlayErrorKind::Usage, "--shadow-metrics and --gi-metrics trace the container's sun: "
                                           "lighting.sun_turn_deg must be 0 with them"});
    // The truth metrics (pnb-judge): one judge each, measuring the same replayed frames.
    std::vector<std::unique_ptr<TruthJudge>> judges;
    TruthRequest request;
    request.scene = args.scene;
    request.origin = first.position;
    request.judgedLight = settings.shadowJudgedLight;
    request.towardSun = towardShadowingSun(*scene);
    request.giSamples = std::max(1u, args.giSamples);
    request.giAllLights = args.giAllLights;
    request.skySamples = std::max(1u, args.skySamples);
    request.skyFromSh = args.skyFromSh;
    struct Wanted {
        TruthMetric metric;
        uint32_t every;
        const char* option;
    };
    for (const Wanted& w : {Wanted{TruthMetric::Shadow, args.shadowMetrics, "--shadow-metrics"},
                            Wanted{TruthMetric::Gi, args.giMetrics, "--gi-metrics"},
                            Wanted{TruthMetric::Sky, args.skyMetrics, "--sky-metrics"}}) {
        if (w.every == 0) continue;
        if (!truth)
            return fail({PlayErrorKind::Usage, std::string(w.option) + " compares with the ray-traced truth, which " +
                                                   gProgram + " does not link: run pnb-judge (the same options)"});
        if (!args.bench) return fail({PlayErrorKind::Usage, std::string(w.option) + " needs --bench"});
        if (bo.quality.measure && bo.quality.every != w.every)
            return fail({PlayErrorKind::Usage, std::string(w.option) + " and the other metrics must measure the same frames"});
        if (w.metric == TruthMetric::Gi && !scene->giPrograms)
            return fail({PlayErrorKind::Usage, "--gi-metrics: the container has no GI (pnb-convert --gi)"});
        if (w.metric == TruthMetric::Sky && !scene->environment)
            return fail({PlayErrorKind::Usage, "--sky-metrics: the container has no environment (pnb-convert --sky or --environment)"});
        auto judge = truth(w.metric, request);
        if (!judge) return fail(judge.error());
        TruthJudge* j = judges.emplace_back(std::move(*judge)).get();
        bo.quality.every = w.every;
        bo.quality.measure = chainQuality(bo.quality.measure, [j](uint32_t, Renderer& r, bool followUp) {
            return j->measure(r, followUp);
        });
    }

    LodFrame lodFrame; // --error-maps: the last measured frame's per-pixel LOD difference
    if (args.lodMetrics > 0) {
        if (!args.bench) return fail({PlayErrorKind::Usage, "--lod-metrics needs --bench"});
        if (bo.quality.measure && bo.quality.every != args.lodMetrics)
            return fail({PlayErrorKind::Usage, "--lod-metrics and the other metrics must measure the same frames"});
        bo.quality.every = args.lodMetrics;
        bo.quality.measure = chainQuality(bo.quality.measure, [&](uint32_t, Renderer& r, bool followUp) {
            return measureLodQuality(r, followUp, args.errorMaps ? &lodFrame : nullptr);
        });
    }
    // --error-maps: the frame the modules' last measurement is of (they keep no follow-up).
    uint32_t errorMapFrame = 0;
    if (args.errorMaps && bo.quality.measure)
        bo.quality.measure = [inner = bo.quality.measure, &errorMapFrame](uint32_t k, Renderer& r, bool followUp) {
            if (!followUp) errorMapFrame = k;
            return inner(k, r, followUp);
        };

    if (args.bench || !window) {
        // Headless screenshot/dump/smoke run: frame times as a run of --frames would have them,
        // but stop once the requested frame is done.
        if (!args.bench) {
            if (args.frames == 0) bo.frames = args.frame + 1;
            bo.lastFrame = args.frame;
        }
        std::function<bool()> present;
        if (window)
            present = [&] {
                int w = 0, h = 0;
                context->framebufferSize(w, h);
                (*renderer)->presentToWindow(w, h);
                context->swapBuffers();
                context->pollEvents();
                return !context->shouldClose();
            };
        // A run past two seconds shows where it is on a terminal (gi.cells at its maximum on a
        // software GL takes minutes); redirected output stays clean.
        bool progressShown = false;
        if (!args.quiet && isatty(STDERR_FILENO))
            bo.progress = [&progressShown, last = 0.0](uint32_t done, uint32_t planned,
                                                       double seconds) mutable {
                if (seconds < 2.0 || seconds - last < 0.25) return;
                last = seconds;
                progressShown = true;
                if (planned) std::fprintf(stderr, "\r%s: frame %u of %u, %.0f s", gProgram, done, planned, seconds);
                else std::fprintf(stderr, "\r%s: frame %u, %.0f s", gProgram, done, seconds);
            };
        auto result = runBenchmark(*scene, **renderer, bo, load, gl, present);
        if (progressShown) std::fprintf(stderr, "\n");
        if (!result) return fail(result.error());
        for (const std::string& w : result->warnings) // a wrong frame is never silent, even -q
            std::fprintf(stderr, "%s: warning: %s\n", gProgram, w.c_str());
        if (const std::string& note = (*renderer)->debugViewNote(); !note.empty())
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
                std::printf("  gpu %-9s median %7.3f ms  p95 %7.3f ms  max %7.3f ms\n", p.pass.c_str(),
                            p.median, p.p95, p.max);
            std::printf("  cpu           median %7.3f ms  p95 %7.3f ms\n", result->cpu.median, result->cpu.p95);
            for (const std::string& f : result->written) std::printf("wrote %s\n", f.c_str());
        }
        return 0;
    }

    // Interactive window.
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
    return runWindow(*context, std::move(scene), std::move(stream), std::move(*renderer), settings, first, wo);
}
