// import_scene.cpp — picks the importer for a source file by its extension.
//
// Does NOT do: content sniffing. A .gltf/.glb goes to tinygltf (importGltf), which gives glTF
// its exact semantics (extensions, samplers, KHR_* data assimp drops); a .obj goes to importObj
// (its own parallel parser, tinyobjloader for the rest), which parses it faster than assimp;
// everything else goes to assimp, which detects the format itself and reports a file it cannot
// read.
#include "pnb_converter/importers.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace pnb::converter {

Result<IrScene, ConvertError> importScene(const std::string& path,
                                          unsigned jobs) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (extension == ".gltf" || extension == ".glb") return importGltf(path);
    if (extension == ".obj") return importObj(path, jobs);
    return importWithAssimp(path);
}

} // namespace pnb::converter
