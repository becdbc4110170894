// pnb_assets/window_scene.h — the "window" scene (issue 43, light through glass) and the analytic
// values its lit floor must show, shared by the scene's own tests and the player's and the truth's.
//
// Layout (metres, glTF axes: +Y up; the room's interior is x in [-6, 6], y in [0, 3], z in
// [-4, 6]). Every wall, the floor and the roof are closed 0.2 m thick boxes outside that interior,
// so the room is sealed against the sun but for one hole in the roof:
//
//   bay A (x < 0)  the sun (light 0, "sun", white, 3 lux, travelling along (-0.36, -0.8, 0.48):
//                  53.13 degrees up) shines through a square hole in the roof (slab y 3.0..3.2)
//                  closed by the pane "sun-pane" (BLEND, colour (0.9, 0.3, 0.1), alpha 0.5, one
//                  double-sided quad at y = 3.1). The hole is the floor patch x in [-4, -2],
//                  z in [-1, 1] seen from the sun through the slab, so exactly that patch is lit,
//                  only through the pane (rays that leave it cross the hole's opaque sides), and
//                  the rest of the room is in the roof's shadow.
//   bay B (x > 0)  a spot (light 1, "spot-lamp", white, 20 cd, range 20 m, cone 40/50 degrees) at
//                  (3, 2.5, 0) points straight down through two horizontal panes: "green-pane"
//                  (colour (0.2, 0.8, 0.3), alpha 0.4) at y = 1.25, shadowing the floor x in
//                  [1.4, 3.4], z in [-1.2, 1.2], and "blue-pane" (colour (0.3, 0.3, 0.9), alpha
//                  0.6) at y = 1.0, shadowing x in [2.6, 4.6], z in [-1.2, 1.2]. So the floor
//                  under the spot is behind no pane, the green one (x 1.4..2.6), both (x
//                  2.6..3.4) or the blue one (x 3.4..4.6).
//   partition      an opaque wall x in [-0.1, 0.1] from the back wall to z = -1.5 between the
//                  bays, lit by neither light.
//
// One camera ("window-camera", 2.8 m up by the front wall, x = 0) sees both lit floors; the
// fly-through is assets_src/paths/window.json (the converter's default orbit would circle the
// closed room from outside).
//
// Transmittance (issue 43's contract): a pane passes T = colour * (1 - alpha) per channel; panes
// along one light path multiply. The floor is Lambertian with normal +Y; both lights are white, so
// a probe's irradiance is the light's unshadowed irradiance times its colour visibility:
//   sun:  E = 3 * cos(theta)                   (cos(theta) = 0.8 on the floor)
//   spot: E = 20 * cos(theta) / d^2 * window(d) * cone
//         window(d) = clamp(1 - (d^2 / range^2)^2, 0, 1)^2 (glTF's range falloff, as the player
//         and the truth apply it); cone = 1 at every probe (each lies inside the 40 degree inner
//         cone).
#pragma once

#include <array>
#include <string_view>
#include <vector>

#include "pnb_assets/gltf_writer.h"

namespace pnb::assets {

using Rgb = std::array<double, 3>;

// One glass pane of the window scene: a horizontal quad (normal +Y, double-sided, BLEND).
struct WindowPane {
    std::string_view name; // its node and material name
    Rgb color;             // base colour factor (linear RGB)
    double alpha;          // base colour factor's alpha
    double height;         // y of the quad
    double x0, x1, z0, z1; // its extent
};

// T = colour * (1 - alpha), per channel.
Rgb paneTransmittance(const WindowPane& pane);

// The scene's parameters, from which both the generator and the expectations are computed.
struct WindowSceneLayout {
    // Interior (the walls' inner faces) and the thickness of every wall, floor and roof slab.
    double x0 = -6, x1 = 6, height = 3, z0 = -4, z1 = 6, wall = 0.2;
    double partitionZ = -1.5; // the partition runs from the back wall (z0) to here, at x = 0

    std::array<double, 3> sunTravel{-0.36, -0.8, 0.48}; // unit; cos(theta) on the floor = 0.8
    double sunIntensity = 3;                            // lux (white)
    double patchX0 = -4, patchX1 = -2, patchZ0 = -1, patchZ1 = 1; // floor lit through the roof
    double roofPaneHeight = 3.1;                        // mid-slab

    Rgb sunPaneColor{0.9, 0.3, 0.1};
    double sunPaneAlpha = 0.5;

    std::array<double, 3> spotPosition{3, 2.5, 0}; // pointing straight down (-Y)
    double spotIntensity = 20;                     // candela (white)
    double spotRange = 20;                         // metres
    double spotInnerDegrees = 40, spotOuterDegrees = 50;
    // The panes under the spot, given by the floor they shadow (the quads are those regions
    // scaled towards the spot to their heights).
    Rgb greenColor{0.2, 0.8, 0.3}, blueColor{0.3, 0.3, 0.9};
    double greenAlpha = 0.4, blueAlpha = 0.6;
    double greenHeight = 1.25, blueHeight = 1.0;
    double greenFloorX0 = 1.4, greenFloorX1 = 3.4, blueFloorX0 = 2.6, blueFloorX1 = 4.6;
    double paneFloorZ0 = -1.2, paneFloorZ1 = 1.2;

    std::array<double, 3> cameraPosition{0, 2.8, 5.8}, cameraTarget{0, 0, -0.5};
    double cameraYFovDegrees = 75;
};
const WindowSceneLayout& windowSceneLayout();

// The three panes: "sun-pane" (in the roof), "green-pane" and "blue-pane" (under the spot), in
// that order; extents derived from windowSceneLayout().
std::vector<WindowPane> windowScenePanes();

// A named floor point (y = 0, normal +Y) and what one light gives it.
struct WindowProbe {
    std::string_view name;
    std::string_view lightNode; // "sun" or "spot-lamp"
    uint32_t lightIndex;        // in the .glb's KHR_lights_punctual list and the container's LGHT
    std::array<double, 3> position;
    std::vector<std::string_view> panes; // crossed on the way to the light
    double opaqueVisibility;             // 0 (an opaque surface is in the way) or 1
    Rgb transmittance;                   // product over `panes` (1, 1, 1 for none)
    Rgb colorVisibility;                 // opaqueVisibility * transmittance
    double unshadowedIrradiance;         // lux, without anything in the way
    Rgb irradiance;                      // unshadowedIrradiance * colorVisibility
};

// The probes, in this order:
//   sun-pane        (-3, 0, 0)    centre of the patch lit through the roof pane
//   sun-roof-shadow (-3, 0, 2.5)  bay A floor in the roof's shadow (visibility 0)
//   spot-clear      (3, 0, 1.6)   under the spot, behind no pane
//   spot-green      (2, 0, 0)     behind the green pane only
//   spot-both       (3, 0, 0)     behind both panes (straight below the spot)
//   spot-blue       (4, 0, 0)     behind the blue pane only
// Each lies at least 0.4 m from the edges of its region (pane shadows, the sun patch).
std::vector<WindowProbe> windowSceneProbes();

// window: the scene above. No randomness.
gltf::Document buildWindowScene();

} // namespace pnb::assets
