// play_options.cpp — pnb-play's option table (play_options.h): every option once, with its
// --help text (as the usage always read, hand-wrapped) and the handler that parses its value.
#include "play_options.h"

#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <string>

#include "pnb/output_guard.h"
#include "pnb_cli/options.h"
#include "pnb_player/settings.h"

namespace pnb::player {

namespace {

using pnb::cli::Option;
using pnb::cli::ValueKind;
using pnb::cli::Verdict;
using pnb::cli::text;

constexpr const char* kModes = "Modes (default: an interactive window)";
constexpr const char* kRun = "Run";
constexpr const char* kTruth = "Truth metrics (pnb-judge only: it links the Embree ray tracer, which pnb-play leaves out)";
constexpr const char* kWindow = "Window (see docs/PLAYER.md)";
constexpr const char* kSettings = "Settings (container RSET < command line)";
constexpr const char* kStartUp = "Start-up (docs/PLAYER.md \"Time to first frame\")";
constexpr const char* kStreaming = "Streaming (docs/PLAYER.md \"Streaming\")";
constexpr const char* kOther = "Other";

pnb::cli::Verdict count(const char* option, const std::string& v, uint32_t& out) {
    char* end = nullptr;
    unsigned long n = std::strtoul(v.c_str(), &end, 10);
    if (v.empty() || *end || n > 1000000000ul)
        return Verdict::error(std::string(option) + " expects a count, got '" + v + "'");
    out = uint32_t(n);
    return true;
}

pnb::cli::Verdict positive(const char* option, const std::string& v, double& out) {
    char* end = nullptr;
    double d = std::strtod(v.c_str(), &end);
    if (v.empty() || *end || !(d > 0) || d > 1e9)
        return Verdict::error(std::string(option) + " expects a positive number, got '" + v + "'");
    out = d;
    return true;
}

pnb::cli::Verdict size(const std::string& v, Args& a) {
    unsigned w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(v.c_str(), "%ux%u%c", &w, &h, &tail) != 2 || w == 0 || h == 0 || w > 16384 || h > 16384)
        return Verdict::error("--size expects WxH (1..16384), got '" + v + "'");
    a.width = w;
    a.height = h;
    return true;
}

// --gi-bounces: a count of diffuse bounces 1..256 or "converged" (0; pnb_reference's
// parseIndirectBounces, which the player cannot link).
pnb::cli::Verdict giBounces(const std::string& v, Args& a) {
    if (v == "converged") {
        a.giBounces = 0;
        return true;
    }
    uint32_t n = 0;
    if (!count("--gi-bounces", v, n).ok || n == 0 || n > 256)
        return Verdict::error("--gi-bounces: a count 1..256 or converged, not '" + v + "'");
    a.giBounces = n;
    return true;
}

pnb::cli::Verdict skySource(const std::string& v, Args& a) {
    if (v != "image" && v != "sh") return Verdict::error("--sky-source: image or sh, not '" + v + "'");
    a.skyFromSh = v == "sh";
    return true;
}

pnb::cli::Verdict programCache(const char* v, Args& a) {
    a.programCacheDir = v;
    if (a.programCacheDir.empty()) return Verdict::error("--program-cache needs a directory");
    return true;
}

// "color,depth" -> {"color", "depth"} (an empty item stays, for --dump to refuse).
void splitDumps(const std::string& v, std::vector<std::string>& dumps) {
    for (size_t p = 0; p <= v.size();) {
        size_t c = v.find(',', p);
        if (c == std::string::npos) c = v.size();
        dumps.push_back(v.substr(p, c - p));
        p = c + 1;
    }
}

// The rows of Modes and Run, in --help order.
std::vector<Option> modesAndRun(Args& a) {
    return {
        Option{kModes, "--headless", "",
               "render offscreen through EGL (no display needed)",
               [&a](const char*) -> Verdict { return a.headless = true; },
               ValueKind::None},
        Option{kModes, "--bench", "",
               "fly through a camera path, write timings (needs --out)",
               [&a](const char*) -> Verdict { return a.bench = true; },
               ValueKind::None},
        Option{kModes, "--ui", "",
               "Dear ImGui overlay with timings and setting toggles (window mode)",
               [&a](const char*) -> Verdict { return a.ui = true; },
               ValueKind::None},
        Option{kRun, "--path", "NAME|FILE",
               "camera path: a name in the container (default: its first), or a\n"
               "keyframe JSON file (what pnb-convert --path reads and F9 records)",
               [&a](const char* v) -> Verdict { a.pathName = v; return true; },
               ValueKind::Required},
        Option{kRun, "--camera", "N",
               "stand still at the container's camera N (no path)",
               [&a](const char* v) -> Verdict { uint32_t n = 0; const Verdict ok = count("--camera", v, n); a.camera = int(n); return ok; },
               ValueKind::Required},
        Option{kRun, "--frames", "N",
               "number of frames (window mode: quit after N)",
               [&a](const char* v) -> Verdict { return count("--frames", v, a.frames); },
               ValueKind::Required},
        Option{kRun, "--seconds", "S",
               "stop after S seconds of path time",
               [&a](const char* v) -> Verdict { return positive("--seconds", v, a.seconds); },
               ValueKind::Required},
        Option{kRun, "--fixed-dt", "[DT]",
               "frame k at path time k*DT (default: path duration / frames, or 1/60 s);\n"
               "in the window, every frame moves the camera by DT of time",
               [&a](const char* v) -> Verdict { a.fixedDt = true; return v ? positive("--fixed-dt", v, a.dt) : Verdict(true); },
               ValueKind::Optional},
        Option{kRun, "--size", "WxH",
               "render size (default 512x288 headless, 1280x720 window)",
               [&a](const char* v) -> Verdict { return size(v, a); },
               ValueKind::Required},
        Option{kRun, "--out", "DIR",
               "output directory for --bench and --dump",
               [&a](const char* v) -> Verdict { a.outDir = v; return true; },
               ValueKind::Required},
        Option{kRun, "--screenshot", "FILE",
               "save the output image (PNG) of frame --frame",
               [&a](const char* v) -> Verdict { a.screenshot = v; return true; },
               ValueKind::Required},
        Option{kRun, "--dump", "KIND[,KIND...]",
               "save exact buffers of frame --frame into --out as EXR/PNG:\n"
               "color, hdr, depth, lineardepth, normal, position (camera-relative),\n"
               "shadow (sun visibility, cascade, texel/pixel ratio; with position\n"
               "or shadow, frameK_frame.json holds the camera and light),\n"
               "indirect (the irradiance GI adds, rgb; 0 with GI off),\n"
               "sky (the sky irradiance lighting applies, rgb, lux; 0 without IBL)",
               [&a](const char* v) -> Verdict { splitDumps(v, a.dumps); return true; },
               ValueKind::Required},
        Option{kRun, "--frame", "K",
               "frame for --screenshot and --dump (default 0)",
               [&a](const char* v) -> Verdict { return count("--frame", v, a.frame); },
               ValueKind::Required},
        Option{kRun, "--no-plot", "",
               "do not call the plot script",
               [&a](const char*) -> Verdict { a.plot = false; return true; },
               ValueKind::None},
        Option{kRun, "--lod-metrics", "N",
               "with --bench: replay every N-th frame and compare it with the same view\n"
               "at full detail (lod.force=0): PSNR, pixels off by > 8/255, triangles\n"
               "(quality.csv, \"quality\" in summary.json); with other metrics, the same N",
               [&a](const char* v) -> Verdict { return count("--lod-metrics", v, a.lodMetrics); },
               ValueKind::Required},
    };
}

// The rows of Truth metrics, in --help order.
std::vector<Option> truthMetrics(Args& a) {
    return {
        Option{kTruth, "--shadow-metrics", "N",
               "with --bench: replay every N-th frame (and the view 1/60 s later) and compare\n"
               "the sun's shadows with Embree ray-traced visibility: quality.csv and\n"
               "\"quality\" in summary.json (misclassified %, mean abs error, texel/pixel\n"
               "ratio per cascade, flicker)",
               [&a](const char* v) -> Verdict { return count("--shadow-metrics", v, a.shadowMetrics); },
               ValueKind::Required},
        Option{kTruth, "--gi-metrics", "N",
               "with --bench, on a container with GI: replay every N-th frame (and the\n"
               "view 1/60 s later) and compare the indirect light with the ray-traced\n"
               "one-bounce truth (gi_rmse_pct, gi_energy_ratio, per-colour ratios,\n"
               "gi_leak_pct, the reference's noise, gi_flicker_pct); with\n"
               "--shadow-metrics, N must be the same",
               [&a](const char* v) -> Verdict { return count("--gi-metrics", v, a.giMetrics); },
               ValueKind::Required},
        Option{kTruth, "--sky-metrics", "N",
               "with --bench, on a container with an environment: every N-th frame (and\n"
               "the view 1/60 s later), the sky irradiance the lighting applied (SH x\n"
               "ibl.visibility) against the ray-traced sky light with Embree visibility\n"
               "(sky_rmse_pct, sky_energy_ratio, ..., sky_flicker_pct); same N as the\n"
               "other metrics",
               [&a](const char* v) -> Verdict { return count("--sky-metrics", v, a.skyMetrics); },
               ValueKind::Required},
        Option{kTruth, "--sky-samples", "S",
               "rays per pixel of the sky truth (default 64)",
               [&a](const char* v) -> Verdict { return count("--sky-samples", v, a.skySamples); },
               ValueKind::Required},
        Option{kTruth, "--sky-source", "image|sh",
               "the truth's radiance: the environment image (default; the whole error)\n"
               "or the radiance of the converter's SH (the visibility term's error alone)",
               [&a](const char* v) -> Verdict { return skySource(v, a); },
               ValueKind::Required},
        Option{kTruth, "--gi-samples", "S",
               "rays per pixel of that truth (default 64)",
               [&a](const char* v) -> Verdict { return count("--gi-samples", v, a.giSamples); },
               ValueKind::Required},
        Option{kTruth, "--gi-bounces", "N|converged",
               "diffuse bounces of that truth: 1 (default: one bounce), up to N,\n"
               "or converged (unlimited, Russian roulette)",
               [&a](const char* v) -> Verdict { return giBounces(v, a); },
               ValueKind::Required},
        Option{kTruth, "--gi-lights", "sun|all",
               "light the truth's bounce with the sun alone (default: what GI models)\n"
               "or every light",
               [&a](const char* v) -> Verdict { a.giAllLights = std::string(v) == "all"; return true; },
               ValueKind::Required},
        Option{kTruth, "--frame-metrics", "N",
               "with --bench: every N-th frame, the whole HDR frame against its path-traced\n"
               "truth (Embree, the player's camera and material model, every light, the\n"
               "sky, all bounces): frame_flip_ldr (LDR-FLIP of the displayed images),\n"
               "frame_flip_hdr, frame_relmse (relative MSE, eps 0.01) and the truth's own\n"
               "noise in both (frame_truth_noise_*); same N as the other metrics",
               [&a](const char* v) -> Verdict { return count("--frame-metrics", v, a.frameMetrics); },
               ValueKind::Required},
        Option{kTruth, "--frame-truth-cache", "DIR",
               "keep each whole-frame truth in DIR (created), keyed by the container's\n"
               "bytes, the camera, the size and the truth's settings: later runs of the\n"
               "same frame read it instead of tracing it again",
               [&a](const char* v) -> Verdict {
                   a.frameTruthCache = v;
                   return a.frameTruthCache.empty() ? Verdict::error("--frame-truth-cache needs a directory") : true;
               },
               ValueKind::Required},
        Option{kTruth, "--frame-truth-scene", "FILE.pnb",
               "trace the truth from this container instead (the same scene converted\n"
               "without lossy options: the error of quantisation and compression)",
               [&a](const char* v) -> Verdict {
                   a.frameTruthScene = v;
                   return a.frameTruthScene.empty() ? Verdict::error("--frame-truth-scene needs a file") : true;
               },
               ValueKind::Required},
        Option{kTruth, "--frame-bounces", "N",
               "bounces of the whole-frame truth after the first hit (default 16; 0: direct\n"
               "light only)",
               [&a](const char* v) -> Verdict { return count("--frame-bounces", v, a.frameBounces); },
               ValueKind::Required},
        Option{kTruth, "--frame-noise", "X",
               "the truth's relative noise target, as the relMSE its noise alone gives\n"
               "(default 0.003)",
               [&a](const char* v) -> Verdict { return positive("--frame-noise", v, a.frameNoise); },
               ValueKind::Required},
        Option{kTruth, "--frame-samples", "S",
               "most paths per pixel of the truth (default 4096)",
               [&a](const char* v) -> Verdict { return count("--frame-samples", v, a.frameMaxSamples); },
               ValueKind::Required},
        Option{kTruth, "--frame-time-limit", "SECONDS",
               "stop tracing the truth after the pass that crosses it (default 120)",
               [&a](const char* v) -> Verdict { return positive("--frame-time-limit", v, a.frameTimeLimit); },
               ValueKind::Required},
        Option{kTruth, "--error-maps", "",
               "with --bench and a metric (--lod-metrics or a truth metric): heat-maps of the last measured frame\n"
               "(not its follow-up) into --out, lined up with --screenshot images:\n"
               "error_shadow.png (dark grey unclassified, light greys correct lit /\n"
               "shadowed, red false lit, blue false shadow; brighter = larger\n"
               "|player - truth|), error_gi.png and error_sky.png (|player - truth|\n"
               "luminance / mean truth luminance, magma ramp black..pale yellow up to\n"
               "100 %; dark grey unmeasured), error_lod.png (largest RGB difference to\n"
               "full detail, same ramp up to 32/255); compare_gi.png, compare_sky.png\n"
               "(player | truth | difference side by side); error_frame.png (LDR-FLIP,\n"
               "magma), compare_frame.png (player | truth | FLIP); error_maps.json: legends",
               [&a](const char*) -> Verdict { return a.errorMaps = true; },
               ValueKind::None},
    };
}

// The rows of Window and Settings, in --help order.
std::vector<Option> windowAndSettings(Args& a) {
    return {
        text(kWindow, "WASD move, Q/E down/up, Shift faster, right-drag look, O orbit (left-drag, W/S in/out)\n"
             "wheel: fly speed (x1.25 a notch); Ctrl+wheel or right button+wheel: field of view (5..120 deg)\n"
             "F9 start/stop recording a camera path, K add a key now, F12 screenshot, Esc or close: quit\n"
             "drop a .pnb to open it, or a .gltf/.glb/.obj to convert it first (child pnb-convert:\n"
             "$PNB_CONVERT, else beside pnb-play, else on PATH); a file that fails to open changes nothing"),
        Option{kWindow, "--record-path", "FILE",
               "where F9 saves the path (default recorded_path.json; an existing file\n"
               "is kept and NAME-2.json, NAME-3.json, ... used instead)",
               [&a](const char* v) -> Verdict { a.recordPath = v; return true; },
               ValueKind::Required},
        Option{kWindow, "--record-every", "S",
               "while recording, also add a key every S seconds",
               [&a](const char* v) -> Verdict { return positive("--record-every", v, a.recordEvery); },
               ValueKind::Required},
        Option{kWindow, "--screenshot-dir", "DIR",
               "where F12 saves pnb-play-DATE-TIME-NNN.png (default: current directory)",
               [&a](const char* v) -> Verdict { a.screenshotDir = v; return true; },
               ValueKind::Required},
        Option{kWindow, "--script-input", "FILE",
               "replay timed input events (keys, mouse, wheel, drops, close, iconify;\n"
               "format in player/tools/input_actions.h); real input is then ignored",
               [&a](const char* v) -> Verdict { a.scriptInput = v; return true; },
               ValueKind::Required},
        Option{kSettings, "--set", "KEY=VALUE",
               "e.g. --set lighting.exposure=1.5 (repeatable)",
               [&a](const char* v) -> Verdict { a.sets.push_back(v); return true; },
               ValueKind::Required},
        Option{kSettings, "--list-settings", "",
               "print every key, its type and meaning",
               [&a](const char*) -> Verdict { a.listSettings = true; return Verdict::stopHere(); },
               ValueKind::None},
    };
}

// The rows of Start-up, Streaming and Other (with the hidden -h), in --help order.
std::vector<Option> startUpAndOther(Args& a, bool& help) {
    return {
        Option{kStartUp, "--program-cache", "DIR",
               "keep linked program binaries in DIR (default: $PNB_PROGRAM_CACHE_DIR,\n"
               "else $XDG_CACHE_HOME/penumbra/programs, else ~/.cache/penumbra/programs)",
               [&a](const char* v) -> Verdict { return programCache(v, a); },
               ValueKind::Required},
        Option{kStartUp, "--no-program-cache", "",
               "compile and link every program from source, write no entries",
               [&a](const char*) -> Verdict { a.programCache = false; return true; },
               ValueKind::None},
        text(kStartUp, "--set startup.warmup=false   no warm-up draws during load (code generation then lands in the\n"
             "                        frames that first draw each state; for measuring)"),
        Option{kStreaming, "--stream", "",
               "draw the first frame once the scene's structure and each texture's\n"
               "smallest mip are in; the texels stream in while frames are drawn\n"
               "(the default in the window and for '-'; settings stream.budget_mib,\n"
               "stream.upload_mib)",
               [&a](const char*) -> Verdict { a.stream = 1; return true; },
               ValueKind::None},
        Option{kStreaming, "--no-stream", "",
               "load everything before the first frame (the default for --headless\n"
               "and --bench, whose frames then do not depend on the loader's timing)",
               [&a](const char*) -> Verdict { a.stream = 0; return true; },
               ValueKind::None},
        Option{kOther, "--no-checksums", "",
               "skip payload checksum verification when loading",
               [&a](const char*) -> Verdict { a.checksums = false; return true; },
               ValueKind::None},
        Option{kOther, "--gl-debug", "",
               "report GL performance messages too",
               [&a](const char*) -> Verdict { return a.glDebug = true; },
               ValueKind::None},
        Option{kOther, "-q, --quiet", "",
               "print only errors",
               [&a](const char*) -> Verdict { return a.quiet = true; },
               ValueKind::None},
        Option{kOther, "-h, --help", "", "", [&help](const char*) -> Verdict {
                   help = true;
                   return Verdict::stopHere();
               },
               ValueKind::None, /*hidden=*/true},
    };
}

// The whole table, in --help order (split by section only to keep each function short).
std::vector<Option> options(Args& a, bool& help) {
    std::vector<Option> table;
    for (std::vector<Option> part : {modesAndRun(a), truthMetrics(a), windowAndSettings(a), startUpAndOther(a, help)})
        table.insert(table.end(), std::make_move_iterator(part.begin()), std::make_move_iterator(part.end()));
    return table;
}

const char* gProgram = "pnb-play";

int usageError(const std::string& message) {
    std::fprintf(stderr, "%s: %s\n(run %s --help for usage)\n", gProgram, message.c_str(), gProgram);
    return 1;
}

void printUsage(const std::vector<Option>& table) {
    // The usage lines name the player that runs (pnb-judge takes the same options).
    std::printf("usage: %s SCENE.pnb [options]\n"
                "       cat SCENE.pnb | %s - [options]     (streams from standard input)\n",
                gProgram, gProgram);
    std::fputs(pnb::cli::helpText(table, {.column = 26}).c_str(), stdout);
    std::printf("\nExit codes: 0 ok, 1 usage, 2 bad input, 3 GL or output failure.\n");
}

// What the options ask for together: files that must not collide, options that need others.
std::optional<int> checkCombination(const Args& a) {
    if (a.scene.empty()) return usageError("no scene given");
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
            return usageError(st.message);
    }
    if (a.bench && a.outDir.empty()) return usageError("--bench needs --out DIR");
    if (!a.dumps.empty() && a.outDir.empty()) return usageError("--dump needs --out DIR");
    if (a.errorMaps && (!a.bench || !(a.shadowMetrics || a.giMetrics || a.skyMetrics || a.lodMetrics || a.frameMetrics)))
        return usageError("--error-maps needs --bench and at least one of --shadow-metrics, --gi-metrics, "
                   "--sky-metrics, --frame-metrics, --lod-metrics (the maps show what those measure)");
    if ((!a.frameTruthCache.empty() || !a.frameTruthScene.empty()) && a.frameMetrics == 0)
        return usageError("--frame-truth-cache and --frame-truth-scene go with --frame-metrics");
    if (a.stream == 0 && a.scene == "-") return usageError("'-' (standard input) is read by streaming: drop --no-stream");
    if (!a.scriptInput.empty() && (a.headless || a.bench))
        return usageError("--script-input drives the window (not --headless or --bench)");
    return std::nullopt;
}

} // namespace

std::optional<int> parsePlayOptions(int argc, char** argv, const char* program, Args& a) {
    gProgram = program;
    bool help = false;
    const std::vector<Option> table = options(a, help);
    auto scene = [&a](const char* arg) {
        if (!a.scene.empty())
            return Verdict::error("more than one scene given ('" + a.scene + "', '" + arg + "')");
        a.scene = arg;
        return Verdict(true);
    };
    if (auto e = pnb::cli::parse(table, scene, argc, argv)) {
        using Kind = pnb::cli::ParseError::Kind;
        switch (e->kind) {
        case Kind::UnknownOption: return usageError("unknown option " + e->option);
        case Kind::MissingValue: return usageError(e->option + " needs a value");
        default: return usageError(pnb::cli::describe(*e));
        }
    }
    if (help) {
        printUsage(table);
        return 0;
    }
    if (a.listSettings) {
        for (const SettingInfo& info : settingInfos())
            std::printf("%-20s %-24s %s\n", std::string(info.key).c_str(), std::string(info.type).c_str(),
                        std::string(info.description).c_str());
        return 0;
    }
    return checkCombination(a);
}

} // namespace pnb::player
