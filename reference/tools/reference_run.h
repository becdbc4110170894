// pnb-reference's run: the shadowing light's ray-traced visibility at every pixel of a dumped
// frame, its comparison with the player's shadow factor, the irradiance truths asked for, and the
// files and summary line that report them.
#pragma once

#include "reference_cli.h"

namespace pnb::reference_tool {

// Returns the process exit code (reference_io.h: kExitOk ... kExitEmbree).
int run(const Settings& settings);

} // namespace pnb::reference_tool
