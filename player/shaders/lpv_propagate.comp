#version 450 core
// lpv_propagate.comp — one propagation step (Kaplanyan & Dachsbacher 2010, with three changes
// measured against the analytic single-VPL case; docs/PLAYER.md, "Global illumination"): every
// cell gathers from its six neighbours. A neighbour's intensity, evaluated towards each of this
// cell's faces that it sees (the far face: 0.4006696846 sr; four side faces: 0.4234313544 sr
// each), times that solid angle, is the flux through the face. Six neighbours x (far + 4 sides)
// cover 4 pi.
//  1. Flux kept for any lobe: the clamped evaluation of an L1 lobe 1 + k cos (k > 1) integrates
//     to (k + 1)^2 / (4k) of its flux (a cosine lobe: +12.5 % a step, a beam: +33 %), so a
//     source is scaled by the inverse before it is evaluated (conservingSource): each step stores
//     its result so scaled as the next step's source, and a first dispatch with uScaleOnly scales
//     the injection (once per cell, not once per neighbour and step: llvmpipe paid 2.5x the step
//     for scaling on reading).
//  2. The flux through a face is a narrow bundle (0.4 sr, a cone of ~20 degrees), re-emitted as a
//     beam (the L1 projection of one direction: band 1 at 1.5x the cosine lobe's), not as a
//     cosine lobe filling a hemisphere. K&D's cosine lobe is what turns the light through 90
//     degrees at every step and makes propagation a diffusion.
//  3. A side face's beam leaves along e + 0.75 d (e the face's normal, d the step), between the
//     face normal (K&D) and the bundle's own direction 2 d + e: light keeps going the way it went.
// With OCCLUSION each face lets in the fraction lpv_resolve.comp's RESOLVE_TRANSMITTANCE found
// from the geometry volume (once per frame, not once per step); the other variant, PLAIN, lets
// everything through. The step's result goes to the next source (images 0-2, scaled as in 1.) and
// is added to the sum (images 3-5). Cascades are stacked along z; a neighbour outside this cell's
// cascade is dark.
// With GLASS (issue 43: translucent casters exist), the flux of each colour entering a cell that
// holds a pane (uGlass: rgb = the pane's T, a = 1; pass_gi_lpv_glass.cpp) from one that holds none
// is multiplied by that colour's T: a pane dims and tints once per crossing, a pane voxelised
// into two neighbouring cells (lying on their shared face) counts once.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

layout(binding = 0) uniform sampler3D uSourceR;
layout(binding = 1) uniform sampler3D uSourceG;
layout(binding = 2) uniform sampler3D uSourceB;
layout(binding = 3) uniform sampler3D uTransmit0; // per cell: faces from the -x, +x, -y, +y neighbours
layout(binding = 4) uniform sampler3D uTransmit1; // from the -z, +z neighbours
#ifdef GLASS
layout(binding = 5) uniform sampler3D uGlass; // per cell: rgb = its pane's T, a = 1 where a pane is
#endif

layout(rgba16f, binding = 0) writeonly uniform image3D uNextR;
layout(rgba16f, binding = 1) writeonly uniform image3D uNextG;
layout(rgba16f, binding = 2) writeonly uniform image3D uNextB;
layout(rgba16f, binding = 3) uniform image3D uSumR;
layout(rgba16f, binding = 4) uniform image3D uSumG;
layout(rgba16f, binding = 5) uniform image3D uSumB;

layout(location = 0) uniform ivec2 uGrid; // cells, cascades
layout(location = 1) uniform bool uScaleOnly; // write the source scaled to the next, no step

const float kFarFace = 0.4006696846;
const float kSideFace = 0.4234313544;
const float kShY0 = 0.282094792, kShY1 = 0.488602512;
const float kLobeC0 = 0.886226925, kLobeC1 = 1.023326708;
const float kInvPi = 0.318309886;
// band 1 over band 0: sqrt(3) for a beam, 2 / sqrt(3) for a cosine lobe; their ratio
const float kBeam = 1.5;
const float kSideForward = 0.75; // how far a side face's beam leans from e towards d
const float kSideUnit = 0.8;     // 1 / |e + kSideForward d| (e and d are orthogonal unit vectors)

vec4 basis(vec3 w) { return vec4(kShY0, -kShY1 * w.y, kShY1 * w.z, -kShY1 * w.x); }
vec4 lobe(vec3 n) { return vec4(kLobeC0, -kLobeC1 * n.y, kLobeC1 * n.z, -kLobeC1 * n.x); }
// A beam of flux pi along n (so that flux / pi scales both it and the lobe alike).
vec4 beam(vec3 n) { return vec4(kLobeC0, kBeam * lobe(n).yzw); }

// The source c (one colour) scaled so that its evaluations, clamped at zero, sum to its flux:
// c = a + b cos with k = b / a = sqrt(3) |c1| / c0; above k = 1 the clamp removes a negative
// lobe and adds (k + 1)^2 / (4k) - 1 of the flux.
vec4 conservingSource(vec4 c) {
    float a = c.x, b = 1.7320508 * length(c.yzw);
    return b > a ? c * (4.0 * a * b / ((a + b) * (a + b))) : c;
}

const ivec3 kDirections[6] = ivec3[](ivec3(1, 0, 0), ivec3(-1, 0, 0), ivec3(0, 1, 0),
                                     ivec3(0, -1, 0), ivec3(0, 0, 1), ivec3(0, 0, -1));

void main() {
    ivec3 id = ivec3(gl_GlobalInvocationID);
    int cells = uGrid.x;
    if (id.x >= cells || id.y >= cells || id.z >= cells * uGrid.y) return;
    if (uScaleOnly) {
        imageStore(uNextR, id, conservingSource(texelFetch(uSourceR, id, 0)));
        imageStore(uNextG, id, conservingSource(texelFetch(uSourceG, id, 0)));
        imageStore(uNextB, id, conservingSource(texelFetch(uSourceB, id, 0)));
        return;
    }
    int cascade = id.z / cells;
    ivec3 local = ivec3(id.xy, id.z - cascade * cells);
    vec4 sum[3] = vec4[](vec4(0.0), vec4(0.0), vec4(0.0));
#ifdef OCCLUSION
    vec4 t0 = texelFetch(uTransmit0, id, 0), t1 = texelFetch(uTransmit1, id, 0);
    float transmitted[6] = float[](t0.x, t0.y, t0.z, t0.w, t1.x, t1.y);
#endif
#ifdef GLASS
    // Per neighbour, the factor its flux takes entering this cell, per colour: this cell's pane's
    // T from a neighbour without a pane, else 1. Fetched before the loop, and only in a pane's
    // cell: a fetch under a condition inside the loop doubled the step's time on llvmpipe.
    vec4 glassHere = texelFetch(uGlass, id, 0);
    vec4 entering[6] = vec4[](vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0), vec4(1.0));
    if (glassHere.a > 0.5) {
        for (int i = 0; i < 6; ++i) {
            ivec3 from = clamp(local - kDirections[i], ivec3(0), ivec3(cells - 1));
            bool paneThere = texelFetch(uGlass, from + ivec3(0, 0, cascade * cells), 0).a > 0.5;
            entering[i] = paneThere ? vec4(1.0) : vec4(glassHere.rgb, 1.0);
        }
    }
#endif
    for (int i = 0; i < 6; ++i) {
        ivec3 d = kDirections[i]; // from the neighbour towards this cell
        ivec3 from = local - d;
        if (any(lessThan(from, ivec3(0))) || any(greaterThanEqual(from, ivec3(cells)))) continue;
        ivec3 at = from + ivec3(0, 0, cascade * cells);
        vec4 src[3] = vec4[](texelFetch(uSourceR, at, 0), texelFetch(uSourceG, at, 0),
                             texelFetch(uSourceB, at, 0));
        float transmit = 1.0;
#ifdef OCCLUSION
        transmit = transmitted[i];
#endif
#ifdef GLASS
        // T >= 0 scales the source: the evaluations below are clamped at zero, so scaling
        // before is scaling after, and the face loops stay as they are.
        for (int ch = 0; ch < 3; ++ch) src[ch] *= entering[i][ch];
#endif
        vec3 dv = vec3(d);
        // The far face: straight on.
        {
            vec4 y = basis(dv), l = beam(dv) * (kFarFace * kInvPi * transmit);
            for (int ch = 0; ch < 3; ++ch) sum[ch] += max(dot(src[ch], y), 0.0) * l;
        }
        // The four side faces: towards d + 0.5 e, re-emitted along e + kSideForward d.
        for (int j = 0; j < 4; ++j) {
            ivec3 e3 = kDirections[(i / 2 * 2 + 2 + j) % 6];
            vec3 e = vec3(e3);
            vec4 y = basis(normalize(dv + 0.5 * e));
            vec4 l = beam((e + kSideForward * dv) * kSideUnit) * (kSideFace * kInvPi * transmit);
            for (int ch = 0; ch < 3; ++ch) sum[ch] += max(dot(src[ch], y), 0.0) * l;
        }
    }
    imageStore(uNextR, id, conservingSource(sum[0]));
    imageStore(uNextG, id, conservingSource(sum[1]));
    imageStore(uNextB, id, conservingSource(sum[2]));
    imageStore(uSumR, id, imageLoad(uSumR, id) + sum[0]);
    imageStore(uSumG, id, imageLoad(uSumG, id) + sum[1]);
    imageStore(uSumB, id, imageLoad(uSumB, id) + sum[2]);
}
