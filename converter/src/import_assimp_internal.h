// converter/src/import_assimp_internal.h — what the assimp importer's files share: the state of
// one import (Context) and each translation step's entry point. Internal: import_assimp.cpp (io
// system, node tree, importWithAssimp), import_assimp_materials.cpp (images, materials),
// import_assimp_meshes.cpp (aiMesh → IrPrimitive) and import_assimp_nodes.cpp (transforms, axes,
// lights, cameras) include it.
#pragma once

#include <assimp/scene.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pnb_converter/importers.h"

namespace pnb::converter::assimp_detail {

namespace fs = std::filesystem;

inline std::string str(const aiString& s) { return std::string(s.C_Str(), s.length); }

// State shared by the translation steps of one import.
struct Context {
    const aiScene* scene = nullptr;
    std::string path;  // as given, for messages
    fs::path sourceDir;
    IrScene* out = nullptr;
    std::map<std::string, int> imageByKey;  // resolved path or "*<embedded index>" → image
    std::vector<int> materialOf;             // aiMaterial → IrScene::materials, -2 = not yet

    void warn(std::string message) { out->warnings.push_back(std::move(message)); }
};

// [SECTION] materials (import_assimp_materials.cpp)

// IrScene::materials index of an aiMaterial, converting it on first use so materials no mesh
// uses (OBJ always has assimp's "DefaultMaterial") stay out of the IR. Assimp's made-up default
// maps to -1, the IR's default material.
int materialFor(Context& ctx, unsigned index);

// [SECTION] meshes (import_assimp_meshes.cpp)

// The triangles of one aiMesh as an IrPrimitive; nullopt (with a warning) when it has none.
// Errors: an index outside the mesh's vertices.
Result<std::optional<IrPrimitive>, ConvertError> convertMesh(Context& ctx, unsigned meshIndex);

// [SECTION] skins and clips (import_assimp_animation.cpp)

using Check = std::optional<ConvertError>; // empty = success

// Bones of the meshes (`meshByList`: the aiMeshes of each IR mesh) into IrSkins on the nodes
// drawing them, with the primitives' Joints0/Weights0 (a mesh with a bone naming no node stays
// unskinned, warned). Errors: a non-finite offset matrix, a weight of a vertex the mesh
// lacks, more than kMaxJoints bones.
Check skinMeshes(Context& ctx, const std::map<std::vector<unsigned>, int>& meshByList,
                 const std::map<std::string, int>& nodeByName);
// Node animations into IrAnimations. `rootConverted`: the root node carries an axis conversion
// (a channel animating it is warned about). Errors: a non-finite key, a negative time.
Check convertAnimations(Context& ctx, const std::map<std::string, int>& nodeByName, bool rootConverted);

// [SECTION] transforms, axes, lights and cameras (import_assimp_nodes.cpp)

// Whether every element of `m` is finite.
bool finite(const aiMatrix4x4& m);

// A node transform as translation, rotation (xyzw) and scale, which the IR stores.
struct Trs {
    Vec3 translation{0, 0, 0};
    Vec4 rotation{0, 0, 0, 1};
    Vec3 scale{1, 1, 1};
    bool exact = true; // false: shear or a projective row, which TRS cannot hold
};

// Column lengths are the scale; a negative determinant (mirroring) goes into scale.x so the
// rotation stays proper. assimp's matrices are row-major with column vectors (a4,b4,c4 =
// translation).
Trs decompose(aiMatrix4x4 m);

// Basis change from the file's axes to +Y-up right-handed (import_assimp.cpp's header block), or
// nullopt when the file says nothing or already is +Y-up.
std::optional<aiMatrix4x4> axisConversion(Context& ctx);

// The file's lights and cameras, each on the node assimp names after it (nodeByName: the first
// IR node of each name), or on a child node carrying its local position and orientation.
void convertLights(Context& ctx, const std::map<std::string, int>& nodeByName);
void convertCameras(Context& ctx, const std::map<std::string, int>& nodeByName);

} // namespace pnb::converter::assimp_detail
