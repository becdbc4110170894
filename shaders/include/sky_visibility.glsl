// sky_visibility.glsl — how much of the sky a point sees (ibl.visibility; deferred lighting only:
// forward materials draw into the depth they would read). Without it the sky lights the floor of
// a street canyon as brightly as a rooftop.
//
// 12 rays (volume: 4) over the hemisphere around n, cosine-distributed (so the unblocked fraction is the
// cosine-weighted visibility the irradiance needs), each marched out to uIblParams.z scene units
// (6 steps for screen, 16 for height, denser near the surface). The ray set is turned per pixel by
// interleaved gradient noise (Jimenez 2014), so banding becomes fine noise. The term is not the
// fraction of open rays but the fraction of the environment's light they carry: each ray weighs
// by the radiance along it (the prefiltered cube at roughness 0.25, when ibl.specular binds it),
// so the irradiance SH times the term keeps where the sky is bright. A canyon's floor sees the
// zenith, not the bright horizon its SH irradiance averages in; counting rays made the street's
// sky light 25 % too dark (energy 0.75, 1.39 x the best constant's error with height; weighted
// by the cube's roughest level 0.86, 1.03; at roughness 0.5: 0.94, 0.73; 0.25: 1.00, 0.53; the mirror
// level: 1.02, 0.48 — 0.25 spreads a sun disc over its neighbours). A step is blocked
//   screen: when it lands behind the depth buffer's surface by less than the radius (thicker
//           gaps are taken as passing behind an object). Blind to occluders off screen or hidden
//           behind nearer surfaces;
//   height: when it is below the height map's highest surface there (the scene seen from above,
//           pass_sky_height.cpp). Sees off screen; blind to overhangs (the sky under a roof's
//           eaves or through a room's open side is taken as hidden by the roof);
//   volume: (GI permutation, gi.occlusion) not blocked but dimmed, cell by cell, by the light
//           propagation volumes' face transmittances (what the LPV's geometry lets through from
//           one cell into the next; lpv_resolve.comp): the LPV's occlusion darkens sky light as
//           it darkens the bounce. As coarse as the cells; sees what the RSM and the camera saw.
//   probes: (GI permutation, gi.technique = probes) no rays per pixel: every probe traced 256
//           directions through the occupancy grid once (gi_probe_gather.comp, SKY_VISIBILITY)
//           and holds the L1 SH of what it sees; a pixel blends the 8 probes around it, those
//           behind the surface (which see the other side's sky) weighing next to nothing, never
//           a probe inside a solid voxel. Sees every surface the grid holds (overhangs, a
//           room's roof and open side alike), as coarse as the probes; noise-free and stable
//           while the camera moves. Panes (BLEND materials that cast shadows, issue 43) tint
//           and dim what a probe sees through them: the volume then holds one SH per colour
//           (red, green, blue stacked along z), and the term is a colour. The probes' open
//           fraction is weighted by the sky's radiance as the rays are (probeSkyVisibility).
// Their errors against the ray-traced sky light: docs/PLAYER.md "Sky and image-based lighting".
#ifndef PNB_SKY_VISIBILITY_GLSL
#define PNB_SKY_VISIBILITY_GLSL

// `p` camera-relative world position, `n` unit normal; uGDepth, uViewProjection and
// uInverseViewProjection are the lighting pass's.
layout(binding = 15) uniform sampler2D uIblHeight;

// Whether camera-relative q is below the highest surface of the height map (outside it: open).
bool belowHeightMap(vec3 q) {
    vec2 uv = (q.xz - uIblHeightRect.xy) * uIblHeightRect.zw;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return false;
    return q.y < uIblHeightRange.x + textureLod(uIblHeight, uv, 0.0).r * uIblHeightRange.y;
}

// Whether camera-relative q is behind the depth buffer's surface by less than `radius`.
bool behindDepthBuffer(vec3 q, float radius, out bool gone) {
    gone = false;
    vec4 clip = uViewProjection * vec4(q, 1.0);
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    if (clip.w <= 0.0 || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
        gone = true; // behind the eye or off screen: nothing known can block it any more
        return false;
    }
    float stored = textureLod(uGDepth, uv, 0.0).r;
    if (stored <= 0.0) return false; // sky there
    vec4 h = uInverseViewProjection * vec4(uv * 2.0 - 1.0, stored, 1.0);
    vec3 surface = h.xyz / h.w; // on q's view ray: how far q lies past it along the ray
    float behind = dot(q - surface, -viewVector(surface));
    return behind > 0.0 && behind < radius;
}

// Ray i of n over the hemisphere around the frame (t, b, nrm), cosine-distributed: the
// Hammersley point (i + 1/2)/n, radical inverse, turned by `turn` radians.
vec3 skyRay(int i, int n, float turn, vec3 t, vec3 b, vec3 nrm) {
    float u1 = (float(i) + 0.5) / float(n);
    float u2 = float(bitfieldReverse(uint(i))) * 2.3283064e-10;
    float r = sqrt(u1), phi = 6.2831853 * u2 + turn;
    return t * (r * cos(phi)) + b * (r * sin(phi)) + nrm * sqrt(max(0.0, 1.0 - u1));
}

// The environment's radiance along world direction `dir`, blurred to roughness 0.25 (weights of
// the rays; the cube is bound only with ibl.specular: uIblRotation.w).
vec3 skyRadianceAlong(vec3 dir) {
    return textureLod(uIblSpecular, iblToEnvironment(dir), 0.25 * uIblRotation.z).rgb + 1e-6;
}

#ifdef GI
layout(binding = 16) uniform sampler3D uGiTransmit0; // faces from the -x, +x, -y, +y neighbours
layout(binding = 17) uniform sampler3D uGiTransmit1; // from the -z, +z neighbours

// The fraction of sky light along `dir` that the propagation volumes' geometry lets through from
// camera-relative p: one cell of the finest cascade holding the point per step (12 at most),
// each step passing the face it enters by (the faces of the three axes weighted by dir's squared
// components, which sum to 1). Leaving the outer cascade: open sky.
float volumeTransmittance(vec3 p, vec3 dir) {
    float through = 1.0;
    float cells = uGiGrid.x;
    int cascades = int(uGiGrid.y);
    vec3 x = p;
    vec3 w = dir * dir;
    for (int s = 0; s < 12 && through > 0.01; ++s) {
        int c = 0;
        vec3 q;
        for (; c < cascades; ++c) {
            q = (x - uGiCascade[c].xyz) / uGiCascade[c].w;
            if (all(greaterThan(q, vec3(0.5))) && all(lessThan(q, vec3(cells - 0.5)))) break;
        }
        if (c == cascades) break; // outside every cascade: nothing known blocks it
        x += dir * uGiCascade[c].w;
        q += dir;
        vec3 t = clamp(q, vec3(0.5), vec3(cells - 0.5));
        vec3 uvw = (t + vec3(0.0, 0.0, float(c) * cells)) / vec3(cells, cells, cells * uGiGrid.y);
        vec4 t0 = textureLod(uGiTransmit0, uvw, 0.0);
        vec2 t1 = textureLod(uGiTransmit1, uvw, 0.0).rg;
        through *= w.x * (dir.x > 0.0 ? t0.r : t0.g) + w.y * (dir.y > 0.0 ? t0.b : t0.a) +
                   w.z * (dir.z > 0.0 ? t1.r : t1.g);
    }
    return through;
}

layout(binding = 18) uniform sampler3D uGiSkyVisibility; // per probe: L1 SH of the open directions
                                                         // (per colour, stacked along z, with panes)

// The cosine-weighted fraction of the sky the probes around camera-relative p see around n:
// the 8 probes around the point half a cell in front of the surface (as the indirect light's
// look-up), each weighted by its trilinear weight times max(0, cos) + 0.01, cos the angle
// between n and the direction to the probe. A probe behind the surface (outside the room's
// wall) sees the whole sky the surface does not: a plain trilinear blend lets it in. (The
// indirect light keeps its plain trilinear fetch: the same weights there cost a quarter of a
// 1280x720 frame on llvmpipe, 8 x 3 fetches instead of 3, for no better error.) Measured on the
// box room's sky (160x90, 64 rays): 0.477 x the best constant's error, DDGI's smoother
// ((cos + 1) / 2)^2 + 0.2: 0.495.
vec3 probeSkyVisibility(vec3 p, vec3 n) {
    int cells = int(uGiGrid.x);
    bool colour = textureSize(uGiSkyVisibility, 0).z > cells;
    float spacing = uGiCascade[0].w;
    vec3 g = (p - uGiCascade[0].xyz) / spacing + 0.5 * n - 0.5; // probe i sits at cell centre i + 0.5
    ivec3 base = ivec3(floor(g));
    vec3 f = g - vec3(base);
    vec4 lobe = vec4(0.886226925, -1.023326708 * n.y, 1.023326708 * n.z, -1.023326708 * n.x);
    vec3 sum = vec3(0.0);
    vec4 blended = vec4(0.0); // the probes' visibility SH (grey), for the radiance weighting
    float total = 0.0;
    for (int i = 0; i < 8; ++i) {
        ivec3 o = ivec3(i & 1, (i >> 1) & 1, i >> 2);
        ivec3 at = clamp(base + o, ivec3(0), ivec3(cells - 1));
        vec4 v = texelFetch(uGiSkyVisibility, at, 0);
        if (v.x < 0.0) continue; // inside a solid voxel
        vec3 tri = mix(1.0 - f, f, vec3(o));
        vec3 toProbe = uGiCascade[0].xyz + (vec3(at) + 0.5) * spacing - p;
        float front = max(dot(toProbe, n) * inversesqrt(max(dot(toProbe, toProbe), 1e-30)), 0.0) + 0.01;
        float w = tri.x * tri.y * tri.z * front;
        vec3 seen = vec3(dot(v, lobe));
        if (colour) {
            seen.g = dot(texelFetch(uGiSkyVisibility, at + ivec3(0, 0, cells), 0), lobe);
            seen.b = dot(texelFetch(uGiSkyVisibility, at + ivec3(0, 0, 2 * cells), 0), lobe);
        }
        sum += w * seen;
        blended += w * v;
        total += w;
    }
    if (total <= 0.0) return vec3(1.0); // every probe around is solid: nothing known blocks it
    vec3 fraction = sum / (total * 3.14159265);
    if (uIblRotation.w < 0.5) return clamp(fraction, 0.0, 1.0);
    // As the rays of the other modes, weighted by the sky's radiance: the open directions'
    // mean radiance (12 fixed directions around n, each by the probes' visibility there, the L1
    // SH's value) over all directions' mean. The cosine-weighted fraction assumes the hidden sky
    // as bright as the visible.
    blended /= total;
    vec3 t = normalize(abs(n.y) < 0.99 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
    vec3 b = cross(n, t);
    vec3 openRadiance = vec3(0.0), allRadiance = vec3(0.0);
    float openWeight = 0.0;
    for (int i = 0; i < 12; ++i) {
        vec3 dir = skyRay(i, 12, 0.0, t, b, n);
        float seen = clamp(0.282094792 * blended.x + 0.488602512 * (dot(blended.wyz, vec3(-dir.x, -dir.y, dir.z))),
                           0.0, 1.0);
        vec3 radiance = skyRadianceAlong(dir);
        openRadiance += seen * radiance;
        openWeight += seen;
        allRadiance += radiance;
    }
    if (openWeight < 1e-3) return clamp(fraction, 0.0, 1.0);
    return clamp(fraction * (openRadiance / openWeight) / (allRadiance / 12.0), 0.0, 1.0);
}
#endif

// A colour: the probes' term is tinted by the panes they see the sky through; the others are grey.
vec3 skyVisibility(vec3 p, vec3 n) {
    float radius = uIblParams.z;
    int mode = int(uIblHeightRange.z + 0.5);
    if (mode == 0 || (radius <= 0.0 && mode < 3)) return vec3(1.0);
#ifdef GI
    if (mode == 4) return probeSkyVisibility(p, n);
#endif
    const int kRays = 12, kSteps = 6, kHeightSteps = 16;
    vec3 t = normalize(abs(n.y) < 0.99 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
    vec3 b = cross(n, t);
    float turn = 6.2831853 * fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715))));
    float eyeDistance = length(p);
    // Off the surface: by a little (screen), or by one and a half height-map texels, so that a
    // wall does not find its own top in the texel it stands in.
    vec3 origin = p + n * (mode == 2 ? 1.5 * uIblHeightRange.w : 1e-3 * eyeDistance + 1e-3 * radius);
    vec3 open = vec3(0.0), total = vec3(0.0); // radiance of the open rays, of all rays
    bool weighted = uIblRotation.w > 0.5;       // the cube is bound (ibl.specular)
    // Volume: a ray returns a transmittance, not a yes/no, so 4 rays carry what 12 do for the
    // binary terms.
    const int rays = mode == 3 ? 4 : kRays;
    for (int i = 0; i < rays; ++i) {
        vec3 dir = skyRay(i, rays, turn, t, b, n);
        vec3 weight = weighted ? skyRadianceAlong(dir) : vec3(1.0);
        total += weight;
#ifdef GI
        if (mode == 3) {
            open += weight * volumeTransmittance(p + n * (0.5 * uGiCascade[0].w), dir);
            continue;
        }
#endif
        bool blocked = false;
        // Height: 16 steps, denser near the surface (quadratic, as screen's). 12 even steps of
        // radius / 12 (25 m in the 2 km street canyon) stepped over its 18-30 m deep buildings:
        // along its path the sky light came out up to 1.6x too bright (1.19 x the best constant's
        // error); quadratic 12: 0.90 at worst, quadratic 16: 0.78, even 24: 0.73 at 1.5x the cost.
        int steps = mode == 2 ? kHeightSteps : kSteps;
        for (int s = 1; s <= steps && !blocked; ++s) {
            vec3 q;
            if (mode == 2) {
                q = origin + dir * (radius * float(s * s) / float(steps * steps));
                blocked = belowHeightMap(q);
            } else {
                q = origin + dir * (radius * float(s * s) / float(steps * steps)); // denser near
                                                                                   // the surface
                bool gone;
                blocked = behindDepthBuffer(q, radius, gone);
                if (gone) break;
            }
        }
        if (!blocked) open += weight;
    }
    return open / total;
}

#endif
