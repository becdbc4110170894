// gui.h — the material editor's window (issue 6): pnb-edit calls runGui when it is started
// without batch options (edit_main.cpp).
//
// Does NOT do: batch editing (edit_main.cpp and pnb_editor do that, without a window).
#pragma once

namespace pnb::editor {

// Runs the editor window; argv is pnb-edit's command line (an optional SCENE.pnb to open).
// Returns the process exit code.
int runGui(int argc, char** argv);

} // namespace pnb::editor
