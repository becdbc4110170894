#include "input_actions.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace pnb::player {

namespace {

std::string upper(std::string_view s) {
    std::string u(s);
    for (char& c : u) c = char(std::toupper(static_cast<unsigned char>(c)));
    return u;
}

bool parseDouble(const std::string& s, double& out) {
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return !s.empty() && !*end && std::isfinite(out);
}

} // namespace

int keyFromName(std::string_view name) {
    std::string n = upper(name);
    if (n.size() == 1 && ((n[0] >= 'A' && n[0] <= 'Z') || (n[0] >= '0' && n[0] <= '9'))) return n[0];
    if (n.size() >= 2 && n.size() <= 3 && n[0] == 'F') {
        int f = std::atoi(n.c_str() + 1);
        if (f >= 1 && f <= 12 && std::to_string(f) == n.substr(1)) return GLFW_KEY_F1 + f - 1;
    }
    static const std::pair<const char*, int> named[] = {
        {"ESCAPE", GLFW_KEY_ESCAPE},          {"ESC", GLFW_KEY_ESCAPE},
        {"SPACE", GLFW_KEY_SPACE},            {"ENTER", GLFW_KEY_ENTER},
        {"TAB", GLFW_KEY_TAB},                {"LEFT_SHIFT", GLFW_KEY_LEFT_SHIFT},
        {"SHIFT", GLFW_KEY_LEFT_SHIFT},       {"RIGHT_SHIFT", GLFW_KEY_RIGHT_SHIFT},
        {"LEFT_CONTROL", GLFW_KEY_LEFT_CONTROL}, {"CTRL", GLFW_KEY_LEFT_CONTROL},
        {"RIGHT_CONTROL", GLFW_KEY_RIGHT_CONTROL}, {"LEFT_ALT", GLFW_KEY_LEFT_ALT},
        {"ALT", GLFW_KEY_LEFT_ALT},           {"UP", GLFW_KEY_UP},
        {"DOWN", GLFW_KEY_DOWN},              {"LEFT", GLFW_KEY_LEFT},
        {"RIGHT", GLFW_KEY_RIGHT}};
    for (const auto& [k, code] : named)
        if (n == k) return code;
    return -1;
}

PlayResult<std::vector<ScriptedEvent>> parseInputScript(std::string_view text, const std::string& fileName) {
    std::vector<ScriptedEvent> out;
    std::istringstream in{std::string(text)};
    std::string line;
    double previous = 0;
    for (int lineNo = 1; std::getline(in, line); ++lineNo) {
        auto fail = [&](const std::string& what) {
            return PlayError{PlayErrorKind::Usage, fileName + ":" + std::to_string(lineNo) + ": " + what};
        };
        if (size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream words(line);
        std::string timeText, kind;
        if (!(words >> timeText)) continue; // blank or comment
        double time = 0;
        if (!parseDouble(timeText, time) || time < 0) return fail("time '" + timeText + "' is not a number >= 0");
        if (time < previous) return fail("time " + timeText + " is before the previous event's");
        previous = time;
        if (!(words >> kind)) return fail("no event after the time");
        std::vector<std::string> rest;
        for (std::string w; words >> w;) rest.push_back(w);
        auto want = [&](size_t n, const char* form) -> std::optional<PlayError> {
            if (rest.size() != n) return fail("'" + kind + "' expects: " + form);
            return std::nullopt;
        };
        InputEvent e;
        if (kind == "key") {
            if (auto err = want(2, "key NAME down|up|tap")) return *err;
            e.type = InputType::Key;
            e.code = keyFromName(rest[0]);
            if (e.code < 0) return fail("unknown key '" + rest[0] + "'");
            if (rest[1] == "tap") {
                e.down = true;
                out.push_back({time, e});
                e.down = false;
            } else if (rest[1] == "down" || rest[1] == "up") {
                e.down = rest[1] == "down";
            } else {
                return fail("key state '" + rest[1] + "' is not down, up or tap");
            }
        } else if (kind == "button") {
            if (auto err = want(2, "button left|right|middle down|up")) return *err;
            e.type = InputType::Button;
            if (rest[0] == "left") e.code = GLFW_MOUSE_BUTTON_LEFT;
            else if (rest[0] == "right") e.code = GLFW_MOUSE_BUTTON_RIGHT;
            else if (rest[0] == "middle") e.code = GLFW_MOUSE_BUTTON_MIDDLE;
            else return fail("unknown button '" + rest[0] + "'");
            if (rest[1] != "down" && rest[1] != "up") return fail("button state '" + rest[1] + "' is not down or up");
            e.down = rest[1] == "down";
        } else if (kind == "cursor" || kind == "scroll") {
            if (auto err = want(2, kind == "cursor" ? "cursor X Y" : "scroll DX DY")) return *err;
            e.type = kind == "cursor" ? InputType::Cursor : InputType::Scroll;
            if (!parseDouble(rest[0], e.x) || !parseDouble(rest[1], e.y))
                return fail("'" + kind + "' expects two numbers");
        } else if (kind == "drop") {
            // The rest of the line, as written (a path may contain spaces).
            size_t at = line.find("drop");
            std::string path = line.substr(at + 4);
            path.erase(0, path.find_first_not_of(" \t"));
            path.erase(path.find_last_not_of(" \t\r") + 1);
            if (path.empty()) return fail("'drop' expects a path");
            e.type = InputType::Drop;
            e.paths.push_back(path);
        } else if (kind == "close" || kind == "iconify" || kind == "restore") {
            if (auto err = want(0, kind.c_str())) return *err;
            e.type = kind == "close" ? InputType::Close : kind == "iconify" ? InputType::Iconify : InputType::Restore;
        } else {
            return fail("unknown event '" + kind + "' (key, button, cursor, scroll, drop, close, iconify, restore)");
        }
        out.push_back({time, std::move(e)});
    }
    return out;
}

PlayResult<std::vector<ScriptedEvent>> readInputScript(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return PlayError{PlayErrorKind::Usage, "--script-input: cannot open " + file};
    std::ostringstream text;
    text << in.rdbuf();
    return parseInputScript(text.str(), file);
}

bool InputState::ctrl() const { return key(GLFW_KEY_LEFT_CONTROL) || key(GLFW_KEY_RIGHT_CONTROL); }

std::vector<Action> InputMapper::apply(const InputEvent& e, bool uiWantsInput) {
    std::vector<Action> actions;
    switch (e.type) {
    case InputType::Key: {
        if (e.code < 0 || size_t(e.code) >= mState.keys.size()) break;
        bool wasDown = mState.keys[size_t(e.code)];
        mState.keys[size_t(e.code)] = e.down;
        if (!e.down || wasDown || uiWantsInput) break; // actions on the press edge only
        switch (e.code) {
        case GLFW_KEY_ESCAPE: actions.push_back({ActionType::Quit, 0, {}}); break;
        case GLFW_KEY_F9: actions.push_back({ActionType::ToggleRecording, 0, {}}); break;
        case GLFW_KEY_K: actions.push_back({ActionType::AddKey, 0, {}}); break;
        case GLFW_KEY_F12: actions.push_back({ActionType::Screenshot, 0, {}}); break;
        case GLFW_KEY_O: actions.push_back({ActionType::ToggleOrbit, 0, {}}); break;
        case GLFW_KEY_SPACE: actions.push_back({ActionType::TogglePlay, 0, {}}); break;
        default: break;
        }
        break;
    }
    case InputType::Button:
        if (e.code >= 0 && size_t(e.code) < mState.buttons.size()) mState.buttons[size_t(e.code)] = e.down;
        break;
    case InputType::Cursor:
        mState.cursorX = e.x;
        mState.cursorY = e.y;
        break;
    case InputType::Scroll:
        if (uiWantsInput || e.y == 0) break;
        if (mState.ctrl() || mState.button(GLFW_MOUSE_BUTTON_RIGHT)) actions.push_back({ActionType::Zoom, e.y, {}});
        else actions.push_back({ActionType::Speed, e.y, {}});
        break;
    case InputType::Drop:
        for (const std::string& p : e.paths) actions.push_back({ActionType::Open, 0, p});
        break;
    case InputType::Close: actions.push_back({ActionType::Quit, 0, {}}); break;
    case InputType::Iconify: actions.push_back({ActionType::Minimised, 1, {}}); break;
    case InputType::Restore: actions.push_back({ActionType::Minimised, 0, {}}); break;
    }
    return actions;
}

} // namespace pnb::player
