// material_preview.h — the selected material on a sphere over a small floor, drawn by the
// player's renderer from a tiny scene built in memory: the document's programs (same shaders),
// the material's own textures, one sun. Rebuilt when the selection or the material changes.
#pragma once

#include <memory>
#include <vector>

#include "pnb/scene.h"
#include "pnb_player/gpu_scene.h"
#include "pnb_player/renderer.h"

namespace pnb::editor {

class MaterialPreview {
public:
    // Builds (or rebuilds) the preview of `material` of `document`. Errors name the cause.
    player::PlayResult<player::Done> show(const Scene& document, uint32_t material);
    // After an edit: updates values in place, or rebuilds if the material, its textures or its
    // program changed.
    player::PlayResult<player::Done> refresh(const Scene& document, uint32_t material);
    // Forgets the preview after the document was read anew (a save or a reload): its scene
    // views the document's strings and shaders, which that replaced. The next refresh rebuilds.
    void clear();
    // Renders at size x size when something changed since the last call; returns the sRGB
    // output texture (0 if nothing is shown).
    GLuint render(uint32_t size);

private:
    uint32_t mMaterial = kNone;
    uint32_t mRenderedSize = 0;         // 0 = the shown image is out of date
    Material mShown;                    // the document's material as last shown
    Scene mScene;                       // views into the document and into mStorage
    std::vector<std::vector<std::byte>> mStorage;
    std::vector<std::string> mStrings;
    std::unique_ptr<player::GpuScene> mGpu;
    std::unique_ptr<player::Renderer> mRenderer;
};

} // namespace pnb::editor
