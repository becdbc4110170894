#version 450 core
// shadow.frag — alpha-tested casters discard below their cutoff; opaque casters need no
// fragment work at all (the ALPHA_MASK-free permutation is an empty shader).
#include "include/interface.glsl"

#ifdef ALPHA_MASK
layout(binding = PNB_TEX_BASE_COLOR) uniform sampler2D uBaseColorMap;
layout(location = 3) in vec2 vUv0;
#endif

void main() {
#ifdef ALPHA_MASK
    if ((uBaseColorFactor.a * texture(uBaseColorMap, vUv0).a) < uAlphaParams.x) discard;
#endif
}
