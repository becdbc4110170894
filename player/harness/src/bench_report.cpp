// The benchmark's reports as text (bench_report.h): frames.csv, quality.csv, summary.json.
#include "bench_report.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "pnb/atomic_file.h"

namespace pnb::player {

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

std::vector<std::string> orderedPassNames(const std::vector<FrameRecord>& records) {
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
    return passNames;
}

PlayResult<Done> writeTextFile(const std::string& path, const std::string& text) {
    Status s = writeFileAtomic(path, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    if (!isOk(s)) return PlayError{PlayErrorKind::Io, s.describe()};
    return Done{};
}

std::string tracerFrameJson(const GpuScene& scene, const Renderer& renderer, const BenchOptions& options) {
    glm::dvec3 eye = renderer.lastView().position;
    glm::vec3 toward = towardShadowingSun(scene);
    nlohmann::json fj = {{"camera_position", {eye.x, eye.y, eye.z}},
                         {"toward_light", {toward.x, toward.y, toward.z}},
                         {"width", options.width}, {"height", options.height},
                         // The environment as lit (pnb-reference --sky reads them).
                         {"ibl_rotation_degrees", renderer.settings().iblRotationDeg},
                         {"ibl_intensity", renderer.settings().iblIntensity}};
    // The camera as pnb-reference --whole-frame traces it (FrameCamera): the view's axes in world
    // (columns +X, +Y, +Z of the inverse of the rotation-only view matrix; it looks down -Z),
    // the projection, and the exposure the displayed image was tone mapped with.
    const ViewMatrices& view = renderer.lastView();
    const glm::mat3 worldFromView = glm::transpose(glm::mat3(view.view));
    nlohmann::json axes = nlohmann::json::array();
    for (int c = 0; c < 3; ++c) axes.push_back({worldFromView[c].x, worldFromView[c].y, worldFromView[c].z});
    fj["camera_world_from_view"] = axes;
    fj["projection"] = view.orthographic ? "orthographic" : "perspective";
    fj["yfov"] = view.yfov;
    fj["aspect"] = view.aspect;
    fj["ymag"] = view.ymag;
    fj["xmag"] = view.ymag * view.aspect;
    fj["exposure"] = renderer.settings().exposure;
    // A point or spot light judged (shadows.judged_light): pnb-reference traces that light,
    // placed as the container places it.
    if (renderer.settings().shadowJudgedLight >= 0) fj["shadow_light_index"] = renderer.settings().shadowJudgedLight;
    // The instant drawn: the truth poses the scene there (pnb-reference reads it).
    const DrawnPose anim = renderer.drawnPose();
    fj["anim"] = {{"enabled", anim.enabled},
                  {"clip", anim.clip ? nlohmann::json(*anim.clip) : nlohmann::json(nullptr)},
                  {"clip_name", anim.clipName},
                  {"time", anim.clipTime}};
    return fj.dump(2) + "\n";
}

QualityTable qualityTable(const std::vector<std::string>& columns,
                          const std::vector<std::pair<uint32_t, std::map<std::string, double>>>& rows) {
    QualityTable table;
    std::ostringstream csv;
    csv << "frame";
    for (const std::string& c : columns) csv << ',' << c;
    csv << '\n';
    for (const auto& [k, row] : rows) {
        csv << k;
        for (const std::string& c : columns) {
            csv << ',';
            if (row.count(c)) csv << row.at(c);
        }
        csv << '\n';
    }
    table.csv = csv.str();
    for (const std::string& c : columns) {
        std::vector<double> v;
        for (const auto& [k, row] : rows)
            if (row.count(c)) v.push_back(row.at(c));
        PassSummary ps = summarize(c, v);
        double mean = 0;
        for (double x : v) mean += x / double(v.size());
        table.summary[c] = {{"mean", mean}, {"median", ps.median}, {"p95", ps.p95}, {"max", ps.max},
                            {"frames", v.size()}};
    }
    return table;
}

std::string framesCsv(const std::vector<FrameRecord>& records, const std::vector<std::string>& passNames,
                      bool streaming, bool animated) {
    std::ostringstream csv;
    csv << "frame,time_s,cpu_ms,gpu_total_ms";
    for (const std::string& n : passNames) csv << ",gpu_" << n << "_ms";
    csv << ",draw_calls,triangles,visible_items,culled_items,deferred_layers,shadow_draws,"
           "shadow_triangles,shadow_casters,camera_x,camera_y,camera_z,camera_yfov_deg,thread_cpu_ms,"
           "lod_switches,frame_ms";
    if (streaming)
        csv << ",stream_ms,stream_upload_bytes,stream_evicted_bytes,resident_bytes,"
               "needed_bytes,bytes_read,streaming";
    // Playback (an animated scene only): the pose's clip time, the deform pass's dispatches and
    // the draw items the pose moved (their GPU time is gpu_deform_ms).
    if (animated) csv << ",anim_time_s,deform_dispatches,deform_vertices,moved_items";
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
        if (streaming)
            csv << ',' << r.streamMs << ',' << r.stream.frame.uploadedBytes << ',' << r.stream.frame.evictedBytes
                << ',' << r.stream.residentBytes << ',' << r.stream.neededBytes << ','
                << r.stream.bytesRead << ',' << (r.stream.complete ? 0 : 1);
        if (animated)
            csv << ',' << r.stats.animationTime << ',' << r.stats.deformDispatches << ',' << r.stats.deformVertices
                << ',' << r.stats.movedItems;
        csv << '\n';
    }
    return csv.str();
}

} // namespace pnb::player
