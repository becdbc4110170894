// The pnb-play window's input layer without a window: events -> actions, the scripted-input
// format, the fly camera's wheel steps, path recording and the keyframe JSON it saves.
#include <gtest/gtest.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "fly_camera.h"
#include "input_actions.h"
#include "path_recorder.h"
#include "pnb_player/path_json.h"

using namespace pnb::player;

namespace {

InputEvent key(int code, bool down) { return {InputType::Key, code, down, 0, 0, {}}; }
InputEvent scroll(double dy) { return {InputType::Scroll, 0, false, 0, dy, {}}; }

std::vector<ActionType> types(const std::vector<Action>& actions) {
    std::vector<ActionType> t;
    for (const Action& a : actions) t.push_back(a.type);
    return t;
}

pnb::Aabb box(float size) {
    pnb::Aabb b;
    b.min = {0, 0, 0};
    b.max = {size, size, size};
    return b;
}

std::string tempFile(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("pnb_input_test_" + std::to_string(getpid()) + "_" + name))
        .string();
}

} // namespace

TEST(InputMapper, KeysTriggerActionsOnThePressEdgeOnly) {
    InputMapper m;
    EXPECT_EQ(types(m.apply(key(GLFW_KEY_ESCAPE, true))), std::vector{ActionType::Quit});
    EXPECT_TRUE(m.apply(key(GLFW_KEY_ESCAPE, true)).empty()); // still held: no second quit
    EXPECT_TRUE(m.apply(key(GLFW_KEY_ESCAPE, false)).empty());
    EXPECT_EQ(types(m.apply(key(GLFW_KEY_F9, true))), std::vector{ActionType::ToggleRecording});
    EXPECT_EQ(types(m.apply(key(GLFW_KEY_K, true))), std::vector{ActionType::AddKey});
    EXPECT_EQ(types(m.apply(key(GLFW_KEY_F12, true))), std::vector{ActionType::Screenshot});
    EXPECT_EQ(types(m.apply(key(GLFW_KEY_O, true))), std::vector{ActionType::ToggleOrbit});
    EXPECT_EQ(types(m.apply(key(GLFW_KEY_SPACE, true))), std::vector{ActionType::TogglePlay});
    EXPECT_TRUE(m.apply(key(GLFW_KEY_W, true)).empty());
    EXPECT_TRUE(m.state().key(GLFW_KEY_W));
    m.apply(key(GLFW_KEY_W, false));
    EXPECT_FALSE(m.state().key(GLFW_KEY_W));
    EXPECT_TRUE(m.apply(key(-1, true)).empty()); // GLFW_KEY_UNKNOWN
}

TEST(InputMapper, WheelIsSpeedOrWithCtrlOrRightButtonZoom) {
    InputMapper m;
    auto a = m.apply(scroll(2));
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(a[0].type, ActionType::Speed);
    EXPECT_EQ(a[0].amount, 2);
    m.apply(key(GLFW_KEY_RIGHT_CONTROL, true));
    a = m.apply(scroll(-1));
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(a[0].type, ActionType::Zoom);
    EXPECT_EQ(a[0].amount, -1);
    m.apply(key(GLFW_KEY_RIGHT_CONTROL, false));
    m.apply({InputType::Button, GLFW_MOUSE_BUTTON_RIGHT, true, 0, 0, {}});
    EXPECT_EQ(types(m.apply(scroll(1))), std::vector{ActionType::Zoom});
    EXPECT_TRUE(m.apply(scroll(0)).empty()); // horizontal-only scrolling
}

TEST(InputMapper, UiFocusSuppressesKeysButNotCloseOrDrops) {
    InputMapper m;
    EXPECT_TRUE(m.apply(key(GLFW_KEY_ESCAPE, true), true).empty());
    EXPECT_TRUE(m.apply(scroll(1), true).empty());
    EXPECT_EQ(types(m.apply({InputType::Close, 0, false, 0, 0, {}}, true)), std::vector{ActionType::Quit});
    auto drops = m.apply({InputType::Drop, 0, false, 0, 0, {"a.pnb", "b.obj"}}, true);
    ASSERT_EQ(drops.size(), 2u);
    EXPECT_EQ(drops[0].type, ActionType::Open);
    EXPECT_EQ(drops[1].path, "b.obj");
    auto icon = m.apply({InputType::Iconify, 0, false, 0, 0, {}});
    ASSERT_EQ(icon.size(), 1u);
    EXPECT_EQ(icon[0].type, ActionType::Minimised);
    EXPECT_EQ(icon[0].amount, 1);
    EXPECT_EQ(m.apply({InputType::Restore, 0, false, 0, 0, {}})[0].amount, 0);
}

TEST(InputScript, ParsesEveryEventKind) {
    auto s = parseInputScript("# a comment\n"
                              "0 key f9 tap\n"
                              "0.5 key W down   # trailing comment\n"
                              "\n"
                              "1 key w up\n"
                              "1 button right down\n"
                              "1.25 cursor 10 20.5\n"
                              "1.5 scroll 0 -2\n"
                              "2 drop /tmp/a dir/scene.pnb\n"
                              "3 iconify\n3 restore\n4 close\n",
                              "t.txt");
    ASSERT_TRUE(s) << s.error().message;
    ASSERT_EQ(s->size(), 11u);
    EXPECT_EQ((*s)[0].event.code, GLFW_KEY_F9);
    EXPECT_TRUE((*s)[0].event.down);
    EXPECT_FALSE((*s)[1].event.down); // tap = press + release at the same time
    EXPECT_EQ((*s)[1].time, 0);
    EXPECT_EQ((*s)[2].event.code, GLFW_KEY_W);
    EXPECT_EQ((*s)[2].time, 0.5);
    EXPECT_EQ((*s)[4].event.code, GLFW_MOUSE_BUTTON_RIGHT);
    EXPECT_EQ((*s)[5].event.y, 20.5);
    EXPECT_EQ((*s)[6].event.y, -2);
    ASSERT_EQ((*s)[7].event.paths.size(), 1u);
    EXPECT_EQ((*s)[7].event.paths[0], "/tmp/a dir/scene.pnb");
    EXPECT_EQ((*s)[8].event.type, InputType::Iconify);
    EXPECT_EQ((*s)[10].event.type, InputType::Close);
    EXPECT_EQ(keyFromName("esc"), GLFW_KEY_ESCAPE);
    EXPECT_EQ(keyFromName("F12"), GLFW_KEY_F12);
    EXPECT_EQ(keyFromName("F13"), -1);
    EXPECT_EQ(keyFromName("F01"), -1);
}

TEST(InputScript, ErrorsNameTheLine) {
    auto expectError = [](const char* text, const char* what) {
        auto s = parseInputScript(text, "s.txt");
        ASSERT_FALSE(s) << text;
        EXPECT_NE(s.error().message.find(what), std::string::npos) << s.error().message;
    };
    expectError("0 key W down\n1 key NOPE down\n", "s.txt:2: unknown key 'NOPE'");
    expectError("1 close\n0.5 close\n", "s.txt:2: time 0.5 is before");
    expectError("x close\n", "s.txt:1: time 'x'");
    expectError("0 jump\n", "unknown event 'jump'");
    expectError("0 key W\n", "key NAME down|up|tap");
    expectError("0 scroll 1 x\n", "two numbers");
    expectError("0 drop\n", "'drop' expects a path");
    expectError("0 close now\n", "'close' expects");
}

TEST(FlyCamera, WheelStepsSpeedLogarithmicallyWithinClamps) {
    CameraState start;
    FlyCamera fly(start, box(10));
    double base = fly.speed();
    EXPECT_NEAR(base, std::sqrt(300.0) * 0.15, 1e-9);
    fly.scaleSpeed(2);
    EXPECT_NEAR(fly.speed(), base * 1.25 * 1.25, 1e-9);
    fly.scaleSpeed(-2);
    EXPECT_NEAR(fly.speed(), base, 1e-9);
    fly.scaleSpeed(1000);
    EXPECT_NEAR(fly.speed(), base * FlyCamera::kMaxSpeedFactor, 1e-6);
    fly.scaleSpeed(-10000);
    EXPECT_NEAR(fly.speed(), base * FlyCamera::kMinSpeedFactor, 1e-9);
}

TEST(FlyCamera, ZoomChangesFieldOfViewWithinClamps) {
    CameraState start;
    start.yfovRadians = float(glm::radians(50.0));
    FlyCamera fly(start, box(1));
    fly.zoom(1);
    EXPECT_NEAR(fly.fovDegrees(), 45.0, 1e-4);
    fly.zoom(100);
    EXPECT_NEAR(fly.fovDegrees(), FlyCamera::kMinFovDegrees, 1e-4);
    fly.zoom(-100);
    EXPECT_NEAR(fly.fovDegrees(), FlyCamera::kMaxFovDegrees, 1e-4);
    EXPECT_NEAR(fly.camera().yfovRadians, glm::radians(120.0), 1e-6);
}

TEST(FlyCamera, HeldKeysMoveAtTheWheelSpeed) {
    CameraState start; // looks down -Z
    FlyCamera fly(start, box(10));
    fly.scaleSpeed(3);
    InputMapper m;
    m.apply(key(GLFW_KEY_W, true));
    fly.update(m.state(), 0.5, false);
    EXPECT_NEAR(fly.camera().position.z, -fly.speed() * 0.5, 1e-9);
    EXPECT_NEAR(fly.camera().position.x, 0, 1e-9);
    fly.update(m.state(), 0.5, true); // the overlay has the keyboard
    EXPECT_NEAR(fly.camera().position.z, -fly.speed() * 0.5, 1e-9);
    m.apply(key(GLFW_KEY_W, false));
    m.apply(key(GLFW_KEY_E, true));
    fly.update(m.state(), 1.0, false);
    EXPECT_NEAR(fly.camera().position.y, fly.speed(), 1e-9);
}

TEST(PathRecorder, KeysAtStartPeriodOnDemandAndStop) {
    PathRecorder rec(0.5);
    CameraState cam;
    EXPECT_FALSE(rec.addKey(cam)); // not recording
    rec.start(cam);
    EXPECT_EQ(rec.keyCount(), 1u);
    EXPECT_FALSE(rec.addKey(cam)); // same time as the first key
    int periodic = 0;
    for (int i = 0; i < 20; ++i) { // 1 s at 1/20 s
        cam.position.x += 0.1;
        periodic += rec.advance(0.05, cam);
    }
    EXPECT_EQ(periodic, 2); // at 0.5 s and 1.0 s
    rec.advance(0.05, cam);
    cam.position.x += 1;
    EXPECT_TRUE(rec.addKey(cam));
    rec.advance(0.2, cam);
    auto path = rec.stop(cam, "walk");
    ASSERT_TRUE(path);
    EXPECT_FALSE(rec.recording());
    EXPECT_EQ(path->name, "walk");
    ASSERT_EQ(path->path.keys.size(), 5u);
    const float times[] = {0, 0.5f, 1.0f, 1.05f, 1.25f};
    for (size_t i = 0; i < 5; ++i) EXPECT_NEAR(path->path.keys[i].timeSeconds, times[i], 1e-5) << i;
    EXPECT_NEAR(path->path.keys[1].position.x, 1.0, 1e-5);
    EXPECT_NEAR(path->path.keys[4].position.x, 3.0, 1e-5);
}

TEST(PathRecorder, ASingleKeyIsNotAPath) {
    PathRecorder rec;
    CameraState cam;
    rec.start(cam);
    EXPECT_FALSE(rec.stop(cam, "x"));
    EXPECT_FALSE(rec.stop(cam, "x")); // not recording any more
}

TEST(PathRecorder, FreshFileNameNeverReturnsAnExistingFile) {
    std::string want = tempFile("fresh.json");
    std::filesystem::remove(want);
    EXPECT_EQ(freshFileName(want), want);
    std::ofstream(want) << "{}";
    std::string second = freshFileName(want);
    EXPECT_EQ(second, tempFile("fresh-2.json"));
    std::ofstream(second) << "{}";
    EXPECT_EQ(freshFileName(want), tempFile("fresh-3.json"));
    std::filesystem::remove(want);
    std::filesystem::remove(second);
}

TEST(PathJson, WriteThenReadKeepsEveryKey) {
    PathRecorder rec;
    CameraState cam;
    cam.position = {1.5, -2.25, 1e4};
    cam.rotation = glm::normalize(glm::dquat(0.9, 0.1, -0.3, 0.2));
    cam.yfovRadians = float(glm::radians(62.5));
    rec.start(cam);
    rec.advance(1.0 / 3.0, cam);
    cam.position.y += 1;
    auto path = rec.stop(cam, "rt");
    ASSERT_TRUE(path);
    std::string file = tempFile("rt.json");
    ASSERT_TRUE(writePathJson(file, *path));
    auto back = readPathJson(file);
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back->name, "rt");
    EXPECT_EQ(back->path.interpolation, pnb::Interpolation::CatmullRom);
    EXPECT_FALSE(back->path.loop);
    ASSERT_EQ(back->path.keys.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        const pnb::CameraKey &a = path->path.keys[i], &b = back->path.keys[i];
        EXPECT_EQ(a.timeSeconds, b.timeSeconds);
        EXPECT_EQ(a.position.x, b.position.x);
        EXPECT_EQ(a.position.y, b.position.y);
        EXPECT_EQ(a.position.z, b.position.z);
        EXPECT_NEAR(a.rotation.x, b.rotation.x, 1e-7);
        EXPECT_NEAR(a.rotation.w, b.rotation.w, 1e-7);
        EXPECT_NEAR(a.yfovRadians, b.yfovRadians, 1e-6);
    }
    std::filesystem::remove(file);
}

TEST(PathJson, ReadsTargetsAndRejectsWhatTheConverterRejects) {
    std::string file = tempFile("p.json");
    auto read = [&](const std::string& text) {
        std::ofstream(file) << text;
        return readPathJson(file);
    };
    auto p = read(R"({"name": "t", "interpolation": "linear", "loop": true, "keys": [
        {"time": 0, "position": [0, 0, 5], "target": [0, 0, 0]},
        {"time": 2, "position": [5, 0, 0], "target": [0, 0, 0], "yfov_degrees": 30}]})");
    ASSERT_TRUE(p) << p.error().message;
    EXPECT_EQ(p->path.interpolation, pnb::Interpolation::Linear);
    EXPECT_TRUE(p->path.loop);
    const pnb::CameraKey& k = p->path.keys[1];
    glm::dquat q(k.rotation.w, k.rotation.x, k.rotation.y, k.rotation.z);
    glm::dvec3 forward = q * glm::dvec3(0, 0, -1);
    EXPECT_NEAR(forward.x, -1, 1e-6); // looks from +X at the origin
    EXPECT_NEAR(k.yfovRadians, glm::radians(30.0), 1e-6);
    EXPECT_NEAR(p->path.keys[0].yfovRadians, glm::radians(45.8), 1e-5);
    auto expectError = [&](const std::string& text, const char* what) {
        auto r = read(text);
        ASSERT_FALSE(r) << text;
        EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().message;
    };
    expectError("[1]", "not a JSON object");
    expectError(R"({"keys": [{"time": 0, "position": [0,0,0], "rotation": [0,0,0,1]}]})", "at least two");
    expectError(R"({"keys": [{"time": 1, "position": [0,0,0], "rotation": [0,0,0,1]},
                             {"time": 1, "position": [0,0,0], "rotation": [0,0,0,1]}]})",
                "keys[1].time does not increase");
    expectError(R"({"keys": [{"time": 0, "position": [0,0], "rotation": [0,0,0,1]},
                             {"time": 1, "position": [0,0,0], "rotation": [0,0,0,1]}]})",
                "keys[0].position");
    expectError(R"({"keys": [{"time": 0, "position": [0,0,0]},
                             {"time": 1, "position": [0,0,0], "rotation": [0,0,0,1]}]})",
                "needs a \"target\" or a \"rotation\"");
    expectError(R"({"interpolation": "cubic", "keys": []})", "interpolation 'cubic'");
    std::filesystem::remove(file);
    EXPECT_FALSE(readPathJson(file));
}
