// pnb_converter/material_resolve.h — from the source's materials to the container's: pipeline
// placement, per-material overrides from a sidecar file, texture requests (one per image and
// colour space, only the channels read), shader features, and which vertex streams each mesh
// must keep.
//
// Default placement (a choice; see docs/CONVERTER.md): OPAQUE and MASK materials go to deferred
// layer 0; BLEND materials go to the forward path, priority 0, because forward shading sorts
// and blends any number of overlapping translucent surfaces correctly, while a deferred layer
// keeps one surface per pixel. Authors move translucent materials into deferred layers (the
// layered-deferred path of seed 003) with the sidecar or pnb-edit; a sidecar survives
// reconversion.
//
// Sidecar: JSON next to the source, `<source stem>.pnb.json` (or --sidecar FILE):
//   { "materials": { "glass*": { "shading_path": "deferred", "layer_priority": 2,
//                                "casts_shadows": false } } }
// Keys are wildcard patterns over material names (globMatch), applied in file order, later
// rules winning; fields are pnb/material_fields.h names except texture slots; values are JSON
// strings, numbers, booleans, or arrays of numbers (colours).
// The scene's environment may come from the sidecar too (the command line's --environment or
// --sky win over it): { "environment": { "image": "sky.exr" } } (a path relative to the
// sidecar) or { "environment": { "sky": true, "turbidity": 4, "ground_albedo": 0.3 } }.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/error.h"
#include "pnb_converter/mesh_processing.h"
#include "pnb_converter/scene_ir.h"
#include "pnb_converter/shader_permutations.h"
#include "pnb_converter/texture_processing.h"

namespace pnb::converter {

struct MaterialOverride {
    std::string pattern;
    std::vector<std::pair<std::string, std::string>> fields; // field name, value as text
};

// The sidecar's "environment" (absent: the sidecar says nothing about it).
struct SidecarEnvironment {
    std::string image;        // resolved against the sidecar's directory; "" = none
    bool sky = false;
    std::optional<float> turbidity, groundAlbedo;
};

struct MaterialOverrides {
    std::string sourcePath; // the sidecar file, for messages ("" if none)
    std::vector<MaterialOverride> rules;
    std::optional<SidecarEnvironment> environment;
};

// Reads a sidecar. Errors (Input) name the file and the JSON position or the offending key.
Result<MaterialOverrides, ConvertError> loadSidecar(const std::string& path);

struct ResolvedMaterials {
    std::vector<Material> materials;       // container materials; name and program left unset
    std::vector<std::string> names;        // per material
    std::vector<MaterialFeatures> features; // per material, for shader selection
    std::vector<TextureRequest> textures;  // container textures, in first-use order
    std::vector<StreamNeeds> meshNeeds;    // per IR mesh
    int defaultMaterial = -1;              // index of the added default material, or -1
    std::vector<std::string> warnings;
};

// Resolves every IR material (plus a glTF-default material if a primitive has none), applies
// the overrides, and derives textures, features and stream needs. Errors: an override naming an
// unknown or texture field, or an invalid value (Input, naming sidecar, pattern and field).
Result<ResolvedMaterials, ConvertError> resolveMaterials(const IrScene& scene,
                                                         const MaterialOverrides& overrides);

// The container material a primitive uses (its IR material, or the default material).
inline uint32_t materialForPrimitive(const ResolvedMaterials& r, int irMaterial) {
    return uint32_t(irMaterial >= 0 ? irMaterial : r.defaultMaterial);
}

} // namespace pnb::converter
