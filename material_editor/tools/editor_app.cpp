#include "editor_app.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pnb/material_fields.h"

namespace pnb::editor {

namespace {

std::vector<std::string> splitChoices(const char* choices) {
    std::vector<std::string> out;
    std::string s = choices ? choices : "";
    for (size_t p = 0; p <= s.size();) {
        size_t bar = s.find('|', p);
        if (bar == std::string::npos) bar = s.size();
        out.push_back(s.substr(p, bar - p));
        p = bar + 1;
    }
    return out;
}

std::string formatFloats(const float* v, int n) {
    std::string s;
    char buf[32];
    for (int i = 0; i < n; ++i) {
        std::snprintf(buf, sizeof buf, "%g", double(v[i]));
        s += (i ? "," : "") + std::string(buf);
    }
    return s;
}

bool usesTextures(const Material& m) {
    return std::any_of(m.textures.begin(), m.textures.end(),
                       [](const TextureSlot& t) { return t.texture != kNone; });
}

} // namespace

EditorApp::EditorApp(std::unique_ptr<Document> document, player::GlContext& context)
    : mDocument(std::move(document)), mContext(context) {}

EditorApp::~EditorApp() = default;

player::PlayResult<player::Done> EditorApp::init() {
    auto gpu = player::uploadScene(mDocument->scene());
    if (!gpu) return gpu.error();
    mGpu = std::move(*gpu);
    auto renderer = player::Renderer::create(*mGpu, player::settingsForCurrentDriver());
    if (!renderer) return renderer.error();
    mRenderer = std::move(*renderer);
    const Aabb& b = mGpu->bounds;
    glm::dvec3 lo(b.min.x, b.min.y, b.min.z), hi(b.max.x, b.max.y, b.max.z);
    if (b.empty()) lo = hi = glm::dvec3(0.0);
    mCenter = (lo + hi) * 0.5;
    mDistance = std::max(glm::length(hi - lo) * 0.9, 1.0);
    if (mDocument->materialCount() > 0) mSelection.insert(0);
    return player::Done{};
}

std::string EditorApp::windowTitle() const {
    return (mDocument->dirty() ? "* " : "") + mDocument->path() + " — pnb-edit";
}

void EditorApp::status(std::string message) { mStatus = std::move(message); }

void EditorApp::syncGpu() {
    mPreviewStale = true;
    if (auto r = player::updateMaterials(*mGpu, mDocument->scene()); !r)
        status("viewport: " + r.error().message);
}

Status EditorApp::setField(uint32_t material, const std::string& field, const std::string& value,
                           bool merge) {
    Status s = mDocument->setField(material, field, value, merge);
    if (!isOk(s)) {
        status(s.message);
        return s;
    }
    if (std::string why = mDocument->noEffectReason(material, field); !why.empty())
        status("note: " + field + " has no effect here: " + why);
    syncGpu();
    return s;
}

Status EditorApp::applyToSelection(const std::string& field, const std::string& value) {
    std::vector<Document::FieldEdit> edits;
    for (uint32_t m : mSelection) edits.push_back({m, field, value});
    Status s = mDocument->apply(edits);
    if (!isOk(s)) {
        status(s.message);
        return s;
    }
    for (uint32_t m : mSelection)
        if (std::string why = mDocument->noEffectReason(m, field); !why.empty()) {
            status("note: " + field + " has no effect on material " + std::to_string(m) + ": " +
                   why);
            break;
        }
    syncGpu();
    return s;
}

void EditorApp::select(uint32_t material, bool additive) {
    mPreviewStale = true;
    if (!additive) mSelection.clear();
    if (additive && mSelection.count(material)) mSelection.erase(material);
    else mSelection.insert(material);
}

void EditorApp::undo() {
    if (!mDocument->canUndo()) return;
    mDocument->undo();
    syncGpu();
}

void EditorApp::redo() {
    if (!mDocument->canRedo()) return;
    mDocument->redo();
    syncGpu();
}

Result<SaveStats> EditorApp::save(const std::string& path) {
    auto r = mDocument->save(path);
    if (!r && r.error().code == FormatError::ChangedOnDisk) {
        // Another program saved the file since this window read it: nothing was written; ask.
        status("not saved: " + mDocument->path() + " changed on disk");
        if (auto change = mDocument->compareWithDisk(); change) {
            mDiskSeen = change->now;
            mDiskChange = std::move(*change);
            mShowDiskPrompt = true;
        }
    } else if (!r) {
        status("save failed: " + r.error().message);
    } else {
        mPreview.clear(); // the document now reads the written file: the preview's views are gone
        mPreviewStale = true;
        status("saved " + mDocument->path() + " in " + std::to_string(r->seconds * 1000.0) + " ms");
    }
    return r;
}

bool EditorApp::requestQuit() {
    if (!mDocument->dirty() || mQuitConfirmed) return true;
    mShowQuitPrompt = true;
    return false;
}

void EditorApp::updateCamera() {
    ImGuiIO& io = ImGui::GetIO();
    if (ImGui::IsItemHovered()) {
        if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
            mYaw -= double(io.MouseDelta.x) * 0.005;
            mPitch = std::clamp(mPitch + double(io.MouseDelta.y) * 0.005, -1.5, 1.5);
        }
        if (io.MouseWheel != 0) mDistance *= std::pow(0.9, double(io.MouseWheel));
    }
    glm::dvec3 dir(std::cos(mPitch) * std::sin(mYaw), std::sin(mPitch), std::cos(mPitch) * std::cos(mYaw));
    mCamera.position = mCenter + dir * mDistance;
    mCamera.rotation = glm::quatLookAt(-dir, glm::dvec3(0, 1, 0));
    mCamera.yfovRadians = 0.8f;
    mCamera.znear = float(std::max(mDistance * 1e-3, 1e-4));
    mCamera.zfar = 0;
}

void EditorApp::drawMaterialList() {
    const Scene& scene = mDocument->scene();
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s", mFilter.c_str());
    if (ImGui::InputTextWithHint("filter", "name, e.g. glass*", buf, sizeof buf)) mFilter = buf;
    const char* paths[] = {"any path", "deferred", "forward"};
    const char* blends[] = {"any alpha", "opaque", "mask", "blend"};
    const char* textures[] = {"any textures", "textured", "untextured"};
    ImGui::Combo("##path", &mPathFilter, paths, 3);
    ImGui::Combo("##blend", &mBlendFilter, blends, 4);
    ImGui::Combo("##tex", &mTextureFilter, textures, 3);
    ImGui::InputInt("layer (-1 any)", &mLayerFilter);
    mLayerFilter = std::clamp(mLayerFilter, -1, 65535);
    if (ImGui::Button("select all listed")) {
        mSelection.clear();
        mSelection.insert(mVisible.begin(), mVisible.end());
        mPreviewStale = true;
    }
    ImGui::Separator();
    mVisible.clear();
    std::string pattern = mFilter.empty() ? "*" : (mFilter.find_first_of("*?") == std::string::npos ? "*" + mFilter + "*" : mFilter);
    for (uint32_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        std::string name(scene.str(m.name));
        if (!globMatch(pattern, name)) continue;
        if (mPathFilter && int(m.shadingPath) != mPathFilter - 1) continue;
        if (mBlendFilter && int(m.alphaMode) != mBlendFilter - 1) continue;
        if (mTextureFilter && usesTextures(m) != (mTextureFilter == 1)) continue;
        if (mLayerFilter >= 0 && (m.shadingPath != ShadingPath::Deferred || m.layerPriority != mLayerFilter)) continue;
        mVisible.push_back(i);
        std::snprintf(buf, sizeof buf, "%s  [%s %u%s]##%u", name.c_str(),
                      m.shadingPath == ShadingPath::Deferred ? "D" : "F", unsigned(m.layerPriority),
                      m.alphaMode == AlphaMode::Blend ? " blend" : "", i);
        if (ImGui::Selectable(buf, mSelection.count(i) > 0))
            select(i, ImGui::GetIO().KeyCtrl);
    }
}

void EditorApp::drawProperties() {
    if (mSelection.empty()) {
        ImGui::TextDisabled("select a material");
        return;
    }
    const Scene& scene = mDocument->scene();
    uint32_t first = *mSelection.begin();
    const Material& m = scene.materials[first];
    ImGui::Text("%s%s", std::string(scene.str(m.name)).c_str(),
                mSelection.size() > 1 ? " (+ selection)" : "");
    if (mPreviewStale) {
        if (auto r = mPreview.refresh(scene, first); !r) status("preview: " + r.error().message);
        mPreviewStale = false;
    }
    if (GLuint tex = mPreview.render(192)) {
        glTextureParameteri(tex, GL_TEXTURE_SRGB_DECODE_EXT, GL_SKIP_DECODE_EXT);
        ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(tex)), ImVec2(192, 192),
                     ImVec2(0, 1), ImVec2(1, 0));
    }
    bool batch = mSelection.size() > 1;
    // Every field name must show whole at the default window size (1280x800): the widgets get
    // what the widest name leaves, not ImGui's default 65 % of the panel, which clipped
    // "metallic_roughness_texture" and its neighbours.
    float labelWidth = 0;
    for (const MaterialField& f : materialFields())
        labelWidth = std::max(labelWidth, ImGui::CalcTextSize(f.name).x);
    ImGui::PushItemWidth(std::max(ImGui::GetContentRegionAvail().x - labelWidth -
                                      ImGui::GetStyle().ItemInnerSpacing.x,
                                  64.0f));
    // Where the panel clips: a widget whose label ends past it shows the label cut off.
    const float clipRight = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
    mClippedLabels.clear();
    for (const MaterialField& f : materialFields()) {
        std::string value = getMaterialField(m, f.name);
        std::string next;
        bool changed = false, dragging = false;
        ImGui::PushID(f.name);
        switch (f.type) {
        case FieldType::Float: {
            float v = std::stof(value);
            changed = ImGui::SliderFloat(f.name, &v, f.min, std::min(f.max, f.min + 100.0f));
            dragging = ImGui::IsItemActive();
            next = formatFloats(&v, 1);
            break;
        }
        case FieldType::Color3:
        case FieldType::Color4: {
            float v[4] = {0, 0, 0, 1};
            std::sscanf(value.c_str(), "%f,%f,%f,%f", &v[0], &v[1], &v[2], &v[3]);
            changed = f.type == FieldType::Color3 ? ImGui::ColorEdit3(f.name, v, ImGuiColorEditFlags_Float)
                                                  : ImGui::ColorEdit4(f.name, v, ImGuiColorEditFlags_Float);
            dragging = ImGui::IsItemActive();
            next = formatFloats(v, f.type == FieldType::Color3 ? 3 : 4);
            break;
        }
        case FieldType::Bool: {
            bool v = value == "true";
            changed = ImGui::Checkbox(f.name, &v);
            next = v ? "true" : "false";
            break;
        }
        case FieldType::Choice: {
            std::vector<std::string> choices = splitChoices(f.choices);
            int current = int(std::find(choices.begin(), choices.end(), value) - choices.begin());
            if (ImGui::BeginCombo(f.name, value.c_str())) {
                for (int c = 0; c < int(choices.size()); ++c)
                    if (ImGui::Selectable(choices[size_t(c)].c_str(), c == current)) {
                        changed = true;
                        next = choices[size_t(c)];
                    }
                ImGui::EndCombo();
            }
            break;
        }
        case FieldType::Integer: {
            int v = std::stoi(value);
            changed = ImGui::InputInt(f.name, &v);
            next = std::to_string(std::clamp(v, int(f.min), int(f.max)));
            break;
        }
        case FieldType::TextureRef: {
            if (ImGui::BeginCombo(f.name, value.c_str())) {
                if (ImGui::Selectable("none", value == "none")) {
                    changed = true;
                    next = "none";
                }
                for (uint32_t t = 0; t < scene.textures.size(); ++t) {
                    std::string label = std::to_string(t) + " " + std::string(scene.str(scene.textures[t].name));
                    if (ImGui::Selectable(label.c_str(), value == std::to_string(t))) {
                        changed = true;
                        next = std::to_string(t);
                    }
                }
                ImGui::EndCombo();
            }
            break;
        }
        }
        if (ImGui::GetItemRectMax().x > clipRight + 0.5f) mClippedLabels.push_back(f.name);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", f.help);
        ImGui::PopID();
        if (!changed || next == value) continue;
        if (batch) applyToSelection(f.name, next);
        else setField(first, f.name, next, dragging && mLastEditMergeable);
        mLastEditMergeable = dragging;
    }
    ImGui::PopItemWidth();
    if (!ImGui::IsAnyItemActive()) mLastEditMergeable = false;

    ImGui::Separator();
    ImGui::Text("batch (%zu selected)", mSelection.size());
    if (ImGui::Button("-> deferred")) applyToSelection("shading_path", "deferred");
    ImGui::SameLine();
    if (ImGui::Button("-> forward")) applyToSelection("shading_path", "forward");
    ImGui::SameLine();
    if (ImGui::Button("blend")) applyToSelection("alpha_mode", "blend");
    ImGui::SameLine();
    if (ImGui::Button("opaque")) applyToSelection("alpha_mode", "opaque");
    static int priority = 1;
    ImGui::InputInt("##priority", &priority);
    ImGui::SameLine();
    if (ImGui::Button("set layer")) applyToSelection("layer_priority", std::to_string(std::clamp(priority, 0, 65535)));

    ImGui::Separator();
    char buf[512];
    std::snprintf(buf, sizeof buf, "%s", mImportPath.c_str());
    if (ImGui::InputTextWithHint("##import", "image file to import", buf, sizeof buf)) mImportPath = buf;
    const char* slots[] = {"base_color_texture", "metallic_roughness_texture", "normal_texture",
                           "occlusion_texture", "emissive_texture"};
    ImGui::Combo("slot", &mImportSlot, slots, 5);
    if (ImGui::Button("import into slot")) {
        // Colour data (base colour, emissive) is sRGB; the others are linear.
        bool srgb = mImportSlot == 0 || mImportSlot == 4;
        auto t = mDocument->importTexture(mImportPath, srgb);
        if (!t) {
            status(t.error().message);
        } else {
            // New textures need a fresh upload; materials then refer to them.
            auto gpu = player::uploadScene(mDocument->scene());
            if (gpu) {
                mRenderer.reset();
                mGpu = std::move(*gpu);
                if (auto r = player::Renderer::create(*mGpu, player::settingsForCurrentDriver())) mRenderer = std::move(*r);
                static_cast<void>(applyToSelection(slots[mImportSlot], std::to_string(*t)));
            } else {
                status(gpu.error().message);
            }
        }
    }
}

void EditorApp::drawLayerOrder() {
    Document::LayerOrder order = mDocument->layerOrder();
    const Scene& scene = mDocument->scene();
    for (const auto& [priority, materials] : order.deferred) {
        std::string names;
        for (uint32_t m : materials) names += (names.empty() ? "" : ", ") + std::string(scene.str(scene.materials[m].name));
        ImGui::BulletText("deferred layer %u: %s", unsigned(priority), names.c_str());
    }
    std::string names;
    for (uint32_t m : order.forward) names += (names.empty() ? "" : ", ") + std::string(scene.str(scene.materials[m].name));
    if (!order.forward.empty()) ImGui::BulletText("forward: %s", names.c_str());
}

void EditorApp::drawViewport() {
    ImVec2 size = ImGui::GetContentRegionAvail();
    mViewportWidth = std::max(int(size.x), 16);
    mViewportHeight = std::max(int(size.y), 16);
    if (!mRenderer) return;
    ImGui::InvisibleButton("viewport", ImVec2(float(mViewportWidth), float(mViewportHeight)));
    updateCamera();
    if (auto r = mRenderer->render(mCamera, uint32_t(mViewportWidth), uint32_t(mViewportHeight)); !r) {
        status(r.error().message);
        return;
    }
    mRenderer->timer().completed().clear();
    GLuint tex = mRenderer->outputTexture();
    // The texture holds sRGB-encoded bytes; show them as they are.
    glTextureParameteri(tex, GL_TEXTURE_SRGB_DECODE_EXT, GL_SKIP_DECODE_EXT);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    ImVec2 p0 = ImGui::GetItemRectMin(), p1 = ImGui::GetItemRectMax();
    draw->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(tex)), p0, p1, ImVec2(0, 1), ImVec2(1, 0));
}

void EditorApp::drawMenuAndPrompts() {
    ImGuiIO& io = ImGui::GetIO();
    // imgui 1.86 (Debian 12) indexes keys by the GLFW backend's key codes.
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Z)) undo();
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Y)) redo();
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_S)) static_cast<void>(save()); // reports in the status bar
    if (ImGui::BeginMainMenuBar()) {
        if (ImGui::BeginMenu("File")) {
            if (ImGui::MenuItem("Save", "Ctrl+S")) static_cast<void>(save());
            if (ImGui::MenuItem("Save As...")) {
                mShowSaveAs = true;
                mSaveAsPath = mDocument->path();
            }
            if (ImGui::MenuItem("Reload and merge my edits")) {
                if (Status s = reloadDocument(Document::Reload::Merge); isOk(s))
                    status("reloaded " + mDocument->path() + " with your edits on top");
            }
            if (ImGui::MenuItem("Quit")) glfwSetWindowShouldClose(mContext.glfwWindow(), GLFW_TRUE);
            ImGui::EndMenu();
        }
        if (ImGui::BeginMenu("Edit")) {
            if (ImGui::MenuItem("Undo", "Ctrl+Z", false, mDocument->canUndo())) undo();
            if (ImGui::MenuItem("Redo", "Ctrl+Y", false, mDocument->canRedo())) redo();
            ImGui::EndMenu();
        }
        ImGui::TextDisabled("%s", mStatus.c_str());
        ImGui::EndMainMenuBar();
    }
    if (mShowSaveAs) ImGui::OpenPopup("Save as");
    if (ImGui::BeginPopupModal("Save as", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        char buf[1024];
        std::snprintf(buf, sizeof buf, "%s", mSaveAsPath.c_str());
        if (ImGui::InputText("path", buf, sizeof buf)) mSaveAsPath = buf;
        if (ImGui::Button("Save")) {
            static_cast<void>(save(mSaveAsPath));
            mShowSaveAs = false;
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) {
            mShowSaveAs = false;
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
    if (mShowQuitPrompt) ImGui::OpenPopup("Unsaved changes");
    if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("%s has unsaved changes.", mDocument->path().c_str());
        if (ImGui::Button("Save and quit")) {
            if (save()) mQuitConfirmed = true;
            mShowQuitPrompt = false;
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Quit without saving")) {
            mQuitConfirmed = true;
            mShowQuitPrompt = false;
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) {
            mShowQuitPrompt = false;
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
    drawDiskPrompt();
}

bool EditorApp::frame() {
    GLFWwindow* window = mContext.glfwWindow();
    if (glfwWindowShouldClose(window)) {
        if (requestQuit()) return false;
        glfwSetWindowShouldClose(window, GLFW_FALSE);
    }
    if (mQuitConfirmed) return false;
    if (std::chrono::steady_clock::now() - mLastDiskCheck > std::chrono::milliseconds(500))
        checkDisk();
    int w = 0, h = 0;
    mContext.framebufferSize(w, h);
    if (std::string title = windowTitle(); title != mTitle) {
        glfwSetWindowTitle(window, title.c_str());
        mTitle = std::move(title);
    }
    drawMenuAndPrompts();
    float top = ImGui::GetFrameHeight(), left = 300, right = 380;
    auto place = [&](float x, float y, float width, float height) {
        ImGui::SetNextWindowPos(ImVec2(x, y), ImGuiCond_Always);
        ImGui::SetNextWindowSize(ImVec2(width, height), ImGuiCond_Always);
    };
    const ImGuiWindowFlags fixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse;
    float H = float(h) - top;
    place(0, top, left, H * 0.65f);
    ImGui::Begin("Materials", nullptr, fixed);
    drawMaterialList();
    ImGui::End();
    place(0, top + H * 0.65f, left, H * 0.35f);
    ImGui::Begin("Layer order", nullptr, fixed);
    drawLayerOrder();
    ImGui::End();
    place(float(w) - right, top, right, H);
    ImGui::Begin("Properties", nullptr, fixed);
    drawProperties();
    ImGui::End();
    place(left, top, std::max(float(w) - left - right, 32.0f), H);
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::Begin("Viewport", nullptr, fixed | ImGuiWindowFlags_NoScrollbar);
    drawViewport();
    ImGui::End();
    ImGui::PopStyleVar();
    return true;
}

} // namespace pnb::editor
