#version 450
// Placeholder of the deforming pre-pass (skins and morph targets), so that the converter's
// packing and glslang validation of a compute program work; the player's version replaces it.
layout(local_size_x = 64) in;
void main() {}
