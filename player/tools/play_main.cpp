// pnb-play — the lean player: loads a .pnb container and renders it in a window, or headless for
// benchmarks, screenshots and buffer dumps (play_app.h). It links no ray tracer: the truth
// metrics are pnb-judge's (judge/).
#include "play_app.h"

int main(int argc, char** argv) { return pnb::player::runPlayer(argc, argv, "pnb-play", {}); }
