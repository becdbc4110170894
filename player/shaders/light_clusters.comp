#version 450 core
// light_clusters.comp — which lights may reach each cluster of this frame (shaders/include/
// lights.glsl reads the result). A cluster is a screen tile x an exponential depth slice; its
// lights are its tile's mask AND its slice's mask, so this pass tests every light against every
// tile's side planes and every slice's depth interval ((tiles + slices) x lights tests, not
// tiles x slices x lights). One invocation writes one 32-bit word of one mask: no atomics, and
// the result is the same whatever the invocation order.
//
// Each light comes as a bounding sphere in view space (the player computes it: a point light's
// range, a spot light's sector, radius < 0 for directional lights, which reach everything).
// The tests are conservative (a sphere near a tile's corner can pass all four planes): a light
// kept where it does not reach is shaded there and its range window makes it add nothing.
#include "shared/bindings.h"
#include "shared/light_cluster_masks.h"

layout(local_size_x = 64) in;

layout(std430, binding = PNB_BINDING_CLUSTER_SPHERES) readonly buffer LightSpheres {
    vec4 uSpheres[]; // view xyz, radius
};

// What lighting reads (shared/light_cluster_masks.h), by the names it reads them with: the
// header (uClusterGrid, uClusterDepth: this frame's uGrid and uDepth), then the masks.
layout(std430, binding = PNB_BINDING_CLUSTER_MASKS_OUT) writeonly buffer LightClusters {
    PNB_LIGHT_CLUSTERS_HEADER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
    uint uClusterMasks[]; // tile masks, then slice masks
};

layout(location = 0) uniform uvec4 uGrid;
layout(location = 1) uniform vec4 uDepth;
layout(location = 2) uniform uint uLightCount;
layout(location = 3) uniform mat4 uProjection; // view -> clip
layout(location = 4) uniform vec2 uViewport;   // width, height (px)

// A sphere reaches the half-space dot(plane, (x, 1)) >= 0 unless it lies wholly outside.
bool reaches(vec4 plane, vec4 sphere) {
    return dot(plane.xyz, sphere.xyz) + plane.w >= -sphere.w * length(plane.xyz);
}

vec4 projectionRow(int i) {
    return vec4(uProjection[0][i], uProjection[1][i], uProjection[2][i], uProjection[3][i]);
}

// The view-space depth (distance along -z) where slice k begins: slice = log(z) * scale + bias.
float sliceStart(uint k) { return exp((float(k) - uDepth.z) / uDepth.y); }

void main() {
    uint tiles = uGrid.x * uGrid.y, words = uGrid.w;
    uint index = gl_GlobalInvocationID.x;
    if (index == 0u) {
        uClusterGrid = uGrid;
        uClusterDepth = uDepth;
    }
    if (index >= (tiles + uGrid.z) * words) return;
    uint row = index / words, word = index % words;

    // The tile's four side planes (clip x >= x0 w, x <= x1 w, same in y), or the slice's depths.
    vec4 planes[4];
    float near = 0.0, far = 0.0;
    bool isTile = row < tiles;
    if (isTile) {
        uvec2 tile = uvec2(row % uGrid.x, row / uGrid.x);
        vec2 tileNdc = 2.0 / (uDepth.x * uViewport);
        vec2 lo = vec2(tile) * tileNdc - 1.0;
        vec2 hi = min(lo + tileNdc, vec2(1.0));
        vec4 rx = projectionRow(0), ry = projectionRow(1), rw = projectionRow(3);
        planes[0] = rx - lo.x * rw;
        planes[1] = hi.x * rw - rx;
        planes[2] = ry - lo.y * rw;
        planes[3] = hi.y * rw - ry;
    } else {
        uint slice = row - tiles;
        near = slice == 0u ? 0.0 : sliceStart(slice); // nearer than the first slice: the first
        far = slice + 1u == uGrid.z ? 3.4e38 : sliceStart(slice + 1u); // farther: the last
    }

    uint bits = 0u;
    uint first = word * 32u;
    uint count = min(32u, uLightCount - min(first, uLightCount));
    for (uint b = 0u; b < count; ++b) {
        vec4 sphere = uSpheres[first + b];
        bool in_;
        if (sphere.w < 0.0) {
            in_ = true; // directional
        } else if (isTile) {
            in_ = reaches(planes[0], sphere) && reaches(planes[1], sphere) &&
                  reaches(planes[2], sphere) && reaches(planes[3], sphere);
        } else {
            float depth = -sphere.z;
            in_ = depth + sphere.w >= near && depth - sphere.w <= far;
        }
        if (in_) bits |= 1u << b;
    }
    uClusterMasks[index] = bits;
}
