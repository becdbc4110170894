// converter/src/convert_internal.h — the stages convertScene (convert.cpp) runs in order, and
// the state one stage hands the next. Each stage is a function named for what it does, in the
// file of its concern: the scene graph and its defaults (convert_scene_graph.cpp), the
// environment (convert_environment.cpp), the container's assembly and write
// (convert_container.cpp); the rest in convert.cpp.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "pnb/output_guard.h"
#include "pnb/scene_builder.h"
#include "pnb_converter/camera_path.h"
#include "pnb_converter/convert.h"
#include "pnb_converter/environment.h"
#include "pnb_converter/material_resolve.h"
#include "pnb_converter/shader_permutations.h"

namespace pnb::converter::convert_detail {

// Times one stage at a time into ConvertSummary::stages, in the order they ran.
class StageClock {
public:
    explicit StageClock(std::vector<StageTiming>& out) : mOut(out) {}
    void start(const char* stage) {
        mStage = stage;
        mStart = std::chrono::steady_clock::now();
    }
    void stop() {
        auto d = std::chrono::steady_clock::now() - mStart;
        mOut.push_back({mStage, std::chrono::duration<double>(d).count()});
    }

private:
    std::vector<StageTiming>& mOut;
    std::string mStage;
    std::chrono::steady_clock::time_point mStart;
};

// The caller's progress callback, called only when there is one.
struct Progress {
    const ProgressFn& fn;
    void operator()(const char* stage, size_t done, size_t total) const {
        if (fn) fn(stage, done, total);
    }
};

// [SECTION] before the import (convert.cpp)

// What the checks before the import settled.
struct ConvertInputs {
    std::string sidecar;           // the sidecar read; "" when none (or --no-sidecar)
    MaterialOverrides overrides;   // the sidecar's
    EnvironmentSettings env;       // the command line's, else the sidecar's
    std::vector<RoleFile> outputs; // every file the conversion writes
};

// Finds and loads the sidecar, settles the environment, and refuses settings and files that
// cannot work (an output that is an input, an input that is not a regular file).
Result<ConvertInputs, ConvertError> checkSettingsAndLoadSidecar(const ConvertSettings& s);

// [SECTION] scene graph (convert_scene_graph.cpp)

// Column-major 4x4 in double: world transforms of deep hierarchies far from the origin keep
// their precision until the final float bounds.
struct Mat4d {
    double m[16];
};

// Where every node is: its world transform and world bounds, and the whole scene's bounds.
// Indexed like IrScene::nodes, nodes added for defaults included.
struct NodePlacement {
    std::vector<Mat4d> world;
    std::vector<Aabb> nodeBounds;
    std::vector<Sphere> nodeSpheres;
    Aabb sceneBounds;
};

// The scene stage's result: where the nodes are, which lights the converter added, the camera
// paths, and whether the source brought lights of its own.
struct SceneGraph {
    NodePlacement placement;
    std::vector<bool> generatedLight; // indexed like IrScene::lights
    std::vector<PathSpec> paths;
    bool sourceHasLights = false;
};

// Places the nodes, adds the sun, camera and camera path the source lacks (each a summary
// line, not a warning), and settles the lights (light_processing.h).
Result<SceneGraph, ConvertError> completeSceneGraph(const ConvertSettings& s, IrScene& scene,
                                                    const std::vector<ProcessedMesh>& meshes,
                                                    ConvertSummary& sum);

// [SECTION] environment (convert_environment.cpp)

// The scene's environment: its own bake, the shared default studio, or none.
struct SceneEnvironment {
    std::optional<BakedEnvironment> own;
    const BakedEnvironment* shared = nullptr;
    const BakedEnvironment* get() const { return own ? &*own : shared; }
};

// After the lights, since the sky follows the scene's sun (the default one if the converter
// added it). Times itself as the stage "environment" when there is one.
Result<SceneEnvironment, ConvertError>
bakeSceneEnvironment(const ConvertSettings& s, const EnvironmentSettings& env, const IrScene& scene,
                     const SceneGraph& graph, StageClock& clock, const Progress& report,
                     ConvertSummary& sum);

// [SECTION] container (convert_container.cpp)

// Fills the builder's scene from every stage's result, in the container's streamable order.
// The order of the appends is the order strings are interned, so it is part of the file's bytes.
struct ContainerParts {
    const ShaderPlan& plan;
    const std::vector<ProcessedTexture>& textures;
    const ResolvedMaterials& materials;
    const BakedEnvironment* environment;
    const std::vector<ProcessedMesh>& meshes;
    const IrScene& scene;
    const SceneGraph& graph;
};
Result<bool, ConvertError> assembleContainer(const ConvertSettings& s, const ContainerParts& parts,
                                             SceneBuilder& b, ConvertSummary& sum);

// Checks the assembled scene, then writes it atomically to s.output.
Result<bool, ConvertError> writeContainer(const ConvertSettings& s, const Scene& out,
                                          const std::vector<RoleFile>& outputs,
                                          ConvertSummary& sum);

// The summary's counts of what the container holds.
void countContainer(const Scene& out, ConvertSummary& sum);

} // namespace pnb::converter::convert_detail
