#version 450 core
// flat.frag — one colour per draw (layer view) or a constant to accumulate (overdraw view).
layout(location = 1) uniform vec4 uColor;
layout(location = 0) out vec4 outColor;

void main() { outColor = uColor; }
