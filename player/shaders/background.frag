#version 450 core
// background.frag — the environment where no surface was drawn (depth still clear): its
// equirectangular radiance (docs/FORMAT.md "ENVM") along each pixel's view ray (one direction
// for all of them under an orthographic camera), turned by
// ibl.rotation_deg and scaled by ibl.intensity, at the mip level whose texels match the pixels
// (textureLod: the seam at u = 0 | 1 would make derivative-chosen levels flicker).
layout(binding = 0) uniform sampler2D uRadiance;
layout(location = 0) uniform mat4 uInverseViewProjection; // NDC -> camera-relative world
layout(location = 1) uniform vec4 uParams;                // cos, sin of the rotation; intensity; level

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() {
    // The view ray: from the pixel's point on the near plane (depth 1) to a farther one on the
    // same ray. Through the eye for perspective; parallel to the view axis, the same direction
    // at every pixel, for orthographic.
    vec4 a = uInverseViewProjection * vec4(vUv * 2.0 - 1.0, 1.0, 1.0);
    vec4 b = uInverseViewProjection * vec4(vUv * 2.0 - 1.0, 0.5, 1.0);
    vec3 w = normalize(b.xyz / b.w - a.xyz / a.w);
    float c = uParams.x, s = uParams.y;
    vec3 e = vec3(c * w.x - s * w.z, w.y, s * w.x + c * w.z); // R_y(-angle) w, as ibl.glsl
    float u = atan(e.z, e.x) / 6.28318531 + 0.5;
    float v = acos(clamp(e.y, -1.0, 1.0)) / 3.14159265;
    outColor = vec4(textureLod(uRadiance, vec2(u, v), uParams.w).rgb * uParams.z, 1.0);
}
