// pnb_converter/convert.h — the whole conversion as one callable function (the CLI is a thin
// wrapper; tests call this directly).
//
// Stages: import (glTF/assimp → IR) → materials (placement, sidecar, texture requests) →
// meshes → textures → lights (ranges, shadows, the kMaxLights cap: light_processing.h), cameras,
// nodes, camera paths (defaults added where missing) →
// shaders (permutations the materials need, validated with glslang) → write (streamable order,
// atomic). Deterministic: the same input and settings give a byte-identical file whatever `jobs`.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pnb/error.h"
#include "pnb/file_lock.h"
#include "pnb/output_guard.h"
#include "pnb_converter/environment.h"
#include "pnb_converter/light_processing.h"
#include "pnb_converter/mesh_processing.h"
#include "pnb_converter/scene_ir.h"
#include "pnb_converter/texture_processing.h"

namespace pnb::converter {

struct ConvertSettings {
    std::string input;          // source scene file
    std::string output;         // .pnb to write (atomically)
    // The wait for the output's lock while another tool saves it (pnb/file_lock.h): the
    // conversion's rename waits for pnb-edit's save rather than landing inside it.
    FileLockOptions outputLock;
    // Files the caller writes after the conversion (pnb-convert's --summary-json): checked, like
    // the output, against every file the conversion reads before anything is written.
    std::vector<RoleFile> alsoWrites;
    std::string sidecar;        // material overrides; "" = <input stem>.pnb.json if it exists
    bool noSidecar = false;     // ignore any sidecar. Default: false.
    std::string cameraPath;     // --path keyframe file; "" = the source's or a generated orbit
    std::string depfile;        // write a Make-style dependency file (for Ninja); "" = none
    MeshSettings mesh;          // see mesh_processing.h for defaults
    TextureSettings texture;    // see texture_processing.h for defaults
    // Image-based lighting (environment.h): an equirect image or the analytic sky, baked into
    // ENVM and its textures; the lighting programs then get the define IBL. Default: none.
    // Both an image and the sky: an Input error.
    EnvironmentSettings environment;
    // With no environment asked for (above or in the sidecar) and no light in the source, add
    // the neutral default studio (environment.h "default-studio", flagged generated in ENVM).
    // Default: false here, so that a program (the tests) gets exactly the light its source
    // says; pnb-convert turns it on unless --no-default-environment.
    bool defaultEnvironment = false;
    LightSettings lights;       // see light_processing.h (the --light-cutoff) for defaults
    uint32_t jobs = 0;          // worker threads for meshes and textures; 0 = all cores
    bool validateShaders = true; // glslang-check every packed program. Default: true.
    // Remember programs glslang accepted (shader_validation_cache.h): in memory for the process
    // and on disk under `cacheDir`, so a program text is validated once. Default: true.
    bool shaderCache = true;
    std::string cacheDir;       // "" = pnb::userCacheDirectory("PNB_CACHE_DIR")
    bool checksums = true;      // payload checksums. Default: true.
    bool compressBulk = false;  // zstd also for meshes and texels (smaller file, no zero-copy
                                // load). Default: false.
    // Render settings stored in the container (RSET), e.g. {"shadows.cascades", "4"}.
    std::vector<std::pair<std::string, std::string>> renderSettings;
};

struct StageTiming {
    std::string stage;
    double seconds = 0;
};

struct ConvertSummary {
    size_t meshes = 0, submeshes = 0, nodes = 0, materials = 0, textures = 0, lights = 0,
           cameras = 0, cameraPaths = 0;
    size_t instances = 0; // EXT_mesh_gpu_instancing copies (NODE version 2), all nodes together
    // Moving scenes (SKIN, ANIM, MRPH): skins and their joints, clips and the longest one's
    // duration, meshes with morph targets.
    size_t skins = 0, joints = 0, clips = 0, morphedMeshes = 0;
    double longestClipSeconds = 0;
    uint64_t inputTriangles = 0, outputTriangles = 0, degenerateTriangles = 0,
             nonFiniteTriangles = 0, inputVertices = 0, outputVertices = 0;
    float maxPositionError = 0, maxNormalErrorRadians = 0; // quantisation, worst mesh
    std::vector<float> lodErrors;                          // worst error per extra LOD level
    size_t deferredMaterials = 0, forwardMaterials = 0;
    std::vector<uint16_t> deferredLayers;                  // distinct priorities, ascending
    std::vector<std::string> programs;                     // "gbuffer[HAS_UV0 ...]"
    size_t programsValidated = 0, programsFromCache = 0;   // glslang runs vs cache hits
    std::vector<std::string> omitted;  // what the scene does not need and so was not written
    std::vector<std::string> warnings; // dropped or repaired input, each naming the item
    // Source features the player does not draw, one line each with what it draws instead
    // ("KHR_materials_sheen (3 materials): the base layer without sheen"), from
    // IrScene::notRendered.
    std::vector<std::string> notRendered;
    std::vector<std::string> notes;    // harmless trouble worth a verbose line (cache not saved)
    // What the converter added because the source lacked it, each flagged generated in the
    // container; reported once (added()), not as warnings.
    bool defaultSun = false, defaultCamera = false, defaultPath = false,
         defaultEnvironment = false;
    double minTexturePsnrDb = 0;       // worst PSNR of compressed textures (0 = none compressed)
    uint64_t outputBytes = 0, meshBytes = 0, textureBytes = 0;
    std::optional<EnvironmentSummary> environment; // when one was written
    std::vector<StageTiming> stages;
    std::vector<std::string> dependencies; // files read (source, buffers, images, sidecar, path,
                                           // environment image)
};

// The additions of a summary in a fixed order, for the one summary line: "default sun",
// "default environment", "default camera", "default orbit" (those that apply).
std::vector<std::string> addedDefaults(const ConvertSummary& summary);

// Called as work progresses: stage name, items done, items in the stage.
using ProgressFn = std::function<void(const std::string& stage, size_t done, size_t total)>;

Result<ConvertSummary, ConvertError> convertScene(const ConvertSettings& settings,
                                                  const ProgressFn& progress = {});

} // namespace pnb::converter
