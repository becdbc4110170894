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
#include <optional>
#include <map>
#include <string>
#include <vector>

#include "editor_app.h"
#include "pnb/material_fields.h"
#include "pnb_cli/options.h"
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

// The --ui-* options (pnb-edit's scripted window session), as a pnb_cli table. Returns the exit
// code when the run ends here (a usage error, reported), nothing when it goes on.
std::optional<int> parseGuiArgs(int argc, char** argv, GuiArgs& a) {
    using pnb::cli::flag;
    using pnb::cli::valued;
    const std::vector<pnb::cli::Option> table = {
        valued("", "--ui-set", "MATERIAL.FIELD=VALUE", "", [&a](const char* v) {
            a.sets.push_back(v);
            return true;
        }),
        valued("", "--ui-external", "CMD", "", [&a](const char* v) {
            a.external = v;
            return true;
        }),
        valued("", "--ui-on-change", "CHOICE", "", [&a](const char* v) {
            a.onChange = v;
            if (kChoices.count(a.onChange)) return pnb::cli::Verdict(true);
            return pnb::cli::Verdict::error("--ui-on-change " + a.onChange +
                                            ": expected reload, merge, merge-mine, save-as or keep");
        }),
        flag("", "--ui-save", "", [&a](const char*) { return a.save = true; }),
        valued("", "--ui-save-as", "FILE", "", [&a](const char* v) {
            a.saveAs = v;
            return true;
        }),
        valued("", "--ui-screenshot", "FILE", "", [&a](const char* v) {
            a.screenshot = v;
            return true;
        }),
        valued("", "--ui-frames", "N", "", [&a](const char* v) {
            a.frames = std::atoi(v);
            return true;
        }),
        flag("", "--ui-check-labels", "", [&a](const char*) { return a.checkLabels = true; }),
        valued("", "--ui-size", "WxH", "", [&a](const char* v) {
            if (std::sscanf(v, "%dx%d", &a.width, &a.height) != 2 || a.width < 64 || a.height < 64)
                return pnb::cli::Verdict::error("--ui-size " + std::string(v) + ": expected WxH, each at least 64");
            return pnb::cli::Verdict(true);
        }),
    };
    // The last scene named is opened; "-" (standard input) is no scene here.
    auto scene = [&a](const char* arg) {
        if (std::string(arg) == "-") return pnb::cli::Verdict::error("unknown option -");
        a.scene = arg;
        return pnb::cli::Verdict(true);
    };
    if (auto e = pnb::cli::parse(table, scene, argc, argv)) {
        using Kind = pnb::cli::ParseError::Kind;
        const std::string sentence = e->kind == Kind::UnknownOption  ? "unknown option " + e->option
                                     : e->kind == Kind::MissingValue ? e->option + " needs a value"
                                                                     : pnb::cli::describe(*e);
        std::fprintf(stderr, "pnb-edit: %s\n", sentence.c_str());
        return 1;
    }
    if (a.scene.empty()) {
        std::fprintf(stderr, "pnb-edit: no scene given (pnb-edit SCENE.pnb)\n");
        return 1;
    }
    return std::nullopt;
}

// Dear ImGui over the window, for as long as this lives.
struct ImGuiSession {
    explicit ImGuiSession(player::GlContext& context) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(context.glfwWindow(), true);
        ImGui_ImplOpenGL3_Init("#version 450 core");
    }
    ~ImGuiSession() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    ImGuiSession(const ImGuiSession&) = delete;
    ImGuiSession& operator=(const ImGuiSession&) = delete;
};

// Frame 2 of a scripted session: the --ui-set edits, through the app's actions as a click would.
void applyScriptedSets(EditorApp& app, const GuiArgs& a, int& exitCode) {
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

// Frame 5 of a scripted session: --ui-save (in place, as Ctrl+S) or --ui-save-as.
void scriptedSave(EditorApp& app, const std::string& path, int& exitCode) {
    auto saved = app.save(path); // "": in place
    if (!saved) {
        std::fprintf(stderr, "pnb-edit: %s\n", saved.error().describe().c_str());
        exitCode = 2;
    } else {
        std::printf("saved %s in %.2f ms\n", path.empty() ? app.document().path().c_str() : path.c_str(),
                    saved->seconds * 1000.0);
    }
}

// What a scripted session does at `frame`, before the frame is drawn.
void runScriptedSteps(EditorApp& app, GuiArgs& a, int frame, int& exitCode) {
    if (frame == 2 && !a.sets.empty()) applyScriptedSets(app, a, exitCode);
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
    if (frame == 5 && a.save) scriptedSave(app, "", exitCode);
    if (frame == 5 && !a.saveAs.empty()) scriptedSave(app, a.saveAs, exitCode);
}

// The last frame of a scripted session, drawn at w x h: --ui-check-labels, --ui-screenshot.
void checkLastFrame(const EditorApp& app, const GuiArgs& a, int w, int h, int& exitCode) {
    if (a.checkLabels) {
        for (const std::string& l : app.clippedLabels())
            std::fprintf(stderr, "pnb-edit: property label '%s' is cut off at %dx%d\n", l.c_str(), w, h);
        if (!app.clippedLabels().empty()) exitCode = 4;
        else std::printf("property labels: all %s shown whole at %dx%d\n", "fields", w, h);
    }
    if (!a.screenshot.empty()) {
        if (auto s = player::saveCapture(a.screenshot, readWindow(w, h)); !s) {
            std::fprintf(stderr, "pnb-edit: %s\n", s.error().message.c_str());
            exitCode = 3;
        }
    }
}

} // namespace

int runGui(int argc, char** argv) {
    GuiArgs a;
    if (auto done = parseGuiArgs(argc, argv, a)) return *done;
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
    ImGuiSession imgui(**context);

    int exitCode = 0;
    std::string lastStatus;
    for (int frame = 0; a.frames == 0 || frame < a.frames; ++frame) {
        (*context)->pollEvents();
        runScriptedSteps(app, a, frame, exitCode);
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
        if (a.frames != 0 && frame + 1 == a.frames) checkLastFrame(app, a, w, h, exitCode);
        (*context)->swapBuffers();
        if (!keepGoing) break;
    }
    return exitCode;
}

} // namespace pnb::editor
