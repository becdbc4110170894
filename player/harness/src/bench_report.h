// The benchmark's reports (internal to pnb_play_harness): frames.csv, quality.csv, summary.json
// and the per-capture frame JSON a ground-truth tracer reads, as text; writeTextFile writes them.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_records.h"

namespace pnb::player {

// Writes `text` atomically (pnb/atomic_file.h). Errors are Io.
PlayResult<Done> writeTextFile(const std::string& path, const std::string& text);

// "<capture>_frame.json": the eye, the light, the environment as lit and the animation state
// the frame was drawn at ("anim": Renderer::drawnPose) (docs/REFERENCE.md).
std::string tracerFrameJson(const GpuScene& scene, const Renderer& renderer, const BenchOptions& options);

// quality.csv and summary.json's "quality" from the quality pass's rows (frame, metric -> value).
QualityTable qualityTable(const std::vector<std::string>& columns,
                          const std::vector<std::pair<uint32_t, std::map<std::string, double>>>& rows);

// frames.csv: one row per timed frame (columns: pnb_player/benchmark.h).
std::string framesCsv(const std::vector<FrameRecord>& records, const std::vector<std::string>& passNames,
                      bool streaming, bool animated = false);

// Everything summary.json is made of.
struct SummaryInputs {
    const GpuScene& scene;
    Renderer& renderer; // not const: the timer's stall count is read through timer()
    const BenchOptions& options;
    const LoadStats& load;
    const GlInfo& gl;
    const RunPlan& plan;
    const TimedRun& run;
    const QualityTable& quality;
};

// summary.json (fields: pnb_player/benchmark.h), from the run and `result`'s statistics.
nlohmann::json summaryJson(const SummaryInputs& in, const BenchResult& result);

} // namespace pnb::player
