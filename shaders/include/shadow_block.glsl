// shadow_block.glsl — the sun's shadow maps as the player fitted them this frame. Written by the
// CPU (single, LiSPSM, PSSM) or by the SDSM compute passes (player/shaders/sdsm.comp), and read
// by the shadow pass and by lighting. The block is declared once, for GLSL and C++, in
// shared/shadow_block.h; this file keeps the name the shaders include.
#ifndef PNB_SHADOW_BLOCK_GLSL
#define PNB_SHADOW_BLOCK_GLSL

#include "../shared/shadow_block.h"

#endif
