// summary.json (bench_report.h): the run's statistics, the machine, the settings, the load and
// startup times, GPU memory, per-frame counts and, with streaming, what streaming cost.
#include <sys/resource.h>
#include <sys/utsname.h>

#include <algorithm>
#include <fstream>
#include <thread>

#include "bench_report.h"

namespace pnb::player {

namespace {

nlohmann::json toJson(const PassSummary& s) {
    return {{"min_ms", s.min}, {"median_ms", s.median}, {"p95_ms", s.p95}, {"max_ms", s.max}};
}

std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown";
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

// "scene", "machine", "gl", "run", "frame_check", "settings", "load_ms".
void describeRun(const SummaryInputs& in, const BenchResult& result, nlohmann::json& j) {
    const GpuScene& scene = in.scene;
    const BenchOptions& options = in.options;
    j["scene"] = {{"file", options.sceneFile}, {"name", scene.name}, {"triangles", scene.triangles},
                  {"draw_items", scene.items.size()}, {"materials", scene.materials.size()},
                  {"lights", scene.lights.size()}, {"deferred_layers", scene.deferredLayers},
                  {"has_forward", scene.hasForward}};
    utsname u{};
    uname(&u);
    j["machine"] = {{"cpu", cpuModel()}, {"cores", std::thread::hardware_concurrency()},
                    {"kernel", std::string(u.sysname) + " " + u.release}};
    j["gl"] = {{"vendor", in.gl.vendor}, {"renderer", in.gl.renderer}, {"version", in.gl.version}, {"glsl", in.gl.glsl}};
    j["run"] = {{"command", options.commandLine}, {"path", in.plan.path ? in.plan.path->name : ""},
                {"path_duration_s", in.plan.duration}, {"fixed_dt", options.fixedDt},
                {"dt_s", options.fixedDt ? in.plan.dt : 0.0}, {"frames", result.frames},
                {"width", options.width}, {"height", options.height},
                {"timer_stalls", in.renderer.timer().stalls()}};
    j["frame_check"] = {{"frame", result.frames ? result.frames - 1 : 0},
                        {"nonfinite_pixels", result.nonFinitePixels}};
    nlohmann::json settings = nlohmann::json::object();
    for (const auto& [k, v] : settingValues(in.renderer.settings())) settings[k] = v;
    j["settings"] = settings;
    const LoadStats& load = in.load;
    j["load_ms"] = {{"open", load.openMs}, {"read", load.readMs}, {"decode", load.decodeMs},
                    {"upload", load.uploadMs}, {"compile", load.compileMs}, {"total", load.totalMs},
                    {"file_bytes", load.fileBytes}, {"zero_copy_bytes", load.zeroCopyBytes},
                    {"decompressed_bytes", load.decompressedBytes}};
}

// "time_to_first_frame_ms": pnb-play's startup split and its program cache (when given).
nlohmann::json startupJson(const StartupTimes& t) {
    const ProgramCacheStats& p = t.programs;
    return {{"total", t.totalMs}, {"process_start", t.processStartMs},
            {"process_start_source", t.processStartSource}, {"context", t.contextMs}, {"load", t.loadMs},
            {"programs", t.programsMs}, {"warmup", t.warmUpMs}, {"first_frame", t.firstFrameMs},
            {"first_frame_thread_cpu", t.firstFrameThreadCpuMs},
            {"other", t.otherMs}, {"warmup_enabled", t.warmUp},
            {"program_cache", {{"enabled", p.enabled}, {"binaries_offered", p.binariesOffered},
                               {"directory", p.directory}, {"hits", p.hits}, {"misses", p.misses},
                               {"rejected", p.rejected}, {"uncached", p.uncached}, {"written", p.written},
                               {"write_failures", p.writeFailures}}}};
}

// "last_frame", "shadow_draws", "triangles", "shadow_triangles", "lod": what the frames drew.
void describeFrames(const SummaryInputs& in, nlohmann::json& j) {
    const std::vector<FrameRecord>& records = in.run.records;
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
    j["lod"] = {{"items_with_levels", in.scene.lodItems.size()}, {"switches", lodSwitches}};
}

// Everything GL holds at the streaming budget's peak: the peak of budgeted storage (textures, LOD
// meshes), the other meshes and the material blocks (resident whole), the frame's targets and
// buffers.
uint64_t peakGpuBytes(const GpuScene& scene, const StreamStatus& st, const nlohmann::json& gpuMemory) {
    uint64_t gpuBytes = st.peakBytes + (scene.memory.meshBytes - std::min(scene.memory.meshBytes, st.residentMeshBytes)) +
                        scene.memory.uniformBytes;
    for (const auto& [name, bytes] : gpuMemory.items())
        if (name != "meshes" && name != "textures" && name != "material_uniforms") gpuBytes += bytes.get<uint64_t>();
    return gpuBytes;
}

} // namespace

nlohmann::json summaryJson(const SummaryInputs& in, const BenchResult& result) {
    const GpuScene& scene = in.scene;
    nlohmann::json j;
    describeRun(in, result, j);
    if (in.options.startup) j["time_to_first_frame_ms"] = startupJson(*in.options.startup);
    TargetMemory tm = in.renderer.targetMemory();
    j["gpu_memory_bytes"] = {{"meshes", scene.memory.meshBytes}, {"textures", scene.memory.textureBytes},
                             {"material_uniforms", scene.memory.uniformBytes},
                             {"gbuffer", tm.gbufferBytes}, {"depth", tm.depthBytes}, {"hdr", tm.hdrBytes},
                             {"output", tm.outputBytes}, {"debug", tm.debugBytes},
                             {"per_frame_stream", tm.streamingBytes}, {"shadow_maps", tm.shadowMapBytes},
                             {"shadow_buffers", tm.shadowBufferBytes},
                             {"shadow_translucent", tm.shadowTranslucentBytes},
                             {"gi", tm.giBytes}, {"sky_height_map", tm.iblBytes}};
    nlohmann::json gpu = nlohmann::json::object();
    for (const PassSummary& s : result.gpu) gpu[s.pass] = toJson(s);
    j["gpu_ms"] = gpu;
    j["cpu_ms"] = toJson(result.cpu);
    describeFrames(in, j);
    if (!in.quality.summary.empty()) j["quality"] = in.quality.summary;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    j["peak_rss_bytes"] = uint64_t(usage.ru_maxrss) * 1024;
    if (in.options.stream) {
        j["streaming"] = streamingSummary(in.run.records, *in.options.stream, in.run.fullQualityMs, in.options.startup);
        j["streaming"]["peak_gpu_bytes"] = peakGpuBytes(scene, in.options.stream->status(), j["gpu_memory_bytes"]);
    }
    return j;
}

} // namespace pnb::player
