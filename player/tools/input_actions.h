// input_actions.h — pnb-play's window input, separated from GLFW: events (from GLFW callbacks or
// a scripted-input file) go through InputMapper, which keeps the held keys/buttons/cursor the fly
// camera reads and turns edges into actions (quit, record, screenshot, open a dropped file, wheel
// speed/zoom). Tests drive the same layer the window does (tests/player/input_actions_test.cpp,
// and `pnb-play --script-input FILE` under Xvfb).
//
// Bindings (docs/PLAYER.md): Esc or the window's close quits; F9 starts/stops path recording;
// K adds a key while recording; F12 saves a screenshot; O toggles orbit; the wheel scales the fly
// speed, and with Ctrl (either) or the right button held changes the field of view.
//
// Scripted input (one event per line, `#` comments, times in seconds of window time, which
// advances by the frame dt — use --fixed-dt for reproducible runs — and non-decreasing):
//   TIME key NAME down|up|tap      NAME: A..Z, 0..9, F1..F12, ESCAPE, SPACE, ENTER, TAB,
//                                  LEFT_SHIFT, RIGHT_SHIFT, LEFT_CONTROL, RIGHT_CONTROL,
//                                  LEFT_ALT, UP, DOWN, LEFT, RIGHT
//   TIME button left|right|middle down|up
//   TIME cursor X Y                window coordinates in pixels
//   TIME scroll DX DY              wheel notches (DY > 0: away from the user)
//   TIME drop PATH                 the rest of the line is one path
//   TIME close | iconify | restore
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "pnb_player/play_error.h"

namespace pnb::player {

enum class InputType { Key, Button, Cursor, Scroll, Drop, Close, Iconify, Restore };

struct InputEvent {
    InputType type = InputType::Key;
    int code = 0;       // Key: GLFW key code; Button: GLFW mouse button
    bool down = false;  // Key/Button: pressed (true) or released
    double x = 0, y = 0; // Cursor position, or Scroll offsets
    std::vector<std::string> paths; // Drop
};

struct ScriptedEvent {
    double time = 0;
    InputEvent event;
};

// GLFW key code of a script key name (case-insensitive; ESC and CTRL/SHIFT/ALT are accepted as
// the left keys), or -1.
int keyFromName(std::string_view name);

// Parses a scripted-input text; errors (Usage) name `fileName`, the line and the problem. A
// `tap` becomes a press and a release at the same time.
PlayResult<std::vector<ScriptedEvent>> parseInputScript(std::string_view text, const std::string& fileName);
PlayResult<std::vector<ScriptedEvent>> readInputScript(const std::string& file);

// What is held right now.
struct InputState {
    std::array<bool, 512> keys{};
    std::array<bool, 8> buttons{};
    double cursorX = 0, cursorY = 0;
    bool key(int code) const { return code >= 0 && size_t(code) < keys.size() && keys[size_t(code)]; }
    bool button(int b) const { return b >= 0 && size_t(b) < buttons.size() && buttons[size_t(b)]; }
    bool ctrl() const;
};

enum class ActionType {
    Quit,            // Esc, or the window was closed
    ToggleRecording, // F9
    AddKey,          // K
    Screenshot,      // F12
    ToggleOrbit,     // O
    TogglePlay,      // Space: play / pause the animation (anim.play)
    Speed,           // wheel: amount = notches (log steps)
    Zoom,            // Ctrl/right button + wheel: amount = notches (> 0 narrows the view)
    Open,            // a dropped file: path
    Minimised,       // amount = 1 iconified, 0 restored
};

struct Action {
    ActionType type = ActionType::Quit;
    double amount = 0;
    std::string path;
};

class InputMapper {
public:
    // Updates the held state and returns the actions `event` triggers. With `uiWantsInput` (the
    // ImGui overlay has focus) keys and the wheel trigger nothing; close, drops and iconify do.
    std::vector<Action> apply(const InputEvent& event, bool uiWantsInput = false);
    const InputState& state() const { return mState; }

private:
    InputState mState;
};

} // namespace pnb::player
