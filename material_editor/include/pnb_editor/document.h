// pnb_editor/document.h — an opened .pnb as the material editor sees it: the decoded scene,
// its materials under edit, undo/redo, and a save that rewrites only what changed.
//
// Edits change Material values only (and may import textures). Saving:
//   - STRS is rewritten with new strings appended (existing StringRefs stay valid), or copied
//     when nothing needs a new string;
//   - every MATL chunk whose material differs from the file's is re-encoded (same compression
//     flag as before); the others are copied;
//   - programs a changed material now needs (another shading path, alpha mask, texture use) are
//     added as new SHDR/PROG chunks after the existing ones, resolved from the built-in shader
//     library exactly as the converter does (converter::planShaders on the same features, the
//     variant checked with glslang once per document); existing programs are kept, and a
//     material whose fields equal the file's keeps the file's program. Scene-level programs
//     (deferred lighting, shadow, masked shadow, tonemap) are added only when an edit creates
//     the need;
//   - imported textures become new TEXR chunks (after the existing ones) and TMIP chunks merged
//     into the file's TMIPs in the streamable order of FORMAT.md §4.1 (smallest level first
//     across all textures), compressed like the file's bulk chunks;
//   - every other chunk's stored payload is copied byte for byte (Writer::copyChunk: no decode,
//     no re-compression; the old file's checksums are verified on the way), unknown chunk kinds
//     included, in their places;
//   - the file is written atomically (temporary + fsync + rename): a crash or kill during save
//     leaves the previous file intact;
//   - no other writer's work is lost (pnb/file_lock.h): the rename happens under the file's
//     lock, and a save in place first compares the file on disk with the one the document read;
//     when another program replaced it, the save refuses, naming the other change, and
//     reload(Reload::Merge) brings this document's edits onto the new file.
//
// Does NOT do: geometry edits; normal maps on meshes without tangents, or textures on meshes
// without the texture coordinates the slot reads (the converter keeps only the streams the
// materials used; an error says to reconvert); removing programs or textures of the file that
// nothing uses any more (they are kept); renaming materials or textures; GL (the viewport is the
// caller's). Not thread-safe: one thread uses a Document at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "pnb/error.h"
#include "pnb/file_lock.h"
#include "pnb/scene.h"

namespace pnb::editor {

// How Document::open reads the file (a namespace-scope struct so it can be a default argument).
struct DocumentOpenOptions {
    // Hold the file's lock from the read until the document is saved in place or destroyed, so
    // no other tool replaces the file in between (pnb-edit's batch mode: a second batch edit
    // waits, then reads this one's result). The window does not: a person edits for minutes;
    // its saves compare stamps instead.
    bool holdLock = false;
    // The wait for that lock, and for the target's lock at every save.
    FileLock::Options lock;
};

struct SaveStats {
    double seconds = 0;       // writing the file: chunks, TOC, fsync, rename (wall clock)
    double reloadSeconds = 0; // re-reading the written file as the document's new baseline
    uint64_t bytesWritten = 0; // size of the written file
    uint32_t chunksCopied = 0;    // stored bytes copied from the old file (Writer::copyChunk)
    uint32_t chunksRewritten = 0; // re-encoded: STRS with new strings, edited MATL
    uint32_t chunksAdded = 0;     // new SHDR, PROG, TEXR, TMIP
};

class Document {
public:
    using OpenOptions = DocumentOpenOptions;
    // Opens and fully validates `path` (checksums on). Errors name the file and the problem;
    // Locked when holdLock and another tool kept the file locked past the timeout.
    static Result<std::unique_ptr<Document>> open(const std::string& path,
                                                  const OpenOptions& options = {});

    const std::string& path() const;
    // The scene with the current edits. After every edit each material's `program` names the
    // PROG its current fields need: a variant the file lacks is added to scene().programs (and
    // its stage sources to scene().shaders) at once, so a viewport can compile it before saving.
    // Indices of existing chunks never change. Beyond the file's, scene() holds exactly what the
    // current state needs (an undo, or an edit that no longer needs a variant, drops it again);
    // imported textures appear in textures/textureMips. The reference stays valid for the
    // Document's lifetime; its contents change with every edit, undo, redo and save.
    const Scene& scene() const;
    std::string_view materialName(uint32_t index) const;
    size_t materialCount() const;

    // One edit: field (material_fields.h name) of material `index` set from text. Errors list
    // what is valid; on error nothing changes. Each successful call is one undo step, unless
    // `mergeWithPrevious` (a slider drag) folds it into the previous step (only when the previous
    // operation was an edit: never into an undo, redo, save or the opened file). Texture slots
    // take a texture index, a texture name, or "none". An edit that changes nothing is no step.
    Status setField(uint32_t index, std::string_view field, std::string_view value,
                    bool mergeWithPrevious = false);
    // Why `field` of material `index`, in its current state, changes nothing the player draws
    // ("" when it does): receives/casts_shadows in a scene without a shadow-casting light,
    // casts_shadows on a BLEND material, alpha_cutoff outside MASK. The editor shows it beside
    // the field and pnb-edit --set prints it, so no edit is silently without effect.
    std::string noEffectReason(uint32_t index, std::string_view field) const;
    // Several edits as one undo step (batch operations, --set with wildcards). All or nothing.
    struct FieldEdit {
        uint32_t material;
        std::string field, value;
    };
    Status apply(const std::vector<FieldEdit>& edits);

    // Imports an image file (PNG, JPEG, ... via the converter's texture processing, same
    // defaults: full mip chain, no block compression, no resizing, constant channels dropped)
    // as a new texture; returns its TEXR index. `srgb`: colour data (base colour, emissive) vs
    // linear (normal, metallic-roughness, occlusion). `name`: the texture's name, by which
    // setField's texture slots can refer to it; "" = the image file's stem, made unique with a
    // "-2", "-3", ... suffix. `maxMemoryBytes`: the memory the import may plan to hold
    // (pnb-edit --max-memory); an image whose declared size needs more is refused from its
    // header; 0 = the converter's default (pnb_converter/memory_budget.h). One undo step.
    // Errors: an unreadable image or one over the memory budget (naming it), a name another
    // texture already has.
    Result<uint32_t> importTexture(const std::string& imagePath, bool srgb,
                                   std::string_view name = {}, uint64_t maxMemoryBytes = 0);

    bool canUndo() const;
    bool canRedo() const;
    void undo();
    void redo();
    // The materials or imported textures differ from the file on disk (compared by content:
    // editing a value and setting it back is clean again).
    bool dirty() const;

    // Distinct deferred layer priorities in use and, per layer, the material indices; then the
    // forward materials. For the layer-order view and --list.
    struct LayerOrder {
        std::vector<std::pair<uint16_t, std::vector<uint32_t>>> deferred;
        std::vector<uint32_t> forward;
    };
    LayerOrder layerOrder() const;

    // The stamp of the file this document read (at open, or at its last save or reload).
    const FileStamp& stamp() const;

    // How the file on disk differs from the one this document read.
    struct DiskChange {
        FileStamp was, now; // equal: unchanged, and the lists below are empty
        // What the other program changed in the materials: "'glass'.roughness: 0.2 -> 0.5",
        // "material 'lamp' is new", "material 'old' is gone"; or why the file cannot be read.
        std::vector<std::string> theirs;
        // Fields this document edited that the other program changed to another value:
        // "'glass'.roughness: mine 0.3, theirs 0.5" (or a material it removed).
        std::vector<std::string> conflicts;
        uint32_t mine = 0;      // fields this document changed against the file it read
        bool readable = true;   // the file now is a container (else `theirs` says why)
        bool changed() const { return !(was == now); }
        // "'S.pnb' changed on disk since it was read (was: ..., now: ...); their changes: ...;
        // conflicts with your edits: ..." (lists cut after a few entries, with a count).
        std::string describe(const std::string& path) const;
    };
    // Cheap when nothing changed (one open, one fstat, two small reads); reads the new file
    // otherwise. Materials are matched by name (by index where names are not unique), texture
    // slots compared by texture name. Errors: the file cannot be stat-ed.
    Result<DiskChange> compareWithDisk() const;

    enum class Reload {
        Discard,      // the file as it is now; this document's edits are dropped
        Merge,        // the file as it is now, with this document's edits on top
        MergeMineWin, // as Merge; on a conflict this document's value replaces theirs
    };
    // Re-reads the file from disk as the new baseline. Merging applies every field this
    // document changed against the file it read (matched as in compareWithDisk; imported
    // textures kept) to the new file as one undo step, so undo shows the file as the other
    // program left it. All or nothing: with conflicts (Merge), a texture the new file lacks, or
    // an edit the new file cannot take, it refuses (ChangedOnDisk or the edit's error, naming
    // them) and the document is unchanged. The undo history before the reload is dropped.
    Status reload(Reload mode);

    // Writes to `path` ("" = the opened file). On success the document is clean and refers to
    // the written file, which is read back (and re-validated) as its new baseline; undo/redo
    // history is kept, re-expressed against the new file. On error the target is untouched
    // (and the document unchanged). Errors: IoError (the disk), the old file's own errors if it
    // changed on disk since it was opened (its checksums are verified while copying); Locked
    // (another tool kept the target locked past OpenOptions::lock's timeout); ChangedOnDisk
    // (saving in place, and another program replaced or rewrote the file since this document
    // read it: the message is DiskChange::describe; reload(Reload::Merge) and save again, or
    // save to another path).
    Result<SaveStats> save(const std::string& path = "");

    // Testing only: called during save() with ("chunk", chunks written so far) after every
    // chunk and with ("commit", chunk count) just before the TOC is written and the file renamed
    // into place, so a test can kill the process at a known point. nullptr (default) = none.
    using SaveProbe = void (*)(std::string_view stage, uint32_t chunks);
    static void setSaveProbeForTesting(SaveProbe probe);

    ~Document();

private:
    Document();
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

} // namespace pnb::editor
