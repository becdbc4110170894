// pnb-judge — pnb-play with the ray-traced truth: every option of pnb-play, plus --shadow-metrics,
// --gi-metrics and --sky-metrics, which compare the frames it draws with Embree (pnb_reference).
// A separate binary so that the lean player never links the ray tracer (docs/ARCHITECTURE.md).
#include "play_app.h"
#include "truth_judges.h"

int main(int argc, char** argv) {
    return pnb::player::runPlayer(argc, argv, "pnb-judge", pnb::player::makeTruthJudge);
}
