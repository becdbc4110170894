#version 450 core
// forward.frag — shades a surface directly into the HDR target (forward materials: blended or
// otherwise kept out of the G-buffer). Output alpha drives SRC_ALPHA / ONE_MINUS_SRC_ALPHA.
#include "include/surface_input.glsl"
#include "include/lights.glsl"
#ifdef GI
#include "include/gi_lookup.glsl"
#endif
#ifdef IBL
#include "include/ibl.glsl"
#endif

layout(location = 0) out vec4 outColor;

void main() {
    Surface s = evaluateSurface(surfaceInput());
    vec3 v = viewVector(vPosition); // camera at the origin of camera-relative space
#ifdef GI
    if (giCaptureIrradiance()) { // CaptureBuffer::Indirect: the irradiance GI adds, per pixel
        // Blended surfaces write no depth: the value below them, whose depth the frame kept,
        // stays (the truth is traced at that surface).
        outColor = vec4(giIrradiance(vPosition, s.normal), s.alpha < 1.0 ? 0.0 : 1.0);
        return;
    }
#endif
    if (uAlphaParams.w > 0.5) { // KHR_materials_unlit: the colour as authored, no light at all
        outColor = vec4(s.baseColor + s.emissive, s.alpha);
        return;
    }
    vec3 color = shadeLights(s.baseColor, s.metallic, s.roughness, s.normal, vPosition, v, true);
#ifdef IBL
    if (iblCaptureSky()) { // CaptureBuffer::Sky (forward surfaces: no sky visibility term)
        outColor = vec4(iblIrradiance(s.normal), s.alpha < 1.0 ? 0.0 : 1.0);
        return;
    }
#endif
    // Occlusion darkens indirect light only (glTF's definition): the ambient term (or the
    // environment's light, which replaces it) and GI.
    vec3 indirect = uAmbient.rgb * s.baseColor;
#ifdef IBL
    if (iblActive()) indirect = iblShade(s.baseColor, s.metallic, s.roughness, s.normal, v);
#endif
#ifdef GI
    indirect += giIrradiance(vPosition, s.normal) * s.baseColor * ((1.0 - s.metallic) / 3.14159265);
#endif
    color += indirect * s.occlusion + s.emissive;
    outColor = vec4(color, s.alpha);
#ifdef SHADOWS
    outColor = shadowOutput(outColor);
#endif
}
