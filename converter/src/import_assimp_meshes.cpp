// converter/src/import_assimp_meshes.cpp — one aiMesh into one IrPrimitive: triangles only,
// non-finite streams dropped with a warning, UVs flipped to glTF's v-down. A step of the assimp
// importer (import_assimp_internal.h); sharing IrMeshes between nodes is import_assimp.cpp's.
#include <assimp/mesh.h>
#include <assimp/scene.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "import_assimp_internal.h"
#include "import_paths.h"

namespace pnb::converter::assimp_detail {

using namespace import_detail;

namespace {

// [SECTION] meshes

std::string meshLabel(const aiMesh& mesh, unsigned index) {
    return mesh.mName.length > 0 ? format("mesh '%s'", mesh.mName.C_Str())
                                 : format("mesh %u", index);
}

// Copies a 3-component stream, reporting whether every value is finite.
bool copyVec3(const aiVector3D* src, unsigned count, std::vector<float>& dst) {
    dst.resize(size_t(count) * 3);
    bool allFinite = true;
    for (unsigned i = 0; i < count; ++i) {
        dst[i * 3 + 0] = src[i].x;
        dst[i * 3 + 1] = src[i].y;
        dst[i * 3 + 2] = src[i].z;
        allFinite = allFinite && std::isfinite(src[i].x) && std::isfinite(src[i].y) &&
                    std::isfinite(src[i].z);
    }
    return allFinite;
}

bool copyUv(const aiVector3D* src, unsigned count, std::vector<float>& dst) {
    dst.resize(size_t(count) * 2);
    bool allFinite = true;
    for (unsigned i = 0; i < count; ++i) {
        dst[i * 2 + 0] = src[i].x;
        dst[i * 2 + 1] = 1.0f - src[i].y; // assimp/OBJ v-up → glTF v-down (header block)
        allFinite = allFinite && std::isfinite(src[i].x) && std::isfinite(src[i].y);
    }
    return allFinite;
}

} // namespace

// The triangles of one aiMesh as an IrPrimitive; nullopt (with a warning) when it has none.
// Errors: an index outside the mesh's vertices.
Result<std::optional<IrPrimitive>, ConvertError> convertMesh(Context& ctx, unsigned meshIndex) {
    const aiMesh* mesh = ctx.scene->mMeshes[meshIndex];
    if (mesh == nullptr) return std::optional<IrPrimitive>{};
    const std::string label = meshLabel(*mesh, meshIndex);
    if (mesh->mNumVertices == 0 || mesh->mVertices == nullptr) {
        ctx.warn(label + ": no vertices; dropped");
        return std::optional<IrPrimitive>{};
    }

    if (mesh->mNumFaces > 0 && mesh->mFaces == nullptr) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: %s has %u faces but no face array", ctx.path.c_str(),
                                   label.c_str(), mesh->mNumFaces)};
    }

    IrPrimitive prim;
    uint64_t points = 0, lines = 0, polygons = 0;
    prim.indices.reserve(size_t(mesh->mNumFaces) * 3);
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices > 0 && face.mIndices == nullptr) {
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: %s face %u has no index array", ctx.path.c_str(),
                                       label.c_str(), f)};
        }
        for (unsigned k = 0; k < face.mNumIndices; ++k) {
            if (face.mIndices[k] >= mesh->mNumVertices) {
                return ConvertError{ConvertErrorKind::Input,
                                    format("%s: %s face %u: index %u out of range 0..%u",
                                           ctx.path.c_str(), label.c_str(), f, face.mIndices[k],
                                           mesh->mNumVertices - 1)};
            }
        }
        switch (face.mNumIndices) {
        case 1: ++points; break;
        case 2: ++lines; break;
        case 3: prim.indices.insert(prim.indices.end(), face.mIndices, face.mIndices + 3); break;
        default: ++polygons; break; // Triangulate leaves none; counted in case a loader does
        }
    }
    if (points + lines + polygons > 0) {
        std::string dropped;
        for (auto [count, kind] : {std::pair{points, "point"}, std::pair{lines, "line"},
                                   std::pair{polygons, "polygon"}}) {
            if (count == 0) continue;
            dropped += format("%s%llu %s(s)", dropped.empty() ? "" : ", ",
                              (unsigned long long)count, kind);
        }
        ctx.warn(format("%s: dropped %s; only triangles are imported", label.c_str(),
                        dropped.c_str()));
    }
    if (prim.indices.empty()) return std::optional<IrPrimitive>{};

    const unsigned n = mesh->mNumVertices;
    // Non-finite positions pass through: the mesh stage drops their triangles with a warning.
    copyVec3(mesh->mVertices, n, prim.positions);
    if (mesh->mNormals != nullptr && !copyVec3(mesh->mNormals, n, prim.normals)) {
        prim.normals.clear();
        ctx.warn(label + ": non-finite normals; dropped (they will be generated)");
    }
    for (unsigned set = 0; set < AI_MAX_NUMBER_OF_TEXTURECOORDS; ++set) {
        if (mesh->mTextureCoords[set] == nullptr) continue;
        if (set > 1) {
            ctx.warn(format("%s: UV set %u ignored (only sets 0 and 1 are imported)",
                            label.c_str(), set));
            continue;
        }
        std::vector<float>& uv = set == 0 ? prim.uv0 : prim.uv1;
        if (!copyUv(mesh->mTextureCoords[set], n, uv)) {
            uv.clear();
            ctx.warn(format("%s: non-finite UV set %u; dropped", label.c_str(), set));
        }
    }
    if (mesh->mColors[0] != nullptr) {
        prim.colors.resize(size_t(n) * 4);
        bool allFinite = true;
        for (unsigned i = 0; i < n; ++i) {
            const aiColor4D& c = mesh->mColors[0][i];
            prim.colors[i * 4 + 0] = c.r;
            prim.colors[i * 4 + 1] = c.g;
            prim.colors[i * 4 + 2] = c.b;
            prim.colors[i * 4 + 3] = c.a;
            allFinite = allFinite && std::isfinite(c.r) && std::isfinite(c.g) &&
                        std::isfinite(c.b) && std::isfinite(c.a);
        }
        if (!allFinite) {
            prim.colors.clear();
            ctx.warn(label + ": non-finite vertex colours; dropped");
        }
    }
    for (unsigned set = 1; set < AI_MAX_NUMBER_OF_COLOR_SETS; ++set) {
        if (mesh->mColors[set] != nullptr) {
            ctx.warn(format("%s: vertex colour set %u ignored", label.c_str(), set));
        }
    }
    // Bones are read with the node tree (skinMeshes, import_assimp_animation.cpp).
    if (mesh->mNumAnimMeshes > 0) {
        ctx.out->noteNotRendered("morph targets", 1, "meshes", "the base shape");
    }
    prim.material = materialFor(ctx, mesh->mMaterialIndex);
    return std::optional<IrPrimitive>(std::move(prim));
}

} // namespace pnb::converter::assimp_detail
