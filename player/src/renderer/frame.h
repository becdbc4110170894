// frame.h — the frame as one ordered list of passes (frame.cpp), each declaring the resources it
// reads and writes, and the few facts of this frame that decide which of them run.
//
// Why a list and not a graph that schedules itself: the frame has about twenty passes in an order
// the techniques fix (seeds 001-004: the sun's fit before its maps, the maps before lighting, the
// first deferred layer's depth before SDSM's fit, the camera's surfels before GI's propagation),
// one set of targets and no transient memory to alias. Reading the order is the point, so the
// list is written out in that order; the declared reads and writes make each dependency visible
// and let a test (tests/player/frame_passes_test.cpp) check the order for every combination of
// the facts below, without GL.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "pnb_player/play_error.h"

namespace pnb::player {

struct FrameContext;
struct ShadowContext;
struct GiContext;
struct IblContext;
struct LightContext;
struct LocalShadowContext;

// What a pass reads or writes. "Produced" resources are made once per frame and must be complete
// before anything reads them; the targets accumulate (each pass adds to them).
enum FrameResource : uint32_t {
    kLightList = 1u << 0,        // the light list in the ring (produced: prepare, local shadows)
    kShadowFit = 1u << 1,        // the sun's matrices and caster lists (prepare, or SDSM's GPU fit)
    kShadowMaps = 1u << 2,       // the cascades' depth array
    kLocalShadowMaps = 1u << 3,  // point and spot lights' atlas
    kGiRsm = 1u << 4,            // the sun's reflective shadow map
    kGiInjected = 1u << 5,       // light and blockers injected into the LPV cascades
    kGiVolumes = 1u << 6,        // the summed volumes (or probes) lighting reads
    kPreviousDepth = 1u << 7,    // last frame's depth, before this frame clears it
    kDepth = 1u << 8,            // targets (accumulated)
    kGBuffer = 1u << 9,
    kHdr = 1u << 10,
    kOutput = 1u << 11,
    kLightClusters = 1u << 12,   // per tile and slice light masks
};
constexpr uint32_t kAccumulatedResources = kDepth | kGBuffer | kHdr | kOutput;
// Written before the list runs (the prepare step), or by the previous frame.
constexpr uint32_t kFrameInputs = kLightList | kShadowFit | kPreviousDepth;

// The facts that decide which passes run, known once the subsystems have prepared the frame.
struct FrameShape {
    bool shadows = false;        // the sun's maps are drawn (ShadowFrame::active)
    bool sdsm = false;           // ... and fitted on the GPU (shadows.technique = sdsm)
    bool deferred = false;       // some deferred layer has visible items
    bool gi = false;             // GiFrame::active
    bool giProbes = false;       // gi.technique = probes (no injection, no propagation)
    bool giCameraSurfels = false; // gi.camera_occlusion: the camera's G-buffer blocks GI light
};

// Everything a pass may be handed: the frame's shared parts and the subsystems. A pass's run
// function passes on only what it uses, so what it touches shows in the call.
struct Frame {
    FrameContext& ctx;
    ShadowContext& shadows;
    GiContext& gi;
    IblContext& ibl;
    LightContext& lights;
    LocalShadowContext& localShadows;
    const std::vector<size_t>& deferredLayers; // with visible items, ascending priority
};

struct FramePass {
    const char* name;
    uint32_t reads, writes;               // FrameResource bits
    bool (*runs)(const FrameShape&);      // whether it runs in a frame of this shape
    void (*run)(Frame&);
};

// The stage before the passes, in order: each subsystem's prepare step (its CPU plan, then what it
// writes into the ring), the sky's height map when stale, the frame block, and the sun's maps'
// storage. Fails only when the GL cannot allocate that storage.
PlayResult<Done> prepareFrame(Frame& frame);

// The facts of this frame that choose its passes (after prepareFrame).
FrameShape frameShape(const Frame& frame);

// The frame's passes, in order.
std::span<const FramePass> framePasses();

// The names of the passes a frame of `shape` runs, in order (tests, --print-frame).
std::vector<std::string> framePassNames(const FrameShape& shape);

// What is wrong with the order for `shape` ("" when nothing): a pass reading a resource no
// earlier pass wrote (and no frame input), or a produced resource written after a pass read it.
std::string checkFrameOrder(std::span<const FramePass> passes, const FrameShape& shape);

// Runs the passes of `shape` in order.
void runFrame(Frame& frame, const FrameShape& shape);

} // namespace pnb::player
