// The window and the file on disk: noticing another program's save of the open file, the
// "Changed on disk" prompt (reload, merge, save as, keep editing), and re-uploading the viewport
// after a reload. The document does the comparing and merging (Document::compareWithDisk,
// Document::reload); saves in place refuse a changed file on their own (document_save.cpp).
#include "editor_app.h"

#include <imgui.h>

#include <algorithm>

namespace pnb::editor {

void EditorApp::checkDisk() {
    mLastDiskCheck = std::chrono::steady_clock::now();
    auto now = stampOf(mDocument->path());
    if (!now || *now == mDocument->stamp() || *now == mDiskSeen) return;
    mDiskSeen = *now;
    auto change = mDocument->compareWithDisk();
    if (!change) {
        status(change.error().message);
        return;
    }
    const std::string what = change->describe(mDocument->path());
    if (!mDocument->dirty() && change->readable) { // nothing of this window's to lose
        if (isOk(reloadDocument(Document::Reload::Discard))) status("reloaded: " + what);
        return;
    }
    mDiskChange = std::move(*change);
    mShowDiskPrompt = true;
    status(what);
}

Status EditorApp::reloadDocument(Document::Reload mode) {
    if (Status s = mDocument->reload(mode); !isOk(s)) {
        status(s.message);
        return s;
    }
    // The renderer draws from the GPU scene: it goes first, then both are built anew.
    mRenderer.reset();
    auto gpu = player::uploadScene(mDocument->scene());
    if (!gpu) {
        status("viewport: " + gpu.error().message);
        return makeError(FormatError::IoError, 0, "%s", gpu.error().message.c_str());
    }
    mGpu = std::move(*gpu);
    auto renderer = player::Renderer::create(*mGpu, player::settingsForCurrentDriver());
    if (!renderer) {
        status("viewport: " + renderer.error().message);
        return makeError(FormatError::IoError, 0, "%s", renderer.error().message.c_str());
    }
    mRenderer = std::move(*renderer);
    std::erase_if(mSelection, [&](uint32_t m) { return m >= mDocument->materialCount(); });
    mPreview.clear(); // it viewed the replaced scene's strings and shaders
    mPreviewStale = true;
    return {};
}

Status EditorApp::resolveDiskChange(DiskChoice choice) {
    Status s;
    const std::string& path = mDocument->path();
    switch (choice) {
    case DiskChoice::Reload:
        if (s = reloadDocument(Document::Reload::Discard); isOk(s))
            status("reloaded " + path + "; your edits were discarded");
        break;
    case DiskChoice::Merge:
    case DiskChoice::MergeMineWin:
        s = reloadDocument(choice == DiskChoice::Merge ? Document::Reload::Merge
                                                       : Document::Reload::MergeMineWin);
        if (isOk(s))
            status("merged your edits into " + path + " as it is now (unsaved; Ctrl+Z shows "
                   "their version)");
        break;
    case DiskChoice::SaveAs:
        mShowSaveAs = true;
        mSaveAsPath = path.size() > 4 && path.ends_with(".pnb")
                          ? path.substr(0, path.size() - 4) + "-mine.pnb"
                          : path + "-mine";
        break;
    case DiskChoice::KeepEditing:
        status("kept your edits; " + path + " differs on disk (a save in place will ask again)");
        break;
    }
    if (isOk(s)) {
        mShowDiskPrompt = false;
        mDiskChange.reset();
    }
    return s;
}

void EditorApp::drawDiskPrompt() {
    if (mShowDiskPrompt && mDiskChange) ImGui::OpenPopup("Changed on disk");
    if (!ImGui::BeginPopupModal("Changed on disk", nullptr, ImGuiWindowFlags_AlwaysAutoResize))
        return;
    if (!mShowDiskPrompt || !mDiskChange) {
        ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
        return;
    }
    const Document::DiskChange& c = *mDiskChange;
    auto list = [](const std::vector<std::string>& items) {
        constexpr size_t kShown = 12;
        for (size_t i = 0; i < items.size() && i < kShown; ++i) ImGui::BulletText("%s", items[i].c_str());
        if (items.size() > kShown) ImGui::BulletText("... and %zu more", items.size() - kShown);
    };
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 40);
    ImGui::TextWrapped("%s was saved by another program while you edited it.",
                       mDocument->path().c_str());
    ImGui::TextDisabled("then: %s", c.was.describe().c_str());
    ImGui::TextDisabled("now:  %s", c.now.describe().c_str());
    if (!c.readable) ImGui::TextWrapped("It cannot be merged into:");
    else ImGui::Text("Their changes (%zu):", c.theirs.size());
    list(c.theirs);
    ImGui::Text("Your unsaved edits: %u field%s.", c.mine, c.mine == 1 ? "" : "s");
    if (!c.conflicts.empty()) {
        ImGui::TextColored(ImVec4(1, 0.45f, 0.35f, 1), "Both changed (%zu):", c.conflicts.size());
        list(c.conflicts);
    }
    ImGui::PopTextWrapPos();
    ImGui::Separator();
    ImGui::BeginDisabled(!c.readable || !c.conflicts.empty());
    if (ImGui::Button("Merge my edits into it")) (void)resolveDiskChange(DiskChoice::Merge);
    ImGui::EndDisabled();
    if (!c.conflicts.empty() && c.readable) {
        ImGui::SameLine();
        if (ImGui::Button("Merge, mine win")) (void)resolveDiskChange(DiskChoice::MergeMineWin);
    }
    ImGui::SameLine();
    if (ImGui::Button(c.mine ? "Reload (discard my edits)" : "Reload"))
        (void)resolveDiskChange(DiskChoice::Reload);
    ImGui::SameLine();
    if (ImGui::Button("Save As...")) (void)resolveDiskChange(DiskChoice::SaveAs);
    ImGui::SameLine();
    if (ImGui::Button("Keep editing")) (void)resolveDiskChange(DiskChoice::KeepEditing);
    ImGui::EndPopup();
}

} // namespace pnb::editor
