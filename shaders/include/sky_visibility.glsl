// sky_visibility.glsl — how much of the sky a point sees, from the depth buffer (ibl.visibility
// = screen; deferred lighting only: forward materials draw into the depth they would read).
// Without it the sky lights the floor of a street canyon as brightly as a rooftop.
//
// 12 rays over the hemisphere around n, cosine-distributed (so the unblocked fraction is the
// cosine-weighted visibility the irradiance needs), each marched in 6 steps out to
// uIblParams.z scene units; a ray is blocked when a step lands behind the depth buffer's surface
// by less than the radius (thicker gaps are taken as passing behind an object). The ray set is
// turned per pixel by interleaved gradient noise (Jimenez 2014), so banding becomes fine noise.
// What it cannot see: occluders off screen or hidden behind nearer surfaces — the error measured
// against the ray-traced sky light (docs/PLAYER.md "Sky and image-based lighting").
#ifndef PNB_SKY_VISIBILITY_GLSL
#define PNB_SKY_VISIBILITY_GLSL

// `p` camera-relative world position, `n` unit normal; uGDepth, uViewProjection and
// uInverseViewProjection are the lighting pass's.
float skyVisibility(vec3 p, vec3 n) {
    float radius = uIblParams.z;
    if (radius <= 0.0) return 1.0;
    const int kRays = 12, kSteps = 6;
    vec3 t = normalize(abs(n.y) < 0.99 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
    vec3 b = cross(n, t);
    float turn = 6.2831853 * fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715))));
    float eyeDistance = length(p);
    vec3 origin = p + n * (1e-3 * eyeDistance + 1e-3 * radius);
    float open = 0.0;
    for (int i = 0; i < kRays; ++i) {
        // Cosine-weighted directions: the Hammersley point (i + 1/2)/N, radical inverse.
        float u1 = (float(i) + 0.5) / float(kRays);
        float u2 = float(bitfieldReverse(uint(i))) * 2.3283064e-10;
        float r = sqrt(u1), phi = 6.2831853 * u2 + turn;
        vec3 dir = t * (r * cos(phi)) + b * (r * sin(phi)) + n * sqrt(max(0.0, 1.0 - u1));
        bool blocked = false;
        for (int s = 1; s <= kSteps && !blocked; ++s) {
            float d = radius * float(s * s) / float(kSteps * kSteps); // denser near the surface
            vec3 q = origin + dir * d;
            vec4 clip = uViewProjection * vec4(q, 1.0);
            if (clip.w <= 0.0) break; // behind the eye: nothing on screen can block it
            vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
            if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) break; // off screen
            float stored = textureLod(uGDepth, uv, 0.0).r;
            if (stored <= 0.0) continue; // sky there
            vec4 h = uInverseViewProjection * vec4(uv * 2.0 - 1.0, stored, 1.0);
            float behind = length(q) - length(h.xyz / h.w);
            blocked = behind > 0.0 && behind < radius;
        }
        open += blocked ? 0.0 : 1.0;
    }
    return open / float(kRays);
}

#endif
