// gl_debug.h — KHR_debug output routed to stderr; shared by both context kinds.
#pragma once

namespace pnb::player {

// Installs the debug callback on the current context. Errors are always reported; with
// `verbose`, performance and portability messages too.
void installGlDebugOutput(bool verbose);

} // namespace pnb::player
