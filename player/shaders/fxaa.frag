#version 450 core
// fxaa.frag — edge anti-aliasing on the tone-mapped image, after Lottes' FXAA 3.11 "quality"
// idea reduced to its core: find the local edge direction from luma, then blend along it with a
// short search for the edge end. Input is sampled linear (sRGB texture); luma uses sqrt as a
// cheap perceptual curve.
layout(binding = 0) uniform sampler2D uImage;
layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

float luma(vec3 c) { return sqrt(dot(c, vec3(0.299, 0.587, 0.114))); }

void main() {
    vec2 texel = 1.0 / vec2(textureSize(uImage, 0));
    vec3 rgbM = texture(uImage, vUv).rgb;
    float lM = luma(rgbM);
    float lN = luma(textureOffset(uImage, vUv, ivec2(0, 1)).rgb);
    float lS = luma(textureOffset(uImage, vUv, ivec2(0, -1)).rgb);
    float lE = luma(textureOffset(uImage, vUv, ivec2(1, 0)).rgb);
    float lW = luma(textureOffset(uImage, vUv, ivec2(-1, 0)).rgb);
    float lMin = min(lM, min(min(lN, lS), min(lE, lW)));
    float lMax = max(lM, max(max(lN, lS), max(lE, lW)));
    float range = lMax - lMin;
    if (range < max(0.0312, lMax * 0.125)) { outColor = vec4(rgbM, 1.0); return; }

    float lNW = luma(textureOffset(uImage, vUv, ivec2(-1, 1)).rgb);
    float lNE = luma(textureOffset(uImage, vUv, ivec2(1, 1)).rgb);
    float lSW = luma(textureOffset(uImage, vUv, ivec2(-1, -1)).rgb);
    float lSE = luma(textureOffset(uImage, vUv, ivec2(1, -1)).rgb);
    float horizontal = abs(lNW + lNE - 2.0 * lN) + 2.0 * abs(lW + lE - 2.0 * lM) + abs(lSW + lSE - 2.0 * lS);
    float vertical = abs(lNW + lSW - 2.0 * lW) + 2.0 * abs(lN + lS - 2.0 * lM) + abs(lNE + lSE - 2.0 * lE);
    bool isHorizontal = horizontal >= vertical;

    float l1 = isHorizontal ? lS : lW, l2 = isHorizontal ? lN : lE;
    float g1 = abs(l1 - lM), g2 = abs(l2 - lM);
    float step = isHorizontal ? texel.y : texel.x;
    float lEdge;
    if (g1 >= g2) { step = -step; lEdge = 0.5 * (l1 + lM); } else { lEdge = 0.5 * (l2 + lM); }
    float gradient = 0.25 * max(g1, g2);

    vec2 uvEdge = vUv;
    if (isHorizontal) uvEdge.y += 0.5 * step; else uvEdge.x += 0.5 * step;
    vec2 dir = isHorizontal ? vec2(texel.x, 0.0) : vec2(0.0, texel.y);
    vec2 uvP = uvEdge + dir, uvN = uvEdge - dir;
    float dP = luma(texture(uImage, uvP).rgb) - lEdge, dN = luma(texture(uImage, uvN).rgb) - lEdge;
    const float kSteps[8] = float[](1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 4.0, 8.0);
    for (int i = 0; i < 8; ++i) {
        bool doneP = abs(dP) >= gradient, doneN = abs(dN) >= gradient;
        if (doneP && doneN) break;
        if (!doneP) { uvP += dir * kSteps[i]; dP = luma(texture(uImage, uvP).rgb) - lEdge; }
        if (!doneN) { uvN -= dir * kSteps[i]; dN = luma(texture(uImage, uvN).rgb) - lEdge; }
    }
    float distP = isHorizontal ? uvP.x - vUv.x : uvP.y - vUv.y;
    float distN = isHorizontal ? vUv.x - uvN.x : vUv.y - uvN.y;
    bool closerP = distP < distN;
    float endDelta = closerP ? dP : dN;
    float offset = 0.0;
    if ((lM - lEdge < 0.0) != (endDelta < 0.0))
        offset = 0.5 - min(distP, distN) / (distP + distN);
    // Sub-pixel aliasing from the 3x3 average.
    float average = (2.0 * (lN + lS + lE + lW) + lNW + lNE + lSW + lSE) / 12.0;
    float sub = clamp(abs(average - lM) / range, 0.0, 1.0);
    sub = (-2.0 * sub + 3.0) * sub * sub;
    offset = max(offset, sub * sub * 0.75);
    vec2 uv = vUv;
    if (isHorizontal) uv.y += offset * step; else uv.x += offset * step;
    outColor = vec4(texture(uImage, uv).rgb, 1.0);
}
