// pnb_converter/importers.h — source files into the IR (scene_ir.h).
//
// Does NOT do: processing of any kind (see mesh_processing.h, texture_processing.h); image
// decoding (images stay paths or encoded bytes until the texture stage).
//
// Both importers: never crash on malformed input (every error names the file and the item at
// fault); turn every primitive mode into triangle lists; drop what they cannot use with a warning
// naming it; order nodes parents first; convert to +Y-up right-handed metres.
#pragma once

#include <string>

#include "pnb/error.h"
#include "pnb_converter/scene_ir.h"

namespace pnb::converter {

// glTF 2.0 (.gltf with external or data-URI buffers, .glb) through tinygltf, with
// KHR_draco_mesh_compression (Draco), EXT_meshopt_compression (meshoptimizer, as gltfpack -c
// writes), KHR_texture_transform, KHR_materials_emissive_strength, KHR_lights_punctual,
// KHR_mesh_quantization, sparse accessors, normalized integer attributes, cameras, node TRS or
// matrices. Unsupported extensions: a warning naming each; an Unsupported error if one is in
// extensionsRequired. KHR_texture_basisu/EXT_texture_webp textures use their fallback image; an
// Unsupported error names the texture and image when there is none.
Result<IrScene, ConvertError> importGltf(const std::string& path);

// Wavefront OBJ/MTL through our parallel OBJ parser, or tinyobjloader for what it leaves (and for
// errors), and tinyobjloader's MTL reader. MTL parameters map onto PBR as mtl_to_pbr.h
// documents; map_Kd → base colour, map_d → alpha (a warning if it is not the base colour's
// alpha), norm/bump/map_bump → normal map, map_Ke → emissive. Errors name the file and, for
// malformed faces, the line. The MTL files read are listed in IrScene::dependencies.
// `jobs`: threads for the parse and the vertex numbering (0 = all cores; the result does not
// depend on it).
Result<IrScene, ConvertError> importObj(const std::string& path, unsigned jobs = 0);

// The other formats assimp reads (FBX, Collada, 3DS, PLY, STL, .blend, ...; OBJ too, though
// importScene sends .obj to importObj). Same MTL mapping for OBJ.
Result<IrScene, ConvertError> importWithAssimp(const std::string& path);

// Picks the importer by extension (.gltf/.glb → glTF, .obj → OBJ, anything else → assimp).
// `jobs` as for importObj (the other importers do not use it).
Result<IrScene, ConvertError> importScene(const std::string& path, unsigned jobs = 0);

} // namespace pnb::converter
