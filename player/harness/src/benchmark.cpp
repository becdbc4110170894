// The benchmark run (pnb_player/benchmark.h): plan the frames, time them, check the last one,
// replay for the quality hook, then write the reports (bench_report.cpp) and the plot.
#include "pnb_player/benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "bench_records.h"
#include "bench_report.h"
#include "plot_script.h"
#include "pnb_player/camera_path.h"

namespace pnb::player {

namespace {

using Clock = std::chrono::steady_clock;

double msBetween(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

// Which frames to draw: the path, its start, the step and the frame count.
PlayResult<RunPlan> planRun(const GpuScene& scene, const BenchOptions& options) {
    RunPlan plan;
    plan.path = options.staticCamera ? nullptr : scene.findPath(options.pathName);
    if (!options.staticCamera && !options.pathName.empty() && !plan.path)
        return PlayError{PlayErrorKind::Usage, "no camera path named '" + options.pathName + "'"};
    const ScenePath* path = plan.path;
    plan.start = path && !path->path.keys.empty() ? path->path.keys.front().timeSeconds : 0.0;
    plan.duration = path ? pathDuration(path->path) : 0.0;
    plan.span = options.seconds > 0 ? options.seconds : plan.duration;
    plan.dt = options.dt;
    if (options.fixedDt && options.frames > 0 && plan.span > 0) plan.dt = plan.span / options.frames;
    plan.frames = options.frames;
    if (plan.frames == 0)
        plan.frames = options.fixedDt ? uint32_t(std::max(1.0, std::ceil(plan.span / plan.dt))) : ~0u;
    if (plan.span <= 0 && options.frames == 0) plan.frames = 1; // a static camera and no frame count
    return plan;
}

PlayResult<Done> makeOutputDirectory(const BenchOptions& options) {
    if (options.outDir.empty()) return Done{};
    std::error_code ec;
    std::filesystem::create_directories(options.outDir, ec);
    if (ec) return PlayError{PlayErrorKind::Io, "cannot create " + options.outDir + ": " + ec.message()};
    return Done{};
}

// Moves the renderer's finished GPU timings into the records (keyed by this run's frame index).
void collectGpuTimes(Renderer& renderer, std::vector<FrameRecord>& records) {
    for (FrameGpuTimes& f : renderer.timer().completed()) {
        if (f.frame >= records.size()) continue;
        FrameRecord& r = records[f.frame];
        for (const PassTime& p : f.passes) r.gpu[p.pass] += p.ms;
        r.gpuTotal = f.totalMs;
    }
    renderer.timer().completed().clear();
}

// The captures asked for at frame k, and what a ground-truth tracer needs beside them.
PlayResult<Done> saveCaptures(const GpuScene& scene, Renderer& renderer, const BenchOptions& options,
                              uint32_t k, BenchResult& result) {
    for (const CaptureRequest& c : options.captures) {
        if (c.frame != k) continue;
        auto img = renderer.capture(c.buffer);
        if (!img) return img.error();
        if (c.buffer == CaptureBuffer::Hdr)
            if (size_t bad = nonFinitePixels(*img))
                result.warnings.push_back("frame " + std::to_string(k) + ": " + std::to_string(bad) +
                                          " pixels of the HDR buffer are NaN or infinite");
        if (auto s = saveCapture(c.path, *img); !s) return s.error();
        result.written.push_back(c.path);
        if (c.buffer == CaptureBuffer::Position || c.buffer == CaptureBuffer::Shadow ||
            c.buffer == CaptureBuffer::ShadowColor || c.buffer == CaptureBuffer::Sky) {
            // frame<N>_<buffer>.exr -> frame<N>_frame.json (a buffer's name may hold a '_')
            const size_t name = c.path.rfind('/') == std::string::npos ? 0 : c.path.rfind('/') + 1;
            std::string jsonPath = c.path.substr(0, c.path.find('_', name)) + "_frame.json";
            if (auto w = writeTextFile(jsonPath, tracerFrameJson(scene, renderer, options)); !w) return w.error();
            if (std::find(result.written.begin(), result.written.end(), jsonPath) == result.written.end())
                result.written.push_back(jsonPath);
        }
    }
    return Done{};
}

// The timed fly-through: one record per frame drawn, captures as asked, GPU timings collected.
PlayResult<TimedRun> runTimedFrames(const GpuScene& scene, Renderer& renderer, const BenchOptions& options,
                                    const RunPlan& plan, const std::function<bool()>& present,
                                    BenchResult& result) {
    TimedRun run;
    run.camera = options.staticCamera ? *options.staticCamera : initialCamera(scene, options.pathName);
    std::vector<FrameRecord>& records = run.records;
    const auto wallStart = Clock::now();
    auto lastFrameStart = wallStart;
    for (uint32_t k = 0; k < plan.frames && k <= options.lastFrame; ++k) {
        double t = options.fixedDt ? double(k) * plan.dt
                                   : std::chrono::duration<double>(Clock::now() - wallStart).count();
        if (!options.fixedDt && options.frames == 0 && plan.span > 0 && t > plan.span) break;
        if (plan.path) evaluatePath(plan.path->path, plan.start + t, run.camera);
        const auto frameStart = Clock::now();
        if (!records.empty()) records.back().frameMs = msBetween(lastFrameStart, frameStart);
        lastFrameStart = frameStart;
        FrameRecord rec;
        if (options.stream) {
            if (auto u = options.stream->update(run.camera, options.width, options.height); !u) return u.error();
            rec.streamMs = msBetween(frameStart, Clock::now());
            rec.stream = options.stream->status();
            if (rec.stream.complete && !run.fullQualityMs) run.fullQualityMs = msBetween(wallStart, Clock::now());
        }
        // Playback follows the same clock as the path: the fixed step in headless runs, so two
        // runs pose frame k identically (anim.*, docs/PLAYER.md "Animation").
        renderer.setAnimationClock(t);
        if (auto r = renderer.render(run.camera, options.width, options.height); !r) return r.error();
        rec.pathTime = t;
        rec.stats = renderer.lastFrame();
        rec.cameraPosition = run.camera.position;
        rec.cameraYfovDegrees = glm::degrees(double(run.camera.yfovRadians));
        records.push_back(rec);
        // Timer results are keyed by the renderer's frame number; map them to this run's index.
        for (FrameGpuTimes& f : renderer.timer().completed()) f.frame -= rec.stats.frame - k;
        collectGpuTimes(renderer, records);
        if (auto s = saveCaptures(scene, renderer, options, k, result); !s) return s.error();
        if (options.progress) {
            const uint32_t planned = options.lastFrame == ~0u ? plan.frames : std::min(plan.frames, options.lastFrame + 1);
            options.progress(k + 1, planned == ~0u ? 0 : planned,
                             std::chrono::duration<double>(Clock::now() - wallStart).count());
        }
        if (present && !present()) break;
    }
    if (!records.empty()) records.back().frameMs = msBetween(lastFrameStart, Clock::now());
    // The last frames' timers: wait for them now that nothing else is queued.
    uint64_t lastRendererFrame = renderer.lastFrame().frame;
    renderer.timer().drain();
    for (FrameGpuTimes& f : renderer.timer().completed()) f.frame -= lastRendererFrame - (records.size() - 1);
    collectGpuTimes(renderer, records);
    result.frames = uint32_t(records.size());
    return run;
}

// The frame check: a NaN or an infinity in the last frame's radiance would otherwise pass as a
// black or white patch (a light the shaders overflow on, a degenerate input).
PlayResult<Done> checkLastFrame(Renderer& renderer, BenchResult& result) {
    if (result.frames == 0) return Done{};
    auto hdr = renderer.capture(CaptureBuffer::Hdr);
    if (!hdr) return hdr.error();
    result.nonFinitePixels = nonFinitePixels(*hdr);
    if (result.nonFinitePixels)
        result.warnings.push_back("the last frame (" + std::to_string(result.frames - 1) + "): " +
                                  std::to_string(result.nonFinitePixels) + " of " +
                                  std::to_string(size_t(hdr->width) * hdr->height) +
                                  " pixels of the HDR buffer are NaN or infinite");
    return Done{};
}

// The quality pass: every `every`-th timed frame again, and the view 1/60 s after it, measured by
// the caller's hook (after the timed run, so measuring costs no timing).
PlayResult<QualityTable> runQualityPass(Renderer& renderer, const BenchOptions& options, const RunPlan& plan,
                                        TimedRun& run) {
    QualityTable table;
    if (options.quality.every == 0 || !options.quality.measure) return table;
    std::vector<std::string> columns;
    std::vector<std::pair<uint32_t, std::map<std::string, double>>> rows;
    for (uint32_t k = 0; k < run.records.size(); k += options.quality.every) {
        std::map<std::string, double> row;
        for (bool followUp : {false, true}) {
            if (plan.path)
                evaluatePath(plan.path->path, plan.start + run.records[k].pathTime + (followUp ? 1.0 / 60.0 : 0.0),
                             run.camera);
            renderer.setAnimationClock(run.records[k].pathTime + (followUp ? 1.0 / 60.0 : 0.0));
            if (auto r = renderer.render(run.camera, options.width, options.height); !r) return r.error();
            auto m = options.quality.measure(k, renderer, followUp);
            if (!m) return m.error();
            for (const auto& [name, value] : *m) {
                if (std::find(columns.begin(), columns.end(), name) == columns.end()) columns.push_back(name);
                if (!followUp || !row.count(name)) row[name] = value;
            }
        }
        rows.emplace_back(k, std::move(row));
    }
    renderer.timer().drain();
    renderer.timer().completed().clear();
    return qualityTable(columns, rows);
}

// Per-pass GPU statistics over the frames that have timings, then the total; CPU time.
void summarizeTimes(const std::vector<FrameRecord>& records, const std::vector<std::string>& passNames,
                    BenchResult& result) {
    std::vector<double> cpu, total;
    for (const std::string& name : passNames) {
        std::vector<double> v;
        for (const FrameRecord& r : records)
            if (r.gpuTotal >= 0) v.push_back(r.gpu.count(name) ? r.gpu.at(name) : 0.0);
        result.gpu.push_back(summarize(name, v));
    }
    for (const FrameRecord& r : records) {
        cpu.push_back(r.stats.cpuMs);
        if (r.gpuTotal >= 0) total.push_back(r.gpuTotal);
    }
    result.gpu.push_back(summarize("total", total));
    result.cpu = summarize("cpu", cpu);
}

// frames.csv, quality.csv (with a quality pass) and summary.json, in that order.
PlayResult<Done> writeReports(const SummaryInputs& in, const std::vector<std::string>& passNames,
                              BenchResult& result) {
    const std::string& outDir = in.options.outDir;
    std::string csvPath = outDir + "/frames.csv";
    if (auto w = writeTextFile(csvPath, framesCsv(in.run.records, passNames, in.options.stream != nullptr,
                                                      in.scene.animation != nullptr)); !w)
        return w.error();
    result.written.push_back(csvPath);
    if (!in.quality.summary.empty()) {
        std::string qualityPath = outDir + "/quality.csv";
        if (auto w = writeTextFile(qualityPath, in.quality.csv); !w) return w.error();
        result.written.push_back(qualityPath);
    }
    std::string jsonPath = outDir + "/summary.json";
    if (auto w = writeTextFile(jsonPath, summaryJson(in, result).dump(2) + "\n"); !w) return w.error();
    result.written.push_back(jsonPath);
    return Done{};
}

// frame_times.png from frames.csv (plot_frames.py); a missing matplotlib is a warning, not an error.
void plotFrameTimes(const GpuScene& scene, const BenchOptions& options, BenchResult& result) {
    if (!options.plot) return;
    std::string csvPath = options.outDir + "/frames.csv";
    std::string png = options.outDir + "/frame_times.png";
    std::string title = scene.name + " " + std::to_string(options.width) + "x" + std::to_string(options.height);
    std::replace(title.begin(), title.end(), '\'', ' ');
    std::string args = "'" + csvPath + "' '" + png + "' --title '" + title + "' 2>&1";
    if (runPlotScript(options.outDir, args)) result.written.push_back(png);
    else std::fprintf(stderr, "pnb-play: warning: plot not written (needs python3-matplotlib)\n");
}

} // namespace

PlayResult<BenchResult> runBenchmark(const GpuScene& scene, Renderer& renderer,
                                     const BenchOptions& options, const LoadStats& load,
                                     const GlInfo& gl, const std::function<bool()>& present) {
    auto plan = planRun(scene, options);
    if (!plan) return plan.error();
    if (auto d = makeOutputDirectory(options); !d) return d.error();
    BenchResult result;
    auto run = runTimedFrames(scene, renderer, options, *plan, present, result);
    if (!run) return run.error();
    if (auto c = checkLastFrame(renderer, result); !c) return c.error();
    auto quality = runQualityPass(renderer, options, *plan, *run);
    if (!quality) return quality.error();
    const std::vector<std::string> passNames = orderedPassNames(run->records);
    summarizeTimes(run->records, passNames, result);
    if (options.outDir.empty()) return result;
    SummaryInputs in{scene, renderer, options, load, gl, *plan, *run, *quality};
    if (auto w = writeReports(in, passNames, result); !w) return w.error();
    plotFrameTimes(scene, options, result);
    return result;
}

} // namespace pnb::player
