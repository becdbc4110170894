// document_impl.h — the inside of pnb::editor::Document, shared by document.cpp (open, edits,
// undo/redo), program_plan.cpp (which programs the edited materials need), texture_import.cpp
// and document_save.cpp. Not a public header.
//
// Model: the opened file is the *baseline* (its container stays mapped; scene blobs point into
// it). An edit produces a new State: the materials, plus what the file lacks and the state needs
// (programs and their stage sources, appended after the file's; imported textures, appended
// after the file's). States are immutable snapshots; undo/redo swap them, and materialize()
// mirrors the current one into `scene`. Saving writes the baseline's chunks with the state's
// changes and reloads the written file as the new baseline.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "pnb/reader.h"
#include "pnb/writer.h"
#include "pnb/scene.h"
#include "pnb_converter/shader_permutations.h"
#include "pnb_editor/document.h"

namespace pnb::editor::detail {

// A texture imported from an image file, processed as the converter does. Shared between the
// states that contain it (pointer identity = the same import).
struct ImportedTexture {
    std::string name;
    TextureDesc desc; // desc.name is interned when the state is materialized
    std::vector<std::vector<std::byte>> levels; // level 0 first, all layers each
};

// A program the state needs and the file lacks: the converter's variant, and the SHDR indices
// of its stages (a file shader, or fileShaders + an index into State::addedShaders).
struct AddedProgram {
    converter::ProgramVariant variant;
    std::vector<uint32_t> shaders;
};

struct State {
    std::vector<Material> materials;         // every material; `program` already planned
    std::vector<AddedProgram> addedPrograms; // PROG fileProgramCount + i
    std::vector<std::string> addedShaders;   // SHDR fileShaderCount + i: a library stage file
    std::vector<std::shared_ptr<const ImportedTexture>> imported; // TEXR fileTextureCount + i
};

// What the opened file holds, for planning and for saving.
struct Baseline {
    size_t strings = 0, shaders = 0, programs = 0, textures = 0, mips = 0;
    std::vector<Material> materials;            // as in the file
    // Names of the file's materials and textures, copied: comparing with the file on disk must
    // not read them from the mapping, which a program that rewrites files in place changes.
    std::vector<std::string> materialNames, textureNames;
    std::vector<std::vector<uint32_t>> meshesOf; // per material: meshes with a submesh drawing it
    std::vector<bool> vertexColor;              // per material: the HAS_VERTEX_COLOR feature
    // Scene-level program variants (deferred lighting, shadow, tonemap) the file's own materials
    // call for: the editor adds one only when an edit creates the need (see program_plan.cpp).
    std::vector<converter::ProgramVariant> sceneLevelBefore;
};

// A library stage file resolved once per document; `text` backs the SHDR blob.
struct ResolvedStage {
    ShaderStage stage = ShaderStage::Vertex;
    std::string text;
};

// Two materials that encode to the same bytes, ignoring `program`.
bool sameExceptProgram(Material a, Material b);

// Result of planning a state's programs (program_plan.cpp).
struct ProgramPlan {
    std::vector<uint32_t> materialProgram; // per material
    std::vector<AddedProgram> addedPrograms;
    std::vector<std::string> addedShaders;
};

} // namespace pnb::editor::detail

namespace pnb::editor {

struct Document::Impl {
    std::string path;
    FileStamp stamp;                 // of the file `container` maps
    FileLock::Options lockOptions;   // for every lock this document takes
    std::optional<FileLock> heldLock; // OpenOptions::holdLock, until a save in place
    std::optional<Container> container;
    Scene scene; // materialized current state
    detail::Baseline base;

    // Strings the state needs beyond the file's: appended to scene.strings (never removed; a
    // save writes only those the state uses).
    std::deque<std::string> pool;
    std::unordered_map<std::string, StringRef> stringIndex;
    std::map<std::string, detail::ResolvedStage> stages; // library stage file -> source
    std::map<std::string, bool> validated;               // program variant key -> glslang ok

    detail::State current;
    std::vector<detail::State> undoStack, redoStack;
    // Content of the file on disk (materials + imports), for dirty().
    std::vector<Material> savedMaterials;
    std::vector<std::shared_ptr<const detail::ImportedTexture>> savedImports;
    bool isDirty = false;
    bool lastWasEdit = false; // the previous operation was an edit (mergeWithPrevious allowed)

    // [SECTION] document.cpp
    Status load(const std::string& file);       // opens file as the baseline (state reset)
    StringRef intern(std::string_view s);
    void materialize();                         // current -> scene
    void updateDirty();
    std::string materialLabel(uint32_t index) const; // "'name'" or "#index"
    std::string_view textureName(uint32_t index, const detail::State& state) const;
    // "0 'checker', 1 'bricks', or none": the valid values of a texture slot.
    std::string textureList(size_t count, const detail::State& state) const;
    Status applyEdits(const std::vector<FieldEdit>& edits, bool merge);
    // Builds the next state from edited materials (and imports): checks texture references and
    // vertex streams, plans programs. On error nothing changes.
    Result<detail::State> makeState(std::vector<Material> materials,
                                    std::vector<std::shared_ptr<const detail::ImportedTexture>>
                                        imported);
    void pushState(detail::State next, bool merge);

    // [SECTION] program_plan.cpp
    Status checkStreams(const std::vector<Material>& materials) const;
    Result<detail::ProgramPlan> planPrograms(const std::vector<Material>& materials);
    // The scene-level variants (not any material's surface program) planShaders chooses.
    std::vector<converter::ProgramVariant> sceneLevelVariants(
        const std::vector<Material>& materials) const;
    std::vector<converter::MaterialFeatures> featuresOf(const std::vector<Material>& materials) const;
    converter::SceneShaderNeeds sceneNeeds(const std::vector<Material>& materials) const;
    Result<const detail::ResolvedStage*> resolveStage(const std::string& file, ShaderStage stage);

    // [SECTION] document_disk.cpp
    // The file at `path` now against the baseline and the current state; with `plan`, this
    // document's edits re-expressed against that file (material indices, texture indices: the
    // file's, or its texture count + k for imported texture k).
    struct DiskComparison {
        Document::DiskChange change;
        std::vector<FieldEdit> plan;
        bool unmergeable = false; // an edit's material or texture is not in their file
    };
    Result<DiskComparison> compareWithDisk() const;
    Status reload(Document::Reload mode);
    // Ok while the file at `path` is still the one read; else ChangedOnDisk naming the change.
    Status unchangedOnDisk() const;
    // Sets the save's guard against other writers into `options`: the lock, and for a save in
    // place the compare-before-rename (checked once now, and again under the lock).
    Status guardSave(const std::string& target, WriteOptions& options);

    // [SECTION] document_save.cpp
    Result<SaveStats> save(const std::string& target);
    // After a save: the written file becomes the baseline; undo/redo states are re-expressed
    // against it (imports it now holds become file textures, programs are re-planned).
    Status rebase(const std::string& file);
};

} // namespace pnb::editor
