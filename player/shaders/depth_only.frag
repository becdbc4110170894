#version 450 core
// depth_only.frag — nothing but depth (the sky-visibility height map).
void main() {}
