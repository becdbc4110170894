// pnb_assets/scene_transform.h — the same scene in another unit of length, somewhere else, under
// another sun: the inputs of the ground-truth extremes matrix (docs/REFERENCE.md, "Extremes").
//
// Does: wraps every root node of a Document in one new root node ("unit-root") whose scale is
// the unit scale and whose translation is the origin offset — as a model exported in the wrong
// unit, or placed far from the world origin, arrives — and scales what node transforms do not
// reach, so the scaled scene renders the same image: camera near/far planes, point-light ranges,
// and point-light intensities (candela over a squared distance: multiplied by scale²). Optionally
// turns the node named "sun" to a new elevation (0..90 degrees; 90 = straight down) and azimuth,
// and sets every camera's near plane (before scaling).
//
// Does NOT do: camera paths (sidecar JSON, in the original unit), textures, animation.
#pragma once

#include <optional>
#include <string>

#include "pnb_assets/gltf_writer.h"

namespace pnb::assets {

struct SceneTransform {
    double unitScale = 1.0;             // lengths multiply by this; > 0, finite
    gltf::Float3 origin{0, 0, 0};       // added after scaling (world units)
    std::optional<float> sunElevationDegrees; // 0..90 above the horizon
    std::optional<float> sunAzimuthDegrees;   // about +Y; default: keep the sun's own
    std::optional<float> cameraNear;    // every camera's znear, in the original unit; > 0
};

// Applies `t` to `doc` in place. Returns "" on success, else a sentence naming the bad value or
// what is missing (a sun option on a scene without a node named "sun"); `doc` is then unchanged.
std::string applySceneTransform(gltf::Document& doc, const SceneTransform& t);

} // namespace pnb::assets
