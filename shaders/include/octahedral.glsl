// octahedral.glsl — unit vectors <-> 2D octahedral coordinates in [-1, 1]^2.
// Based on: Cigolle et al., "A Survey of Efficient Representations for Independent Unit
// Vectors" (JCGT 2014). The converter's quantiser uses the same mapping.
#ifndef PNB_OCTAHEDRAL_GLSL
#define PNB_OCTAHEDRAL_GLSL

vec2 signNotZero(vec2 v) { return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }

vec2 octEncode(vec3 n) {
    vec2 p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    return n.z <= 0.0 ? (1.0 - abs(p.yx)) * signNotZero(p) : p;
}

vec3 octDecode(vec2 e) {
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) v.xy = (1.0 - abs(v.yx)) * signNotZero(v.xy);
    return normalize(v);
}

#endif
