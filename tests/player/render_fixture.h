// render_fixture.h — headless rendering for the player tests: one EGL context per test binary,
// small glTF scenes built in code and converted with the real converter (with a sidecar to place
// materials), rendered at test resolution and read back.
#pragma once

#include <chrono>

#include <string>

#include <gtest/gtest.h>

#include "gltf_fixture.h"
#include "pnb_player/renderer.h"

namespace pnb::player::test {

// A wall-time bound for loops that wait on a streaming loader thread: on a loaded machine the
// thread can be starved for seconds, so a frame count is no bound on what it has read.
struct StreamTimeLimit {
    std::chrono::steady_clock::time_point end = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    bool left() const { return std::chrono::steady_clock::now() < end; }
};


namespace gltf = pnb::assets::gltf;

// Creates the headless context before any test and keeps it for the whole binary.
class HeadlessEnvironment : public ::testing::Environment {
public:
    void SetUp() override;
    void TearDown() override;
};

using pnb::test::addSun;
using pnb::test::addObject;
using pnb::test::box;
using pnb::test::quad;

// A UV sphere centred on the origin with exact normals, counter-clockwise from outside.
gltf::Primitive uvSphere(float radius, uint32_t rings, uint32_t segments, uint32_t material);

// A sun from the upper left and a warm point light.
void addLights(gltf::Document& doc, gltf::Float3 offset = {0, 0, 0});

// Writes doc as .glb (+ sidecar JSON if non-empty) in a per-test temporary directory, converts
// it, and returns the .pnb path. Fails the test on a conversion error.
std::string convert(const gltf::Document& doc, const std::string& name,
                    const std::string& sidecarJson = "");

struct Rendered {
    CapturedImage color, hdr, depth, position; // position: camera-relative, NaN = no geometry
    FrameStats stats;
    TargetMemory memory;
    size_t deferredLayers = 0;
    bool lightingProgramCompiled = false;
};

Rendered render(const std::string& pnbPath, const CameraState& camera, uint32_t width = 160,
                uint32_t height = 120, const RenderSettings& settings = {});

// A camera at `position` looking at `target`.
CameraState lookAt(glm::dvec3 position, glm::dvec3 target, float znear = 0.1f, float zfar = 0.0f);

struct ImageDiff {
    double meanAbs = 0;  // over all channels, in 0..255 units
    int maxAbs = 0;      // largest channel difference
    double fractionOver(int threshold) const;
    std::vector<int> perPixelMax;
};
ImageDiff compareRgba8(const CapturedImage& a, const CapturedImage& b);

// Every float finite.
bool allFinite(const CapturedImage& image);

} // namespace pnb::player::test
