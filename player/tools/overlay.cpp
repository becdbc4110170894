#include "overlay.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

namespace pnb::player {

Overlay::Overlay(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini next to the user's files
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
}

Overlay::~Overlay() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

bool Overlay::wantsInput() const {
    return ImGui::GetIO().WantCaptureMouse || ImGui::GetIO().WantCaptureKeyboard;
}

namespace {

// Play/pause, the time slider and the clip choice (anim.*).
bool drawPlayback(const Renderer& renderer, const SceneAnimation& a, RenderSettings& settings) {
    bool changed = false;
    const std::optional<uint32_t> clip = resolveClip(a, settings.animClip);
    const float now = float(renderer.lastFrame().animationTime);
    if (ImGui::Button(settings.animPlay ? "pause" : "play")) {
        settings.animTime = now; // resume from (or hold) the pose shown
        settings.animPlay = !settings.animPlay;
        changed = true;
    }
    ImGui::SameLine();
    const float length = clip ? float(a.clipDurations[*clip]) : 0.0f;
    float t = now;
    if (ImGui::SliderFloat("time", &t, 0.0f, std::max(length, 1e-3f), "%.3f s")) {
        settings.animTime = t;
        settings.animPlay = false; // scrubbing holds the pose
        changed = true;
    }
    std::vector<std::string> names = {"none"};
    int current = 0;
    for (size_t i = 0; i < a.clipNames.size(); ++i) {
        names.push_back(std::to_string(i) + (a.clipNames[i].empty() ? "" : ": " + a.clipNames[i]));
        if (clip && *clip == i) current = int(i + 1);
    }
    std::vector<const char*> labels;
    for (const std::string& n : names) labels.push_back(n.c_str());
    if (ImGui::Combo("clip", &current, labels.data(), int(labels.size()))) {
        settings.animClip = current == 0 ? "none" : std::to_string(current - 1);
        settings.animTime = 0;
        changed = true;
    }
    return changed;
}

} // namespace

bool Overlay::draw(const Renderer& renderer, const FrameGpuTimes* times, RenderSettings& settings,
                   const std::vector<std::string>& status, const SceneAnimation* animation) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    bool changed = false;
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::Begin("pnb-play", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    for (const std::string& line : status) ImGui::TextUnformatted(line.c_str());
    if (!status.empty()) ImGui::Separator();
    if (const std::string& note = renderer.debugViewNote(); !note.empty()) {
        ImGui::TextColored(ImVec4(1, 0.75f, 0.3f, 1), "%s", note.c_str());
        ImGui::Separator();
    }
    if (animation) {
        changed |= drawPlayback(renderer, *animation, settings);
        ImGui::Separator();
    }
    const FrameStats& s = renderer.lastFrame();
    ImGui::Text("CPU %.2f ms   draws %u   triangles %llu", s.cpuMs, s.drawCalls,
                static_cast<unsigned long long>(s.triangles));
    ImGui::Text("items %u visible, %u culled; deferred layers drawn %u", s.visibleItems,
                s.culledItems, s.deferredLayersDrawn);
    ImGui::Text("shadow triangles %llu; LOD switches %u", static_cast<unsigned long long>(s.shadowTriangles),
                s.lodSwitches);
    if (times) {
        ImGui::Text("GPU %.2f ms (frame %llu)", times->totalMs, static_cast<unsigned long long>(times->frame));
        for (const PassTime& p : times->passes) ImGui::BulletText("%-9s %.3f ms", p.pass.c_str(), p.ms);
    }
    TargetMemory m = renderer.targetMemory();
    ImGui::Text("targets %.1f MiB (G-buffer %.1f)", double(m.total()) / 1048576.0,
                double(m.gbufferBytes) / 1048576.0);
    ImGui::Separator();
    for (const SettingInfo& info : settingInfos()) {
        std::string key(info.key), value = settingValue(settings, info.key);
        if (info.type == "bool") {
            bool b = value == "true";
            if (ImGui::Checkbox(key.c_str(), &b)) changed |= bool(applySetting(settings, key, b ? "1" : "0"));
        } else if (info.type.rfind("float", 0) == 0) {
            float f = std::stof(value);
            if (ImGui::DragFloat(key.c_str(), &f, 0.01f * std::max(std::abs(f), 0.1f)))
                changed |= bool(applySetting(settings, key, std::to_string(f)));
        } else if (info.type.rfind("int", 0) == 0) {
            int i = std::stoi(value);
            if (ImGui::InputInt(key.c_str(), &i))
                changed |= bool(applySetting(settings, key, std::to_string(i))); // range checked there
        } else if (auto choices = settingChoices(key); !choices.empty()) {
            std::vector<std::string> storage(choices.begin(), choices.end());
            std::vector<const char*> names;
            int current = 0;
            for (size_t i = 0; i < storage.size(); ++i) {
                names.push_back(storage[i].c_str());
                if (storage[i] == value) current = int(i);
            }
            if (ImGui::Combo(key.c_str(), &current, names.data(), int(names.size())))
                changed |= bool(applySetting(settings, key, names[size_t(current)]));
        }
        const std::string why = settingNote(info.key, settings);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("%s%s%s", std::string(info.description).c_str(),
                              why.empty() ? "" : "\nno effect now: ", why.c_str());
        if (!why.empty()) { // greyed out: changing it changes nothing as the others stand
            ImGui::SameLine();
            ImGui::TextDisabled("(no effect)");
        }
    }
    ImGui::TextDisabled("WASD/QE move, right-drag look, O orbit, wheel speed, Ctrl+wheel zoom");
    ImGui::TextDisabled("Space play/pause the animation");
    ImGui::TextDisabled("F9 record path, K add key, F12 screenshot, Esc quit, drop a file to open");
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    return changed;
}

} // namespace pnb::player
