// import_assimp.cpp — the formats assimp 5.2 reads (FBX, Collada, 3DS, PLY, STL, .blend, ...)
// into the scene IR. OBJ/MTL has its own importer (import_obj.cpp, tinyobjloader), which
// importScene picks for .obj; this file still reads OBJ when called directly, and its OBJ
// behaviour below is what import_obj.cpp reproduces.
//
// A translation, not a processing step: assimp runs only Triangulate, SortByPType and
// ValidateDataStructure; welding, normals, tangents and every optimisation are the mesh stage's
// (mesh_processing.h), written once for both importers.
//
// Decisions (also in the report that introduced this file):
// - Post-processing: NO aiProcess_FindInvalidData. It silently deletes whole streams it judges
//   invalid (a UV channel whose coordinates are all equal, zero normals, ...) and we could not
//   warn about it. Instead this file drops a normal/UV/colour stream holding NaN/Inf with a
//   warning naming the mesh; non-finite positions pass through because the mesh stage already
//   drops their triangles with a warning. NO JoinIdenticalVertices/GenNormals/CalcTangentSpace/
//   optimisations (the mesh stage does them), NO MakeLeftHanded/FlipWindingOrder (the IR is
//   right-handed like assimp's output), NO FlipUVs (see the V flip below).
// - Points and lines: SortByPType splits them into their own aiMeshes, which are dropped here
//   with a warning naming the mesh (the IR is triangles only).
// - V flip: IR UVs follow glTF (v = 0 is the top row of the image); assimp keeps OBJ's
//   convention (v = 0 is the bottom row), so every UV becomes (u, 1 - v). Done here rather than
//   with aiProcess_FlipUVs so the one place that knows the convention is this file.
// - Up axis: OBJ is +Y-up right-handed and taken as is. For other formats the file's "UpAxis",
//   "FrontAxis" and "CoordAxis" metadata (+ signs), which assimp 5.2 reports for FBX, become a
//   basis change on the root node. Collada and 3DS need nothing: assimp already converts them
//   in their root node. .blend is Z-up and assimp neither converts it nor reports metadata, so
//   it gets the Z-up → Y-up rotation. Units are NOT converted (FBX UnitScaleFactor is ignored).
// - Meshes: one IrMesh per distinct list of aiMeshes a node references, one IrPrimitive per
//   aiMesh. Assimp splits an OBJ object per material, so an object with two materials is one
//   IrMesh with two primitives (one submesh each) on one node, as glTF would model it; nodes
//   referencing the same list share the IrMesh (instancing).
// - map_d: the same file as map_Kd → alpha of the base colour texture (alphaMode Mask when d is
//   1, the common cut-out case; Blend when d < 1). Another file → a warning (separate opacity
//   maps are not supported yet) and the alpha mode comes from d alone.
// - Texture paths: relative to the source file's directory, '\' → '/', then a
//   case-insensitive, component-by-component lookup, then (with a warning) the file name alone
//   next to the source file (absolute paths from another machine): import_paths.h, shared with
//   import_obj.cpp. Files assimp itself opens (mtllib) go through the same resolver via an
//   IOSystem. Missing textures are dropped with a
//   warning; the material is kept.
//
// Does NOT do: processing of any kind, image decoding, animation, skinning, morph targets
// (each dropped with a warning), unit conversion.
//
// The translation steps are one file each (import_assimp_internal.h lists them); this file
// holds the io system, walks the node tree and is the entry point.
//
// Index: [SECTION] io system, [SECTION] scene and entry point.
#include "pnb_converter/importers.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "import_assimp_internal.h"
#include "import_paths.h"

namespace pnb::converter {

namespace {

using namespace assimp_detail;
using namespace import_detail;

// [SECTION] io system

// The files assimp opens itself (OBJ's mtllib, other formats' companion files) get the same
// backslash and case fix-ups as textures, and the ones that stay missing become warnings:
// assimp only logs them, and its logger is a process-wide singleton we cannot use per import.
class ResolvingIOSystem : public Assimp::DefaultIOSystem {
public:
    explicit ResolvingIOSystem(fs::path sourceDir) : mSourceDir(std::move(sourceDir)) {}

    bool Exists(const char* file) const override {
        return Assimp::DefaultIOSystem::Exists(file) || resolve(file).has_value();
    }

    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (Assimp::IOStream* stream = Assimp::DefaultIOSystem::Open(file, mode)) return stream;
        const bool readOnly = std::strpbrk(mode, "wa+") == nullptr;
        if (readOnly) {
            if (auto resolved = resolve(file)) {
                const std::string path = resolved->path.string();
                if (Assimp::IOStream* s = Assimp::DefaultIOSystem::Open(path.c_str(), mode)) {
                    if (resolved->byNameOnly) {
                        note(format("'%s' not found; using '%s' (same file name, next to the "
                                    "source file)", file, path.c_str()));
                    }
                    return s;
                }
            }
        }
        note(format("could not open '%s' (referenced by the source file)", file));
        return nullptr;
    }

    // Warnings collected while assimp read the file, in the order they happened.
    const std::vector<std::string>& notes() const { return mNotes; }

private:
    // Loaders retry the same name; one warning per file is enough.
    void note(std::string message) {
        if (std::find(mNotes.begin(), mNotes.end(), message) == mNotes.end()) {
            mNotes.push_back(std::move(message));
        }
    }

    // Assimp hands over paths it has already joined with the source directory (or absolute
    // ones), so they resolve from the working directory; the bare-name fallback uses the
    // source directory.
    std::optional<ResolvedPath> resolve(const char* file) const {
        if (file == nullptr || *file == '\0') return std::nullopt;
        std::string ref(file);
        std::replace(ref.begin(), ref.end(), '\\', '/');
        const fs::path p(ref);
        if (isRegularFile(p)) return ResolvedPath{p};
        if (p.is_absolute()) {
            if (auto found = findIgnoringCase(p.root_path(), p.relative_path())) {
                return ResolvedPath{*found};
            }
        } else {
            // Some loaders (LWS) open companion files by their bare relative name.
            if (auto found = findIgnoringCase(fs::path("."), p)) return ResolvedPath{*found};
            if (auto found = findIgnoringCase(mSourceDir, p)) return ResolvedPath{*found};
        }
        if (p.has_filename()) {
            if (auto byName = findIgnoringCase(mSourceDir, p.filename())) {
                return ResolvedPath{*byName, true};
            }
        }
        return std::nullopt;
    }

    fs::path mSourceDir;
    std::vector<std::string> mNotes;
};

// [SECTION] scene and entry point

Result<IrScene, ConvertError> translate(Context& ctx) {
    const aiScene* scene = ctx.scene;
    IrScene& out = *ctx.out;
    ctx.materialOf.assign(scene->mNumMaterials, -2);

    // Each aiMesh is converted once; nodes then share IrMeshes by the list of aiMeshes they use.
    std::vector<std::optional<IrPrimitive>> primitives(scene->mNumMeshes);
    std::vector<bool> converted(scene->mNumMeshes, false);
    auto primitiveOf = [&](unsigned meshIndex) -> Result<const IrPrimitive*, ConvertError> {
        if (!converted[meshIndex]) {
            auto r = convertMesh(ctx, meshIndex);
            if (!r) return r.error();
            primitives[meshIndex] = std::move(r.value());
            converted[meshIndex] = true;
        }
        return primitives[meshIndex] ? &*primitives[meshIndex] : nullptr;
    };
    std::map<std::vector<unsigned>, int> meshByList;

    const auto rootConversion = axisConversion(ctx);
    std::map<std::string, int> nodeByName;
    struct Pending {
        const aiNode* node;
        int parent;
    };
    std::vector<Pending> stack{{scene->mRootNode, -1}};
    while (!stack.empty()) {
        const Pending pending = stack.back();
        stack.pop_back();
        const aiNode* src = pending.node;
        if (src == nullptr) continue;
        IrNode node;
        node.name = str(src->mName);
        node.parent = pending.parent;
        aiMatrix4x4 local = src->mTransformation;
        if (pending.parent < 0 && rootConversion) local = *rootConversion * local;
        if (!finite(local)) {
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: node '%s' has a non-finite transform",
                                       ctx.path.c_str(), node.name.c_str())};
        }
        const Trs trs = decompose(local);
        if (!trs.exact) {
            ctx.warn(format("node '%s': transform has shear or projection; approximated by "
                            "translation/rotation/scale", node.name.c_str()));
        }
        node.translation = trs.translation;
        node.rotation = trs.rotation;
        node.scale = trs.scale;

        std::vector<unsigned> list;
        for (unsigned k = 0; k < src->mNumMeshes; ++k) {
            const unsigned meshIndex = src->mMeshes[k];
            if (meshIndex >= scene->mNumMeshes) {
                return ConvertError{ConvertErrorKind::Input,
                                    format("%s: node '%s' refers to mesh %u of %u",
                                           ctx.path.c_str(), node.name.c_str(), meshIndex,
                                           scene->mNumMeshes)};
            }
            auto prim = primitiveOf(meshIndex);
            if (!prim) return prim.error();
            if (prim.value() != nullptr) list.push_back(meshIndex);
        }
        if (!list.empty()) {
            auto [it, inserted] = meshByList.emplace(list, int(out.meshes.size()));
            if (inserted) {
                IrMesh mesh; // primitives are filled in once all lists are known
                const aiMesh* first = scene->mMeshes[list[0]];
                mesh.name = list.size() == 1 && first->mName.length > 0 ? str(first->mName)
                                                                        : node.name;
                out.meshes.push_back(std::move(mesh));
            }
            node.mesh = it->second;
        }
        out.nodes.push_back(std::move(node));
        const int index = int(out.nodes.size() - 1);
        nodeByName.emplace(str(src->mName), index); // first node of a name wins
        // Reverse order so children come out in their source order (preorder: parents first).
        for (unsigned k = src->mNumChildren; k-- > 0;) stack.push_back({src->mChildren[k], index});
    }

    // An aiMesh in several distinct lists is copied into each IrMesh; the last one takes it.
    std::vector<unsigned> uses(scene->mNumMeshes, 0);
    for (const auto& entry : meshByList) {
        for (unsigned meshIndex : entry.first) ++uses[meshIndex];
    }
    for (const auto& [list, meshIndex] : meshByList) {
        IrMesh& mesh = out.meshes[size_t(meshIndex)];
        for (unsigned m : list) {
            if (--uses[m] == 0) mesh.primitives.push_back(std::move(*primitives[m]));
            else mesh.primitives.push_back(*primitives[m]);
        }
    }

    size_t unused = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) unused += converted[m] ? 0 : 1;
    if (unused > 0) ctx.warn(format("%zu mesh(es) used by no node; dropped", unused));
    if (out.meshes.empty()) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: no triangle meshes (%u mesh(es) in the file, none with "
                                   "triangles)", ctx.path.c_str(), scene->mNumMeshes)};
    }

    convertLights(ctx, nodeByName);
    convertCameras(ctx, nodeByName);
    if (auto e = skinMeshes(ctx, meshByList, nodeByName)) return *e;
    if (auto e = convertAnimations(ctx, nodeByName, rootConversion.has_value())) return *e;
    return std::move(out);
}

} // namespace

Result<IrScene, ConvertError> importWithAssimp(const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: no such file (or not a regular file)", path.c_str())};
    }
    // Assimp reports bad data through its error string, but a std::bad_alloc (or a loader's
    // stray exception) must not cross our module boundary either.
    try {
        const fs::path sourceDir = fs::path(path).parent_path();
        Assimp::Importer importer;
        // Formats with bones but no meshes (BVH) would otherwise get a generated skeleton mesh.
        importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
        // One node per FBX node instead of a chain of "$AssimpFbx$" pivot helpers.
        importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
        auto* io = new ResolvingIOSystem(sourceDir.empty() ? fs::path(".") : sourceDir);
        importer.SetIOHandler(io); // the importer owns and deletes it

        const unsigned flags =
            aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure;
        const aiScene* scene = importer.ReadFile(path, flags);
        if (scene == nullptr) {
            const char* message = importer.GetErrorString();
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: assimp could not read it: %s", path.c_str(),
                                       message && *message ? message : "unknown error")};
        }
        if (scene->mRootNode == nullptr || scene->mNumMeshes == 0) {
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: the file has no meshes", path.c_str())};
        }
        if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) {
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: assimp could only read part of it (scene marked "
                                       "incomplete)", path.c_str())};
        }

        IrScene out;
        out.sourcePath = path;
        out.warnings = io->notes();
        Context ctx;
        ctx.scene = scene;
        ctx.path = path;
        ctx.sourceDir = sourceDir.empty() ? fs::path(".") : sourceDir;
        ctx.out = &out;
        return translate(ctx);
    } catch (const std::exception& e) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: import failed: %s", path.c_str(), e.what())};
    } catch (...) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: import failed (unknown exception)", path.c_str())};
    }
}

} // namespace pnb::converter
