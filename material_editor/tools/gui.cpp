// The interactive editor: a GLFW window, Dear ImGui, and EditorApp. With --ui-* options it runs
// a scripted session through the same actions the widgets use (the Xvfb smoke test).
#include "gui.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "editor_app.h"
#include "pnb/material_fields.h"
#include "pnb_editor/set_expression.h"
#include "pnb_player/save_capture.h"

namespace pnb::editor {

namespace {

struct GuiArgs {
    std::string scene;
    std::vector<std::string> sets; // --ui-set PATTERN.FIELD=VALUE, applied at frame 2
    // --ui-external CMD: at frame 3 another program (CMD, through the shell) changes the file;
    // at frame 4 the window checks the disk; --ui-on-change picks the prompt's button.
    std::string external, onChange;
    bool save = false; // --ui-save: save in place at frame 5 (as Ctrl+S)
    std::string saveAs, screenshot; // --ui-save-as at frame 5
    int frames = 0;                // 0 = until the window closes
    int width = 1400, height = 800; // --ui-size WxH: the window (the default is the first)
    bool checkLabels = false;      // --ui-check-labels: exit 4 if a property label is cut off
};

const std::map<std::string, EditorApp::DiskChoice> kChoices = {
    {"reload", EditorApp::DiskChoice::Reload},
    {"merge", EditorApp::DiskChoice::Merge},
    {"merge-mine", EditorApp::DiskChoice::MergeMineWin},
    {"save-as", EditorApp::DiskChoice::SaveAs},
    {"keep", EditorApp::DiskChoice::KeepEditing},
};

// The window's default framebuffer, bottom-up RGBA8.
player::CapturedImage readWindow(int w, int h) {
    player::CapturedImage img;
    img.width = uint32_t(w);
    img.height = uint32_t(h);
    img.channels = 4;
    img.u8.resize(size_t(w) * size_t(h) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, img.u8.data());
    return img;
}

} // namespace

int runGui(int argc, char** argv) {
    GuiArgs a;
    for (int i = 1; i < argc; ++i) {
        std::string s = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "pnb-edit: %s needs a value\n", s.c_str());
                std::exit(1);
            }
            return argv[++i];
        };
        if (s == "--ui-set") a.sets.push_back(value());
        else if (s == "--ui-external") a.external = value();
        else if (s == "--ui-on-change") {
            a.onChange = value();
            if (!kChoices.count(a.onChange)) {
                std::fprintf(stderr, "pnb-edit: --ui-on-change %s: expected reload, merge, "
                                     "merge-mine, save-as or keep\n", a.onChange.c_str());
                return 1;
            }
        }
        else if (s == "--ui-save") a.save = true;
        else if (s == "--ui-save-as") a.saveAs = value();
        else if (s == "--ui-screenshot") a.screenshot = value();
        else if (s == "--ui-frames") a.frames = std::atoi(value().c_str());
        else if (s == "--ui-check-labels") a.checkLabels = true;
        else if (s == "--ui-size") {
            const std::string v = value();
            if (std::sscanf(v.c_str(), "%dx%d", &a.width, &a.height) != 2 || a.width < 64 ||
                a.height < 64) {
                std::fprintf(stderr, "pnb-edit: --ui-size %s: expected WxH, each at least 64\n",
                             v.c_str());
                return 1;
            }
        }
        else if (!s.empty() && s[0] == '-') {
            std::fprintf(stderr, "pnb-edit: unknown option %s\n", s.c_str());
            return 1;
        } else a.scene = s;
    }
    if (a.scene.empty()) {
        std::fprintf(stderr, "pnb-edit: no scene given (pnb-edit SCENE.pnb)\n");
        return 1;
    }
    auto doc = Document::open(a.scene);
    if (!doc) {
        std::fprintf(stderr, "pnb-edit: %s\n", doc.error().describe().c_str());
        return 2;
    }
    player::WindowOptions wo;
    wo.width = a.width;
    wo.height = a.height;
    wo.title = "pnb-edit";
    auto context = player::createWindowContext(wo);
    if (!context) {
        std::fprintf(stderr, "pnb-edit: %s (batch options such as --list work without a display)\n",
                     context.error().message.c_str());
        return 3;
    }
    EditorApp app(std::move(*doc), **context);
    if (auto r = app.init(); !r) {
        std::fprintf(stderr, "pnb-edit: %s\n", r.error().message.c_str());
        return 3;
    }
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL((*context)->glfwWindow(), true);
    ImGui_ImplOpenGL3_Init("#version 450 core");

    int exitCode = 0;
    std::string lastStatus;
    for (int frame = 0; a.frames == 0 || frame < a.frames; ++frame) {
        (*context)->pollEvents();
        // Scripted session: the edits go through the app's actions, as a click would.
        if (frame == 2 && !a.sets.empty()) {
            for (const std::string& text : a.sets) {
                auto expr = parseSetExpression(text);
                Status st = expr.ok() ? Status{} : expr.error();
                if (isOk(st)) {
                    bool any = false;
                    for (uint32_t m = 0; m < app.document().materialCount(); ++m)
                        if (globMatch(expr->pattern, app.document().materialName(m))) {
                            app.select(m, any);
                            any = true;
                        }
                    st = any ? app.applyToSelection(expr->field, expr->value)
                             : makeError(FormatError::BadReference, 0, "no material matches '%s'", expr->pattern.c_str());
                }
                if (!isOk(st)) {
                    std::fprintf(stderr, "pnb-edit: %s\n", st.message.c_str());
                    exitCode = 1;
                }
            }
        }
        if (frame == 3 && !a.external.empty()) {
            const int rc = std::system(a.external.c_str());
            std::printf("external command exited %d\n", rc);
        }
        if (frame == 4) app.checkDisk();
        // The scripted answer to the "Changed on disk" prompt, whenever it is open.
        if (app.diskPromptOpen() && !a.onChange.empty()) {
            Status st = app.resolveDiskChange(kChoices.at(a.onChange));
            if (!isOk(st)) {
                std::fprintf(stderr, "pnb-edit: %s\n", st.message.c_str());
                exitCode = 2;
                a.onChange.clear(); // answered once; the prompt stays as a person would see it
            }
        }
        if (frame == 5 && a.save) {
            auto saved = app.save();
            if (!saved) {
                std::fprintf(stderr, "pnb-edit: %s\n", saved.error().describe().c_str());
                exitCode = 2;
            } else {
                std::printf("saved %s in %.2f ms\n", app.document().path().c_str(),
                            saved->seconds * 1000.0);
            }
        }
        if (frame == 5 && !a.saveAs.empty()) {
            auto saved = app.save(a.saveAs);
            if (!saved) {
                std::fprintf(stderr, "pnb-edit: %s\n", saved.error().describe().c_str());
                exitCode = 2;
            } else {
                std::printf("saved %s in %.2f ms\n", a.saveAs.c_str(), saved->seconds * 1000.0);
            }
        }
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        bool keepGoing = app.frame();
        if (a.frames != 0 && app.statusLine() != lastStatus) { // scripted: the status bar, logged
            lastStatus = app.statusLine();
            std::printf("status: %s\n", lastStatus.c_str());
        }
        ImGui::Render();
        int w = 0, h = 0;
        (*context)->framebufferSize(w, h);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, w, h);
        glDisable(GL_FRAMEBUFFER_SRGB);
        glClearColor(0.1f, 0.1f, 0.12f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        bool last = a.frames != 0 && frame + 1 == a.frames;
        if (last && a.checkLabels) {
            for (const std::string& l : app.clippedLabels())
                std::fprintf(stderr, "pnb-edit: property label '%s' is cut off at %dx%d\n",
                             l.c_str(), w, h);
            if (!app.clippedLabels().empty()) exitCode = 4;
            else std::printf("property labels: all %s shown whole at %dx%d\n", "fields", w, h);
        }
        if (last && !a.screenshot.empty()) {
            if (auto s = player::saveCapture(a.screenshot, readWindow(w, h)); !s) {
                std::fprintf(stderr, "pnb-edit: %s\n", s.error().message.c_str());
                exitCode = 3;
            }
        }
        (*context)->swapBuffers();
        if (!keepGoing) break;
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    return exitCode;
}

} // namespace pnb::editor
