#version 450 core
// shadow_debug.frag — debug.view=shadowmap: one layer of the cascade array, depth as grey
// (near the light dark); debug.view=histogram: the view-depth histogram SDSM reduced this frame
// (logarithmic bins over the shadowed range, bar height relative to the fullest bin) with each
// cascade's range underneath in seed 000's colours and its end marked by a white line.
#include "shared/bindings.h"
#include "shared/sdsm_state.h"

layout(binding = 0) uniform sampler2DArray uShadowDepth;
// SDSM's state this frame (shared/sdsm_state.h): the histogram and the cascades' ranges.
layout(std430, binding = PNB_BINDING_SDSM_STATE) readonly buffer SdsmState {
    PNB_SDSM_STATE_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
layout(location = 0) uniform int uMode;         // 0 map layer, 1 histogram
layout(location = 1) uniform int uLayer;
layout(location = 2) uniform vec2 uDepthRange;  // shadowed view depths [near, far]
layout(location = 3) uniform int uCascades;
layout(location = 4) uniform float uSplits[9];  // CPU fits' split depths (SDSM: from the buffer)
layout(location = 13) uniform int uHasHistogram;

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

const vec3 kCascade[8] = vec3[8](vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 1, 1),
                                 vec3(1, 0, 1), vec3(1, 0.5, 0), vec3(0.5, 0, 1), vec3(0.5, 0.5, 0.5));

float depthAt(float x) { return uDepthRange.x * pow(uDepthRange.y / uDepthRange.x, x); }

void main() {
    if (uMode == 0) {
        float d = texture(uShadowDepth, vec3(vUv, float(uLayer))).r;
        outColor = vec4(vec3(d), 1.0);
        return;
    }
    float depth = depthAt(vUv.x);
    vec3 c = vec3(0.05);
    int cascade = -1;
    for (int i = 0; i < uCascades; ++i) {
        vec2 range = uHasHistogram != 0 ? cascadeRange[i].xy : vec2(uSplits[i], uSplits[i + 1]);
        if (depth >= range.x && depth <= range.y && cascade < 0) cascade = i;
        float px = log(range.y / uDepthRange.x) / log(uDepthRange.y / uDepthRange.x);
        if (abs(vUv.x - px) * 512.0 < 0.75) c = vec3(1.0);
    }
    if (vUv.y < 0.08) {
        outColor = vec4(cascade >= 0 ? kCascade[cascade] : vec3(1, 1, 0), 1.0);
        return;
    }
    if (uHasHistogram != 0) {
        uint fullest = 1u;
        for (int b = 0; b < PNB_SDSM_BINS; ++b) fullest = max(fullest, histogram[b]);
        int bin = clamp(int(vUv.x * float(PNB_SDSM_BINS)), 0, PNB_SDSM_BINS - 1);
        float h = float(histogram[bin]) / float(fullest);
        if ((vUv.y - 0.1) / 0.9 < h) c = cascade >= 0 ? kCascade[cascade] * 0.8 + 0.2 : vec3(0.6);
    }
    outColor = vec4(c, 1.0);
}
