// What a benchmark run records (internal to pnb_play_harness): the plan of the run, one record
// per timed frame, and the statistics the reports are written from. benchmark.cpp fills them;
// bench_report.cpp turns them into frames.csv, quality.csv and summary.json.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "pnb_player/benchmark.h"

namespace pnb::player {

// Which frames a run draws, at which path times (from BenchOptions and the scene's path).
struct RunPlan {
    const ScenePath* path = nullptr; // null: a static camera
    double start = 0;                // path time of frame 0
    double duration = 0;             // the path's duration (0 without one)
    double span = 0;                 // path time the run covers (BenchOptions::seconds or the path's)
    double dt = 0;                   // the fixed step (with BenchOptions::fixedDt)
    uint32_t frames = 0;             // ~0u: until the path's time runs out
};

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

// The timed frames, and the camera as the last one left it (the quality pass starts from it).
struct TimedRun {
    std::vector<FrameRecord> records;
    CameraState camera;
    std::optional<double> fullQualityMs; // from the first timed frame to the stream's completion
};

// The quality pass's metrics: quality.csv's text and summary.json's "quality" (empty: no pass).
struct QualityTable {
    nlohmann::json summary = nlohmann::json::object();
    std::string csv;
};

// min/median/p95/max of `v` (nearest rank).
PassSummary summarize(std::string name, std::vector<double> v);

// The GPU pass names found in `records`, in the frame's order (setup, shadow, gbuffer, ...).
std::vector<std::string> orderedPassNames(const std::vector<FrameRecord>& records);

} // namespace pnb::player
