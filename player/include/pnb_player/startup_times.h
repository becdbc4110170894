// pnb_player/startup_times.h — time to first frame, split into where it goes.
//
// The parts add up to the total (exec of the process to the first frame finished on the GPU):
//   process start  exec to main(): the dynamic linker, static constructors. Taken from
//                  $PNB_LAUNCH_TIME_NS when a launcher sets it (CLOCK_MONOTONIC nanoseconds read
//                  just before it spawned the process: exact), else from /proc/self/stat's
//                  starttime (kernel clock ticks since boot: 1/CLK_TCK = 10 ms resolution)
//   context        creating the GL context (EGL or window), driver start-up included
//   load           open, read, decode, upload to GPU-ready (LoadStats::totalMs less programs)
//   programs       every program made before the first frame: loaded from the program binary
//                  cache (hits) or compiled and linked (misses), scene and built-in alike
//   warm-up        Renderer::warmUp less the programs it linked: the driver's code generation
//                  for the states the scene is drawn in (0 with startup.warmup off: it then lands
//                  in the first frame)
//   first frame    rendering the first frame, through glFinish
//   other          the rest (argument parsing, settings, renderer set-up)
#pragma once

#include <string>

#include "pnb_player/program_cache.h"

namespace pnb::player {

struct StartupTimes {
    double processStartMs = 0;
    std::string processStartSource; // "PNB_LAUNCH_TIME_NS" or "/proc/self/stat"
    double contextMs = 0, loadMs = 0, programsMs = 0, warmUpMs = 0, firstFrameMs = 0, otherMs = 0;
    double totalMs = 0;
    // The first frame's render-thread CPU time (FrameStats::threadCpuMs): about a steady frame's
    // when the warm-up did its job, tens to thousands of ms of code generation when it did not.
    double firstFrameThreadCpuMs = 0;
    bool warmUp = false;            // startup.warmup was on
    ProgramCacheStats programs;     // hits, misses, ... of the programs made before the first frame
};

// Milliseconds since this process was exec'ed, and where that came from (see above); call it
// first thing in main(). -1 if neither source is available.
double processAgeMs(std::string* source);

// "time to first frame: 183.2 ms = process start 12.0 + context 15.3 + ..."
std::string startupSummary(const StartupTimes& t);

} // namespace pnb::player
