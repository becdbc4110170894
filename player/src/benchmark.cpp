#include "pnb_player/benchmark.h"

#include <sys/resource.h>
#include <sys/utsname.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "player_tools.h"
#include "pnb_player/camera_path.h"
#include "pnb_player/image_write.h"

namespace pnb::player {

namespace {

struct FrameRecord {
    double pathTime = 0;
    FrameStats stats;
    std::map<std::string, double> gpu; // summed per pass name
    double gpuTotal = -1;              // -1 = not measured
    glm::dvec3 cameraPosition{0.0};
    double cameraYfovDegrees = 0;
    double frameMs = 0;  // wall time from this frame's start to the next one's
    double streamMs = 0; // SceneStream::update
    StreamStatus stream; // after this frame's update
};

PassSummary summarize(std::string name, std::vector<double> v) {
    PassSummary s;
    s.pass = std::move(name);
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    auto at = [&](double q) { return v[size_t(std::min(q * double(v.size() - 1) + 0.5, double(v.size() - 1)))]; };
    s.min = v.front();
    s.median = at(0.5);
    s.p95 = at(0.95);
    s.max = v.back();
    return s;
}

nlohmann::json toJson(const PassSummary& s) {
    return {{"min_ms", s.min}, {"median_ms", s.median}, {"p95_ms", s.p95}, {"max_ms", s.max}};
}

std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown";
}

PlayResult<Done> writeText(const std::string& path, const std::string& text) {
    Status s = writeFileAtomic(path, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    if (!isOk(s)) return PlayError{PlayErrorKind::Io, s.describe()};
    return Done{};
}

// Debian's python3-matplotlib belongs to /usr/bin/python3, which a user's PATH may shadow
// (pyenv, venvs); PNB_PYTHON overrides.
std::string python() {
    if (const char* env = std::getenv("PNB_PYTHON")) return env;
    return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

// Runs player/tools/plot_frames.py with ARGS (already shell-quoted); true on exit status 0. The
// script is embedded in the library (player_tools.h), so an installed pnb-play plots from any
// directory: it is written next to the outputs in OUT_DIR for the run and removed afterwards.
// $PNB_PLOT_SCRIPT names a script file to run instead.
bool runPlotScript(const std::string& outDir, const std::string& args) {
    std::string script;
    bool temporary = false;
    if (const char* env = std::getenv("PNB_PLOT_SCRIPT")) {
        script = env;
    } else {
        script = outDir + "/.plot_frames.py";
        for (const EmbeddedFile& f : kPlayerTools) {
            if (f.name != "plot_frames.py") continue;
            std::ofstream out(script, std::ios::binary | std::ios::trunc);
            out.write(f.text.data(), std::streamsize(f.text.size()));
            if (!out) return false;
            temporary = true;
        }
        if (!temporary) return false;
    }
    std::string cmd = python() + " '" + script + "' " + args;
    bool ok = std::system(cmd.c_str()) == 0;
    if (temporary) {
        std::error_code ec;
        std::filesystem::remove(script, ec);
    }
    return ok;
}

} // namespace

CameraState sceneCamera(const GpuScene& scene, size_t index) {
    const SceneCamera& c = scene.cameras[index];
    CameraState cam;
    cam.position = c.position;
    cam.rotation = c.rotation;
    cam.yfovRadians = c.desc.yfovRadians;
    cam.znear = c.desc.znear;
    cam.zfar = c.desc.zfar;
    cam.projection = c.desc.projection;
    cam.ymag = c.desc.ymag;
    return cam;
}

CameraState initialCamera(const GpuScene& scene, const std::string& pathName) {
    CameraState cam;
    if (!scene.cameras.empty()) {
        cam = sceneCamera(scene, 0);
    } else {
        cam = framingCamera(scene.bounds, 0.8f);
    }
    if (const ScenePath* p = scene.findPath(pathName); p && !p->path.keys.empty())
        evaluatePath(p->path, p->path.keys.front().timeSeconds, cam);
    return cam;
}

PlayResult<Done> saveCapture(const std::string& path, const CapturedImage& image) {
    ImageView view{image.width, image.height, image.channels, {}, {}};
    size_t row = size_t(image.width) * image.channels;
    Status s;
    if (!image.u8.empty()) {
        std::vector<uint8_t> flipped(image.u8.size());
        for (uint32_t y = 0; y < image.height; ++y)
            std::copy_n(image.u8.data() + size_t(image.height - 1 - y) * row, row, flipped.data() + y * row);
        view.u8 = flipped;
        s = writePng(path, view);
    } else {
        std::vector<float> flipped(image.f32.size());
        for (uint32_t y = 0; y < image.height; ++y)
            std::copy_n(image.f32.data() + size_t(image.height - 1 - y) * row, row, flipped.data() + y * row);
        view.f32 = flipped;
        s = writeExr(path, view);
    }
    if (!isOk(s)) return PlayError{PlayErrorKind::Io, s.describe()};
    return Done{};
}

// summary.json's "streaming": what it cost to draw while the texels streamed in.
nlohmann::json streamingSummary(const std::vector<FrameRecord>& records, const SceneStream& stream,
                                std::optional<double> fullQualityMs, const std::optional<StartupTimes>& startup) {
    const StreamStatus& last = stream.status();
    std::vector<double> frameMs, during, after, uploads;
    for (const FrameRecord& r : records) {
        frameMs.push_back(r.frameMs);
        (r.stream.complete ? after : during).push_back(r.frameMs);
        uploads.push_back(double(r.stream.frame.uploadedBytes));
    }
    const double median = summarize("", frameMs).median;
    uint32_t stalls = 0;
    for (double ms : frameMs) stalls += ms > 2 * median;
    nlohmann::json j = {
        {"complete", last.complete},
        {"frames_streaming", during.size()},
        {"file_bytes", last.fileBytes},
        {"budget_bytes", stream.options().budgetBytes},
        {"upload_bytes_per_frame_limit", stream.options().uploadBytesPerFrame},
        {"full_bytes", last.fullBytes},
        {"peak_bytes", last.peakBytes},
        {"resident_bytes", last.residentBytes},
        {"resident_mesh_bytes", last.residentMeshBytes},
        {"needed_bytes", last.neededBytes},
        {"uploaded_bytes", last.uploadedBytes},
        {"uploaded_bytes_per_frame", {{"median", summarize("", uploads).median}, {"p95", summarize("", uploads).p95},
                                      {"max", summarize("", uploads).max}}},
        {"evicted_bytes", last.evictedBytes},
        {"evictions", last.evictions},
        {"refetches", last.refetches},
        {"lost_levels", last.lostLevels},
        {"meshes_replaced", last.meshesReplaced},
        {"stalls", stalls},
        {"frame_ms_median", median},
        {"frame_ms_p95_streaming", during.empty() ? nlohmann::json() : nlohmann::json(summarize("", during).p95)},
        {"frame_ms_p95_after", after.empty() ? nlohmann::json() : nlohmann::json(summarize("", after).p95)}};
    j["first_frame_bytes_read"] = last.firstFrameBytesRead;
    // From the process start (the time to first frame) when known, else from the first timed frame.
    if (fullQualityMs) j["time_to_full_quality_ms"] = *fullQualityMs + (startup ? startup->totalMs : 0.0);
    return j;
}

PlayResult<BenchResult> runBenchmark(const GpuScene& scene, Renderer& renderer,
                                     const BenchOptions& options, const LoadStats& load,
                                     const GlInfo& gl, const std::function<bool()>& present) {
    const ScenePath* path = options.staticCamera ? nullptr : scene.findPath(options.pathName);
    if (!options.staticCamera && !options.pathName.empty() && !path)
        return PlayError{PlayErrorKind::Usage, "no camera path named '" + options.pathName + "'"};
    double start = path && !path->path.keys.empty() ? path->path.keys.front().timeSeconds : 0.0;
    double duration = path ? pathDuration(path->path) : 0.0;
    double span = options.seconds > 0 ? options.seconds : duration;
    double dt = options.dt;
    if (options.fixedDt && options.frames > 0 && span > 0) dt = span / options.frames;
    uint32_t frames = options.frames;
    if (frames == 0) frames = options.fixedDt ? uint32_t(std::max(1.0, std::ceil(span / dt))) : ~0u;
    if (span <= 0 && options.frames == 0) frames = 1; // a static camera and no frame count
    if (!options.outDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(options.outDir, ec);
        if (ec) return PlayError{PlayErrorKind::Io, "cannot create " + options.outDir + ": " + ec.message()};
    }

    CameraState camera = options.staticCamera ? *options.staticCamera : initialCamera(scene, options.pathName);
    std::vector<FrameRecord> records;
    BenchResult result;
    auto wallStart = std::chrono::steady_clock::now();
    auto lastFrameStart = wallStart;
    std::optional<double> fullQualityMs; // from the first timed frame to the stream's completion
    auto collect = [&] {
        for (FrameGpuTimes& f : renderer.timer().completed()) {
            if (f.frame >= records.size()) continue;
            FrameRecord& r = records[f.frame];
            for (const PassTime& p : f.passes) r.gpu[p.pass] += p.ms;
            r.gpuTotal = f.totalMs;
        }
        renderer.timer().completed().clear();
    };
    for (uint32_t k = 0; k < frames && k <= options.lastFrame; ++k) {
        double t = options.fixedDt
                       ? double(k) * dt
                       : std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
        if (!options.fixedDt && options.frames == 0 && span > 0 && t > span) break;
        if (path) evaluatePath(path->path, start + t, camera);
        const auto frameStart = std::chrono::steady_clock::now();
        if (!records.empty())
            records.back().frameMs = std::chrono::duration<double, std::milli>(frameStart - lastFrameStart).count();
        lastFrameStart = frameStart;
        FrameRecord rec;
        if (options.stream) {
            if (auto u = options.stream->update(camera, options.width, options.height); !u) return u.error();
            rec.streamMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameStart).count();
            rec.stream = options.stream->status();
            if (rec.stream.complete && !fullQualityMs)
                fullQualityMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wallStart).count();
        }
        auto r = renderer.render(camera, options.width, options.height);
        if (!r) return r.error();
        rec.pathTime = t;
        rec.stats = renderer.lastFrame();
        rec.cameraPosition = camera.position;
        rec.cameraYfovDegrees = glm::degrees(double(camera.yfovRadians));
        records.push_back(rec);
        // Timer results are keyed by the renderer's frame number; map them to this run's index.
        for (FrameGpuTimes& f : renderer.timer().completed()) f.frame -= rec.stats.frame - k;
        collect();
        for (const CaptureRequest& c : options.captures) {
            if (c.frame != k) continue;
            auto img = renderer.capture(c.buffer);
            if (!img) return img.error();
            if (c.buffer == CaptureBuffer::Hdr)
                if (size_t bad = nonFinitePixels(*img))
                    result.warnings.push_back("frame " + std::to_string(k) + ": " +
                                              std::to_string(bad) + " pixels of the HDR buffer "
                                              "are NaN or infinite");
            if (auto s = saveCapture(c.path, *img); !s) return s.error();
            result.written.push_back(c.path);
            if (c.buffer == CaptureBuffer::Position || c.buffer == CaptureBuffer::Shadow ||
                c.buffer == CaptureBuffer::Sky) {
                // What a ground-truth tracer needs besides the buffers (docs/REFERENCE.md).
                std::string jsonPath = c.path.substr(0, c.path.rfind('_')) + "_frame.json";
                glm::dvec3 eye = renderer.lastView().position;
                glm::vec3 toward = towardShadowingSun(scene);
                nlohmann::json fj = {{"camera_position", {eye.x, eye.y, eye.z}},
                                     {"toward_light", {toward.x, toward.y, toward.z}},
                                     {"width", options.width}, {"height", options.height},
                                     // The environment as lit (pnb-reference --sky reads them).
                                     {"ibl_rotation_degrees", renderer.settings().iblRotationDeg},
                                     {"ibl_intensity", renderer.settings().iblIntensity}};
                // A point or spot light judged (shadows.judged_light): pnb-reference traces that
                // light, placed as the container places it.
                if (renderer.settings().shadowJudgedLight >= 0)
                    fj["shadow_light_index"] = renderer.settings().shadowJudgedLight;
                if (auto w = writeText(jsonPath, fj.dump(2) + "\n"); !w) return w.error();
                if (std::find(result.written.begin(), result.written.end(), jsonPath) == result.written.end())
                    result.written.push_back(jsonPath);
            }
        }
        if (options.progress) {
            const uint32_t planned =
                options.lastFrame == ~0u ? frames : std::min(frames, options.lastFrame + 1);
            options.progress(k + 1, planned == ~0u ? 0 : planned,
                             std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count());
        }
        if (present && !present()) break;
    }
    if (!records.empty())
        records.back().frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - lastFrameStart).count();
    // The last frames' timers: wait for them now that nothing else is queued.
    uint64_t lastRendererFrame = renderer.lastFrame().frame;
    renderer.timer().drain();
    for (FrameGpuTimes& f : renderer.timer().completed())
        f.frame -= lastRendererFrame - (records.size() - 1);
    collect();
    result.frames = uint32_t(records.size());
    // The frame check: a NaN or an infinity in the last frame's radiance would otherwise pass
    // as a black or white patch (a light the shaders overflow on, a degenerate input).
    if (!records.empty()) {
        auto hdr = renderer.capture(CaptureBuffer::Hdr);
        if (!hdr) return hdr.error();
        result.nonFinitePixels = nonFinitePixels(*hdr);
        if (result.nonFinitePixels)
            result.warnings.push_back("the last frame (" + std::to_string(result.frames - 1) +
                                      "): " + std::to_string(result.nonFinitePixels) + " of " +
                                      std::to_string(size_t(hdr->width) * hdr->height) +
                                      " pixels of the HDR buffer are NaN or infinite");
    }

    // The quality pass: the same frames again, measured by the caller's hook.
    nlohmann::json quality = nlohmann::json::object();
    std::ostringstream qualityCsv;
    if (options.quality.every > 0 && options.quality.measure) {
        std::vector<std::string> columns;
        std::vector<std::pair<uint32_t, std::map<std::string, double>>> rows;
        for (uint32_t k = 0; k < records.size(); k += options.quality.every) {
            std::map<std::string, double> row;
            for (bool followUp : {false, true}) {
                if (path) evaluatePath(path->path, start + records[k].pathTime + (followUp ? 1.0 / 60.0 : 0.0), camera);
                if (auto r = renderer.render(camera, options.width, options.height); !r) return r.error();
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
        qualityCsv << "frame";
        for (const std::string& c : columns) qualityCsv << ',' << c;
        qualityCsv << '\n';
        for (const auto& [k, row] : rows) {
            qualityCsv << k;
            for (const std::string& c : columns) {
                qualityCsv << ',';
                if (row.count(c)) qualityCsv << row.at(c);
            }
            qualityCsv << '\n';
        }
        for (const std::string& c : columns) {
            std::vector<double> v;
            for (const auto& [k, row] : rows)
                if (row.count(c)) v.push_back(row.at(c));
            PassSummary ps = summarize(c, v);
            double mean = 0;
            for (double x : v) mean += x / double(v.size());
            quality[c] = {{"mean", mean}, {"median", ps.median}, {"p95", ps.p95}, {"max", ps.max},
                          {"frames", v.size()}};
        }
    }

    // Per-pass statistics over frames that have timings.
    std::vector<std::string> passNames;
    for (const FrameRecord& r : records)
        for (const auto& [name, ms] : r.gpu)
            if (std::find(passNames.begin(), passNames.end(), name) == passNames.end()) passNames.push_back(name);
    const std::vector<std::string> order = {"setup", "shadow", "gbuffer", "reduce", "lighting", "forward",
                                           "tonemap", "fxaa", "debug"};
    std::stable_sort(passNames.begin(), passNames.end(), [&](const std::string& a, const std::string& b) {
        auto ia = std::find(order.begin(), order.end(), a) - order.begin();
        auto ib = std::find(order.begin(), order.end(), b) - order.begin();
        return ia < ib;
    });
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
    if (options.outDir.empty()) return result;

    // frames.csv
    std::ostringstream csv;
    csv << "frame,time_s,cpu_ms,gpu_total_ms";
    for (const std::string& n : passNames) csv << ",gpu_" << n << "_ms";
    csv << ",draw_calls,triangles,visible_items,culled_items,deferred_layers,shadow_draws,"
           "shadow_triangles,shadow_casters,camera_x,camera_y,camera_z,camera_yfov_deg,thread_cpu_ms,"
           "lod_switches,frame_ms";
    if (options.stream)
        csv << ",stream_ms,stream_upload_bytes,stream_evicted_bytes,resident_bytes,"
               "needed_bytes,bytes_read,streaming";
    csv << '\n';
    for (size_t k = 0; k < records.size(); ++k) {
        const FrameRecord& r = records[k];
        csv << k << ',' << r.pathTime << ',' << r.stats.cpuMs << ',';
        if (r.gpuTotal >= 0) csv << r.gpuTotal;
        for (const std::string& n : passNames) {
            csv << ',';
            if (r.gpuTotal >= 0) csv << (r.gpu.count(n) ? r.gpu.at(n) : 0.0);
        }
        csv << ',' << r.stats.drawCalls << ',' << r.stats.triangles << ',' << r.stats.visibleItems
            << ',' << r.stats.culledItems << ',' << r.stats.deferredLayersDrawn << ','
            << r.stats.shadowDraws << ',' << r.stats.shadowTriangles << ',' << r.stats.shadowCasters << ','
            << std::setprecision(9) << r.cameraPosition.x << ',' << r.cameraPosition.y << ','
            << r.cameraPosition.z << ',' << r.cameraYfovDegrees << std::setprecision(6) << ','
            << r.stats.threadCpuMs << ',' << r.stats.lodSwitches << ',' << r.frameMs;
        if (options.stream)
            csv << ',' << r.streamMs << ',' << r.stream.frame.uploadedBytes << ',' << r.stream.frame.evictedBytes
                << ',' << r.stream.residentBytes << ',' << r.stream.neededBytes << ','
                << r.stream.bytesRead << ',' << (r.stream.complete ? 0 : 1);
        csv << '\n';
    }
    std::string csvPath = options.outDir + "/frames.csv";
    if (auto w = writeText(csvPath, csv.str()); !w) return w.error();
    result.written.push_back(csvPath);
    if (!quality.empty()) {
        std::string qualityPath = options.outDir + "/quality.csv";
        if (auto w = writeText(qualityPath, qualityCsv.str()); !w) return w.error();
        result.written.push_back(qualityPath);
    }

    // summary.json
    nlohmann::json j;
    j["scene"] = {{"file", options.sceneFile}, {"name", scene.name}, {"triangles", scene.triangles},
                  {"draw_items", scene.items.size()}, {"materials", scene.materials.size()},
                  {"lights", scene.lights.size()}, {"deferred_layers", scene.deferredLayers},
                  {"has_forward", scene.hasForward}};
    utsname u{};
    uname(&u);
    j["machine"] = {{"cpu", cpuModel()}, {"cores", std::thread::hardware_concurrency()},
                    {"kernel", std::string(u.sysname) + " " + u.release}};
    j["gl"] = {{"vendor", gl.vendor}, {"renderer", gl.renderer}, {"version", gl.version}, {"glsl", gl.glsl}};
    j["run"] = {{"command", options.commandLine}, {"path", path ? path->name : ""},
                {"path_duration_s", duration}, {"fixed_dt", options.fixedDt},
                {"dt_s", options.fixedDt ? dt : 0.0}, {"frames", result.frames},
                {"width", options.width}, {"height", options.height},
                {"timer_stalls", renderer.timer().stalls()}};
    j["frame_check"] = {{"frame", result.frames ? result.frames - 1 : 0},
                        {"nonfinite_pixels", result.nonFinitePixels}};
    nlohmann::json settings = nlohmann::json::object();
    for (const auto& [k, v] : settingValues(renderer.settings())) settings[k] = v;
    j["settings"] = settings;
    j["load_ms"] = {{"open", load.openMs}, {"read", load.readMs}, {"decode", load.decodeMs},
                    {"upload", load.uploadMs}, {"compile", load.compileMs}, {"total", load.totalMs},
                    {"file_bytes", load.fileBytes}, {"zero_copy_bytes", load.zeroCopyBytes},
                    {"decompressed_bytes", load.decompressedBytes}};
    if (options.startup) {
        const StartupTimes& t = *options.startup;
        const ProgramCacheStats& p = t.programs;
        j["time_to_first_frame_ms"] = {
            {"total", t.totalMs}, {"process_start", t.processStartMs},
            {"process_start_source", t.processStartSource}, {"context", t.contextMs}, {"load", t.loadMs},
            {"programs", t.programsMs}, {"warmup", t.warmUpMs}, {"first_frame", t.firstFrameMs},
            {"first_frame_thread_cpu", t.firstFrameThreadCpuMs},
            {"other", t.otherMs}, {"warmup_enabled", t.warmUp},
            {"program_cache", {{"enabled", p.enabled}, {"binaries_offered", p.binariesOffered},
                               {"directory", p.directory}, {"hits", p.hits}, {"misses", p.misses},
                               {"rejected", p.rejected}, {"uncached", p.uncached}, {"written", p.written},
                               {"write_failures", p.writeFailures}}}};
    }
    TargetMemory tm = renderer.targetMemory();
    j["gpu_memory_bytes"] = {{"meshes", scene.memory.meshBytes}, {"textures", scene.memory.textureBytes},
                             {"material_uniforms", scene.memory.uniformBytes},
                             {"gbuffer", tm.gbufferBytes}, {"depth", tm.depthBytes}, {"hdr", tm.hdrBytes},
                             {"output", tm.outputBytes}, {"debug", tm.debugBytes},
                             {"per_frame_stream", tm.streamingBytes}, {"shadow_maps", tm.shadowMapBytes},
                             {"shadow_buffers", tm.shadowBufferBytes},
                             {"gi", tm.giBytes}, {"sky_height_map", tm.iblBytes}};
    nlohmann::json gpu = nlohmann::json::object();
    for (const PassSummary& s : result.gpu) gpu[s.pass] = toJson(s);
    j["gpu_ms"] = gpu;
    j["cpu_ms"] = toJson(result.cpu);
    const FrameRecord& last = records.back();
    j["last_frame"] = {{"draw_calls", last.stats.drawCalls}, {"triangles", last.stats.triangles},
                       {"visible_items", last.stats.visibleItems}, {"culled_items", last.stats.culledItems},
                       {"deferred_layers_drawn", last.stats.deferredLayersDrawn},
                       {"shadow_draws", last.stats.shadowDraws}, {"shadow_triangles", last.stats.shadowTriangles},
                       {"shadow_casters", last.stats.shadowCasters}};
    std::vector<double> shadowDraws, triangles, shadowTriangles;
    uint64_t trianglesSum = 0, shadowTrianglesSum = 0, lodSwitches = 0;
    for (const FrameRecord& r : records) {
        shadowDraws.push_back(r.stats.shadowDraws);
        triangles.push_back(double(r.stats.triangles));
        shadowTriangles.push_back(double(r.stats.shadowTriangles));
        trianglesSum += r.stats.triangles;
        shadowTrianglesSum += r.stats.shadowTriangles;
        lodSwitches += r.stats.lodSwitches;
    }
    j["shadow_draws"] = toJson(summarize("shadow_draws", shadowDraws));
    // Triangles drawn per frame (main view and shadow maps), at the levels of detail drawn; the
    // sums compare runs along the same fixed-step path (lod.force=0 against by-error selection).
    auto counts = [](const std::vector<double>& v, uint64_t sum) {
        PassSummary p = summarize("", v);
        return nlohmann::json{{"min", p.min}, {"median", p.median}, {"p95", p.p95}, {"max", p.max}, {"sum", sum}};
    };
    j["triangles"] = counts(triangles, trianglesSum);
    j["shadow_triangles"] = counts(shadowTriangles, shadowTrianglesSum);
    j["lod"] = {{"items_with_levels", scene.lodItems.size()}, {"switches", lodSwitches}};
    if (!quality.empty()) j["quality"] = quality;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    j["peak_rss_bytes"] = uint64_t(usage.ru_maxrss) * 1024;
    if (options.stream) {
        j["streaming"] = streamingSummary(records, *options.stream, fullQualityMs, options.startup);
        // Everything GL holds at the budget's peak: the peak of budgeted storage (textures, LOD
        // meshes), the other meshes and the material blocks (resident whole), the frame's
        // targets and buffers.
        const StreamStatus& st = options.stream->status();
        uint64_t gpuBytes = st.peakBytes + (scene.memory.meshBytes - std::min(scene.memory.meshBytes, st.residentMeshBytes)) + scene.memory.uniformBytes;
        for (const auto& [name, bytes] : j["gpu_memory_bytes"].items())
            if (name != "meshes" && name != "textures" && name != "material_uniforms") gpuBytes += bytes.get<uint64_t>();
        j["streaming"]["peak_gpu_bytes"] = gpuBytes;
    }
    std::string jsonPath = options.outDir + "/summary.json";
    if (auto w = writeText(jsonPath, j.dump(2) + "\n"); !w) return w.error();
    result.written.push_back(jsonPath);

    if (options.plot) {
        std::string png = options.outDir + "/frame_times.png";
        std::string title = scene.name + " " + std::to_string(options.width) + "x" +
                            std::to_string(options.height);
        std::replace(title.begin(), title.end(), '\'', ' ');
        std::string args = "'" + csvPath + "' '" + png + "' --title '" + title + "' 2>&1";
        if (runPlotScript(options.outDir, args)) result.written.push_back(png);
        else std::fprintf(stderr, "pnb-play: warning: plot not written (needs python3-matplotlib)\n");
    }
    return result;
}

} // namespace pnb::player
