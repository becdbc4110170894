// pnb-reference's files: the dumped frame it reads (frame.json and the EXR buffers, the input
// contract of docs/REFERENCE.md) and the images and JSON it writes, with the exit code and
// sentence of whatever fails on the way.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <OpenImageIO/typedesc.h>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "pnb/error.h"
#include "pnb_reference/frame_pose.h"

namespace pnb::reference_tool {

constexpr int kExitOk = 0, kExitUsage = 1, kExitInput = 2, kExitUnsupported = 3, kExitOutput = 4,
              kExitEmbree = 5;

// A failure on the way: the exit code and a sentence naming the file.
struct Failure {
    int exitCode = kExitInput;
    std::string message;
};
template <class T> using Expected = pnb::Result<T, Failure>;

// Prints "Error: MESSAGE" and returns the failure's exit code.
int fail(const Failure& f);

struct Frame {
    glm::dvec3 cameraPosition{0.0};
    glm::vec3 towardLight{0.0f}; // the sun's; unused (and optional) with shadowLightIndex
    // The judged light is LGHT light K, a point or spot light (optional key).
    std::optional<uint32_t> shadowLightIndex;
    int width = 0, height = 0;
    // The player's environment settings, when the dump records them (optional keys).
    std::optional<double> iblRotationDegrees, iblIntensity;
    // The camera's orientation and projection (optional keys; pnb-reference --whole-frame needs
    // camera_world_from_view, projection and its yfov/aspect or xmag/ymag).
    std::optional<glm::dmat3> worldFromView; // columns: the view's +X, +Y, +Z in world
    std::optional<std::string> projection;   // "perspective" or "orthographic"
    std::optional<double> yfov, aspect, xmag, ymag, exposure;
    // The animation state the frame was drawn at (optional key "anim", docs/REFERENCE.md "Moving
    // frames"): the clip (none: the rest pose) and the clip time the player sampled, or enabled =
    // false (the container as stored). Absent: as stored, as every frame before issue 42.
    struct Animation {
        bool enabled = true;
        std::optional<uint32_t> clip;
        std::string clipName;
        double time = 0;
    };
    std::optional<Animation> anim;
    // The instant traced: `anim` with the command line's --anim-clip/--anim-time applied, checked
    // against the scene (reference_pose.h resolvePose fills it once the scene is read).
    pnb::reference::FramePose pose;
};

Expected<Frame> readFrameJson(const std::string& path);

// A float image, channels interleaved, rows in file order.
struct FloatImage {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels;
    float at(size_t pixel, int channel) const { return pixels[pixel * size_t(channels) + size_t(channel)]; }
};

// Reads `path` as float, keeping the channels named in `wanted` (by name, e.g. "R"; a file with
// unnamed or differently named channels is read positionally) in that order.
Expected<FloatImage> readExr(const std::string& path, const std::vector<std::string>& wanted, size_t required,
                             const Frame& frame);

// Outputs: encoded in memory, then placed with pnb::writeFileAtomic (readers never see a partial
// file; a failed write leaves the previous one).
Expected<bool> writeImage(const std::string& path, int width, int height, int channels, OIIO::TypeDesc type,
                          const void* pixels);
Expected<bool> writeText(const std::string& path, const std::string& text);

} // namespace pnb::reference_tool
