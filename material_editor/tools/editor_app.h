// editor_app.h — the pnb-edit window: material list with filters, properties of the selection,
// batch operations, the layer order, and a live viewport drawn by the player's renderer (same
// passes, same shaders as pnb-play). Every widget goes through the public actions below, which
// the GUI smoke test also drives, so the test exercises the UI's code path.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "material_preview.h"
#include "pnb_editor/document.h"
#include "pnb_player/camera.h"
#include "pnb_player/gl_context.h"
#include "pnb_player/gpu_scene.h"
#include "pnb_player/renderer.h"

namespace pnb::editor {

class EditorApp {
public:
    EditorApp(std::unique_ptr<Document> document, player::GlContext& context);
    ~EditorApp();

    // Uploads the scene and creates the renderer. Errors name what failed.
    player::PlayResult<player::Done> init();

    // One frame: UI, viewport, present. Returns false when the user has confirmed quitting.
    bool frame();

    // --- actions (widgets and the smoke test) ------------------------------------------------
    Status setField(uint32_t material, const std::string& field, const std::string& value,
                    bool mergeWithPrevious = false);
    Status applyToSelection(const std::string& field, const std::string& value);
    void select(uint32_t material, bool additive = false);
    void undo();
    void redo();
    Result<SaveStats> save(const std::string& path = "");
    // Asks to quit: true if nothing is unsaved (or the user already chose), else the
    // unsaved-changes prompt opens and false is returned.
    bool requestQuit();

    // --- the file on disk (editor_disk_change.cpp) -------------------------------------------
    enum class DiskChoice { Reload, Merge, MergeMineWin, SaveAs, KeepEditing };
    // Notices another program's save of the open file (frame() calls it twice a second: one
    // open, fstat and two small reads). With no unsaved edits the window reloads the file and
    // the status line names what changed; otherwise the "Changed on disk" prompt opens.
    void checkDisk();
    bool diskPromptOpen() const { return mShowDiskPrompt; }
    // The prompt's buttons. Reload drops this window's edits; Merge brings them onto the file as
    // it is now (one undo step; refused, naming the fields, when both changed one differently);
    // MergeMineWin resolves such conflicts with this window's values; SaveAs opens the save-as
    // prompt; KeepEditing closes the prompt (a save in place then refuses and asks again). On
    // an error the prompt stays open and the status line says why.
    Status resolveDiskChange(DiskChoice choice);
    const std::string& statusLine() const { return mStatus; }

    const Document& document() const { return *mDocument; }
    std::string windowTitle() const;
    // The property labels the last frame could not show whole (the panel cut them off).
    const std::vector<std::string>& clippedLabels() const { return mClippedLabels; }

private:
    void syncGpu();          // after any material change
    void drawMaterialList();
    void drawProperties();
    void drawLayerOrder();
    void drawViewport();
    void drawMenuAndPrompts();
    void updateCamera();
    void status(std::string message);
    void drawDiskPrompt();
    // Document::reload, then the viewport's scene uploaded anew (the file may be another scene).
    Status reloadDocument(Document::Reload mode);

    std::unique_ptr<Document> mDocument;
    player::GlContext& mContext;
    std::unique_ptr<player::GpuScene> mGpu;
    std::unique_ptr<player::Renderer> mRenderer;
    MaterialPreview mPreview;
    bool mPreviewStale = true;
    std::set<uint32_t> mSelection;
    std::string mFilter, mStatus, mSaveAsPath, mImportPath;
    int mPathFilter = 0, mBlendFilter = 0, mTextureFilter = 0, mLayerFilter = -1, mImportSlot = 0;
    std::vector<uint32_t> mVisible; // materials passing the filters, in list order
    bool mQuitConfirmed = false, mShowQuitPrompt = false, mShowSaveAs = false;
    bool mLastEditMergeable = false;
    double mYaw = 0.6, mPitch = 0.35, mDistance = 10;
    glm::dvec3 mCenter{0.0};
    player::CameraState mCamera;
    int mViewportWidth = 640, mViewportHeight = 400;
    std::string mTitle; // last title given to the window
    std::vector<std::string> mClippedLabels;
    FileStamp mDiskSeen; // the last stamp on disk this window handled (reloaded or prompted)
    std::optional<Document::DiskChange> mDiskChange; // what the prompt shows
    bool mShowDiskPrompt = false;
    std::chrono::steady_clock::time_point mLastDiskCheck{};
};

} // namespace pnb::editor
