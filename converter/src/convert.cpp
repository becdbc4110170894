// The conversion pipeline (convert.h): import → materials → meshes → textures → scene graph →
// environment → shaders → write. convertScene runs the stages in order, each a function named
// for what it does (convert_internal.h). This file holds the checks before the import, the
// stages up to the textures, and the shaders; convert_scene_graph.cpp the scene graph and the
// defaults it adds, convert_environment.cpp the environment, convert_container.cpp the
// container's assembly and write.

#include "pnb_converter/convert.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <optional>

#include "convert_internal.h"
#include "parallel_for.h"
#include "pnb/output_guard.h"
#include "pnb/user_cache_directory.h"
#include "pnb_converter/importers.h"
#include "pnb_converter/material_resolve.h"
#include "pnb_converter/shader_permutations.h"
#include "pnb_converter/shader_validation_cache.h"

namespace pnb::converter {

using namespace convert_detail;

namespace {

namespace fs = std::filesystem;

std::string defaultSidecarPath(const std::string& input) {
    fs::path p(input);
    return (p.parent_path() / (p.stem().string() + ".pnb.json")).string();
}

ConvertError outputError(std::string message) {
    return ConvertError{ConvertErrorKind::Output, std::move(message)};
}

std::string escapeDepfilePath(const std::string& path) {
    std::string out;
    for (char c : path) {
        if (c == ' ' || c == '#' || c == '\\') out += '\\';
        if (c == '$') out += '$';
        out += c;
    }
    return out;
}

Result<bool, ConvertError> writeDepfile(const ConvertSettings& s,
                                        const std::vector<std::string>& deps) {
    std::string tmp = s.depfile + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        f << escapeDepfilePath(s.output) << ":";
        for (const std::string& d : deps) f << " \\\n  " << escapeDepfilePath(d);
        f << "\n";
        if (!f) return outputError(s.depfile + ": cannot write the dependency file");
    }
    std::error_code ec;
    fs::rename(tmp, s.depfile, ec);
    if (ec) return outputError(s.depfile + ": " + ec.message());
    return true;
}

// Lists what the scene does not need and so was not written ("model only what is required").
void describeOmissions(const ResolvedMaterials& r, const ShaderPlan& plan,
                       const SceneShaderNeeds& needs, ConvertSummary& sum) {
    bool any[6] = {};
    for (const MaterialFeatures& f : r.features) {
        any[0] |= f.normalMap;
        any[1] |= f.uv0;
        any[2] |= f.uv1;
        any[3] |= f.vertexColor;
        any[4] |= f.alphaMask;
    }
    if (!any[0]) sum.omitted.push_back("tangents and normal-map variants: no material has a normal map");
    if (!any[1]) sum.omitted.push_back("texture coordinates: no material samples a texture");
    else if (!any[2]) sum.omitted.push_back("second UV set: no material reads TEXCOORD_1");
    if (!any[3]) sum.omitted.push_back("vertex colours: none in the source");
    if (!any[4]) sum.omitted.push_back("alpha-test variants: no MASK material");
    auto hasProgram = [&](const char* name) {
        return std::any_of(plan.programs.begin(), plan.programs.end(),
                           [&](const ProgramVariant& v) { return v.name == name; });
    };
    if (!hasProgram("forward")) sum.omitted.push_back("forward programs: no forward material");
    if (!hasProgram("gbuffer"))
        sum.omitted.push_back("G-buffer and deferred lighting programs: no deferred material");
    if (!needs.shadows)
        sum.omitted.push_back("shadow programs: no shadow-casting light and caster");
    else if (!needs.translucentCasters)
        sum.omitted.push_back("translucent shadow programs: no BLEND material casts shadows");
    if (!needs.gi) sum.omitted.push_back("GI programs: gi.enabled is not true (pnb-convert --gi)");
    if (!needs.ibl)
        sum.omitted.push_back(
            "environment (no --environment or --sky): no sky light, IBL programs, cube map or SH");
}

// [SECTION] import

// The source read into the IR, with what it warned about, what it does not draw, and the files
// it named; each of those files must be a regular file before the stages below read them.
Result<IrScene, ConvertError> importSource(const ConvertSettings& s, const Progress& report,
                                           ConvertSummary& sum) {
    report("import", 0, 1);
    auto imported = importScene(s.input, s.jobs);
    if (!imported) return imported.error();
    IrScene& scene = *imported;
    sum.warnings = scene.warnings;
    for (const IrNotRendered& n : scene.notRendered) {
        std::string use = n.count ? std::to_string(n.count) : std::string();
        if (!n.unit.empty()) use += (use.empty() ? "" : " ") + n.unit;
        sum.notRendered.push_back(n.feature + " (" + use + "): " + n.fallback);
    }
    sum.dependencies.push_back(s.input);
    for (const std::string& d : scene.dependencies) sum.dependencies.push_back(d);
    // The files the textures will be read from (a glTF or MTL may name a FIFO too).
    std::vector<RoleFile> read;
    for (const std::string& d : scene.dependencies) read.push_back({d, "a file the scene names"});
    for (const IrImage& img : scene.images) read.push_back({img.path, "an image the scene names"});
    if (Status st = checkInputs(read); !isOk(st))
        return ConvertError{ConvertErrorKind::Input, s.input + ": " + st.message};
    return imported;
}

// The image decoder module's load (dynamic linking of OpenImageIO), when an image needs it, so
// that it overlaps materials and meshes; processTextures waits for it if it is not done by
// then. The future joins when it is destroyed.
std::future<void> startImageDecoderLoad(const IrScene& scene, const EnvironmentSettings& env) {
    if (std::any_of(scene.images.begin(), scene.images.end(), imageNeedsDecoderModule) ||
        (!env.image.empty() && imageNeedsDecoderModule(IrImage{"environment", env.image, {}, {}})))
        return std::async(std::launch::async, loadImageDecoder);
    return {};
}

// [SECTION] materials

Result<ResolvedMaterials, ConvertError> resolveSceneMaterials(const IrScene& scene,
                                                              const ConvertInputs& inputs,
                                                              ConvertSummary& sum) {
    if (!inputs.sidecar.empty()) sum.dependencies.push_back(inputs.sidecar);
    auto resolved = resolveMaterials(scene, inputs.overrides);
    if (!resolved) return resolved.error();
    for (const std::string& w : resolved->warnings) sum.warnings.push_back(w);
    return resolved;
}

// [SECTION] meshes

// Meshes left without primitives by the importer (only points or lines, which we do not
// draw) are dropped and their node references cleared: nothing is written for them.
Result<bool, ConvertError> dropMeshesWithoutTriangles(const ConvertSettings& s, IrScene& scene,
                                                      ResolvedMaterials& materials,
                                                      ConvertSummary& sum) {
    std::vector<int> meshRemap(scene.meshes.size(), -1);
    std::vector<IrMesh> kept;
    std::vector<StreamNeeds> keptNeeds;
    for (size_t i = 0; i < scene.meshes.size(); ++i) {
        if (scene.meshes[i].primitives.empty()) {
            sum.warnings.push_back("mesh '" + scene.meshes[i].name +
                                   "': no triangles (points and lines are not drawn); "
                                   "dropped");
            continue;
        }
        meshRemap[i] = int(kept.size());
        kept.push_back(std::move(scene.meshes[i]));
        keptNeeds.push_back(materials.meshNeeds[i]);
    }
    if (kept.empty() && !scene.meshes.empty())
        return ConvertError{ConvertErrorKind::Input,
                            s.input + ": no triangle geometry to convert (the source's " +
                                std::to_string(scene.meshes.size()) +
                                " mesh(es) hold only points or lines)"};
    scene.meshes = std::move(kept);
    materials.meshNeeds = std::move(keptNeeds);
    for (IrNode& n : scene.nodes)
        if (n.mesh >= 0) n.mesh = size_t(n.mesh) < meshRemap.size() ? meshRemap[size_t(n.mesh)] : -1;
    return true;
}

// One mesh's statistics into the summary's totals and warnings.
void addMeshStats(const IrMesh& mesh, const MeshStats& st, ConvertSummary& sum) {
    sum.inputTriangles += st.inputTriangles;
    sum.outputTriangles += st.outputTriangles;
    sum.degenerateTriangles += st.degenerateTriangles;
    sum.nonFiniteTriangles += st.nonFiniteTriangles;
    sum.inputVertices += st.inputVertices;
    sum.outputVertices += st.outputVertices;
    sum.maxPositionError = std::max(sum.maxPositionError, st.maxPositionError);
    sum.maxNormalErrorRadians = std::max(sum.maxNormalErrorRadians, st.maxNormalErrorRadians);
    if (sum.lodErrors.size() < st.lodErrors.size()) sum.lodErrors.resize(st.lodErrors.size());
    for (size_t l = 0; l < st.lodErrors.size(); ++l)
        sum.lodErrors[l] = std::max(sum.lodErrors[l], st.lodErrors[l]);
    if (st.tangentsArbitrary)
        sum.warnings.push_back("mesh '" + mesh.name +
                               "': a normal map needs tangents but a primitive has no UVs; "
                               "its tangents are arbitrary");
    if (st.nonFiniteTriangles)
        sum.warnings.push_back("mesh '" + mesh.name + "': dropped " +
                               std::to_string(st.nonFiniteTriangles) +
                               " triangles with non-finite positions");
}

// Every mesh through processMesh, in parallel; statistics and errors are gathered in mesh
// order afterwards, so the summary and the error reported do not depend on the jobs.
Result<std::vector<ProcessedMesh>, ConvertError>
processSceneMeshes(const ConvertSettings& s, const IrScene& scene,
                   const ResolvedMaterials& materials, const Progress& report,
                   ConvertSummary& sum) {
    const size_t count = scene.meshes.size();
    std::vector<std::optional<ProcessedMesh>> meshes(count);
    std::vector<MeshStats> meshStats(count);
    std::vector<std::optional<ConvertError>> meshErrors(count);
    report("meshes", 0, count);
    parallelFor(count, s.jobs, [&](size_t i) {
        auto r = processMesh(scene.meshes[i], materials.meshNeeds[i], s.mesh, meshStats[i]);
        if (r) meshes[i] = std::move(*r);
        else meshErrors[i] = r.error();
    });
    std::vector<ProcessedMesh> processed;
    processed.reserve(count);
    uint64_t renormalised = 0, zero = 0;
    for (size_t i = 0; i < count; ++i) {
        if (meshErrors[i]) return *meshErrors[i]; // the first failing mesh, deterministically
        addMeshStats(scene.meshes[i], meshStats[i], sum);
        renormalised += meshStats[i].weightsRenormalised;
        zero += meshStats[i].weightsZero;
        processed.push_back(std::move(*meshes[i]));
    }
    // One warning for the whole scene: a file that needs it usually needs it everywhere.
    if (renormalised || zero)
        sum.warnings.push_back(std::to_string(renormalised) +
                               " skinned vertices had joint weights not summing to 1 (normalised), " +
                               std::to_string(zero) +
                               " had weights summing to 0 (weight 1 on their first joint)");
    report("meshes", count, count);
    return processed;
}

// [SECTION] textures

// The textures the materials sample, decoded, resized and encoded; the images they came from
// become dependencies.
Result<std::vector<ProcessedTexture>, ConvertError>
processSceneTextures(const ConvertSettings& s, const IrScene& scene,
                     const ResolvedMaterials& materials, const Progress& report,
                     ConvertSummary& sum) {
    report("textures", 0, materials.textures.size());
    TextureSettings textureSettings = s.texture;
    textureSettings.jobs = s.jobs;
    auto processed = processTextures(materials.textures, textureSettings);
    if (!processed) return processed.error();
    const std::vector<ProcessedTexture>& textures = *processed;
    for (size_t t = 0; t < textures.size(); ++t)
        if (s.texture.maxSize == 0 &&
            std::max(textures[t].sourceWidth, textures[t].sourceHeight) > kMaxPortableTextureSize)
            sum.warnings.push_back(
                "texture " + std::to_string(t) + ": " + std::to_string(textures[t].sourceWidth) +
                "x" + std::to_string(textures[t].sourceHeight) + " is larger than " +
                std::to_string(kMaxPortableTextureSize) +
                ", the largest texture every OpenGL 4.5 GPU takes; resized to " +
                std::to_string(textures[t].desc.width) + "x" + std::to_string(textures[t].desc.height) +
                " (--max-texture-size keeps more)");
    for (const IrImage& img : scene.images)
        if (!img.path.empty()) sum.dependencies.push_back(img.path);
    report("textures", textures.size(), textures.size());
    return processed;
}

// [SECTION] shaders

// What the scene's shaders must handle besides the materials' own features.
SceneShaderNeeds sceneShaderNeeds(const ConvertSettings& s, const IrScene& scene,
                                  const std::vector<ProcessedMesh>& meshes,
                                  const ResolvedMaterials& materials, bool hasEnvironment) {
    SceneShaderNeeds needs;
    needs.ibl = hasEnvironment;
    // Any shadow-casting light, sun or lamp: point and spot shadows use the same SHADOWS define.
    // (The default sun makes this true for every scene today; it stays right without it.)
    const bool shadowLight = std::any_of(scene.lights.begin(), scene.lights.end(),
                                         [](const IrLight& l) { return l.castsShadows; });
    for (const Material& m : materials.materials) {
        needs.shadows |= shadowLight && m.castsShadows;
        needs.maskedCasters |= shadowLight && m.castsShadows && m.alphaMode == AlphaMode::Mask;
        needs.translucentCasters |= shadowLight && m.castsShadows && m.alphaMode == AlphaMode::Blend;
    }
    for (const auto& [key, value] : s.renderSettings)
        if (key == "gi.enabled") needs.gi = value == "true"; // the last assignment wins
    // What the container's SKIN and MRPH chunks will hold (convert_container.cpp writes a skin
    // for the nodes that still draw a mesh, and morph targets for every morphed mesh).
    for (const IrNode& n : scene.nodes) needs.skins |= n.skin >= 0 && n.mesh >= 0;
    for (const ProcessedMesh& m : meshes) needs.morphs |= !m.morphTargets.empty();
    return needs;
}

// Every program the plan packs through glslang, or through the cache of programs it accepted.
Result<bool, ConvertError> validateShaderPlan(const ConvertSettings& s, const ShaderPlan& plan,
                                              const Progress& report, ConvertSummary& sum) {
    report("shaders", 0, plan.programs.size());
    ShaderValidationCache* cache = nullptr;
    if (s.shaderCache)
        cache = &processShaderValidationCache(
            s.cacheDir.empty() ? pnb::userCacheDirectory("PNB_CACHE_DIR") : s.cacheDir);
    ShaderValidationStats stats;
    auto validated = validateShaders(plan, builtinShaderFiles(), cache, &stats);
    if (cache)
        for (std::string& n : cache->takeNotes()) sum.notes.push_back(std::move(n));
    if (!validated) return validated.error();
    sum.programsValidated = stats.compiled;
    sum.programsFromCache = stats.fromCache;
    return true;
}

// The program variants the materials and the scene need, validated unless the settings say not.
Result<ShaderPlan, ConvertError> planSceneShaders(const ConvertSettings& s, const IrScene& scene,
                                                  const std::vector<ProcessedMesh>& meshes,
                                                  const ResolvedMaterials& materials,
                                                  bool hasEnvironment, const Progress& report,
                                                  ConvertSummary& sum) {
    const SceneShaderNeeds needs = sceneShaderNeeds(s, scene, meshes, materials, hasEnvironment);
    ShaderPlan plan = planShaders(materials.materials, materials.features, needs);
    if (s.validateShaders)
        if (auto r = validateShaderPlan(s, plan, report, sum); !r) return r.error();
    for (const ProgramVariant& v : plan.programs) sum.programs.push_back(describeVariant(v));
    describeOmissions(materials, plan, needs, sum);
    return plan;
}

} // namespace

std::vector<std::string> addedDefaults(const ConvertSummary& r) {
    std::vector<std::string> out;
    if (r.defaultSun) out.push_back("default sun");
    if (r.defaultEnvironment) out.push_back("default environment");
    if (r.defaultCamera) out.push_back("default camera");
    if (r.defaultPath) out.push_back("default orbit");
    return out;
}

Result<ConvertInputs, ConvertError> convert_detail::checkSettingsAndLoadSidecar(
    const ConvertSettings& s) {
    ConvertInputs in;
    // The sidecar first: it may name the environment (the command line's wins).
    std::string sidecar = s.sidecar;
    if (sidecar.empty() && !s.noSidecar && fs::exists(defaultSidecarPath(s.input)))
        sidecar = defaultSidecarPath(s.input);
    if (!s.noSidecar) in.sidecar = sidecar;
    // Inputs are regular files: a FIFO or a device named here would block the read forever.
    const std::vector<RoleFile> given = {{s.input, "the input"},
                                         {in.sidecar, "the sidecar"},
                                         {s.environment.image, "the environment image"},
                                         {s.cameraPath, "the camera path"}};
    if (Status st = checkInputs(given); !isOk(st))
        return ConvertError{ConvertErrorKind::Input, st.message};
    if (!in.sidecar.empty()) {
        auto loaded = loadSidecar(in.sidecar);
        if (!loaded) return loaded.error();
        in.overrides = std::move(*loaded);
    }
    EnvironmentSettings& env = in.env;
    env = s.environment;
    if (!env.any() && in.overrides.environment) {
        const auto& fromSidecar = *in.overrides.environment;
        env.image = fromSidecar.image;
        env.sky = fromSidecar.sky;
        if (fromSidecar.turbidity) env.skyTurbidity = *fromSidecar.turbidity;
        if (fromSidecar.groundAlbedo) env.skyGroundAlbedo = *fromSidecar.groundAlbedo;
    }
    if (env.sky && !env.image.empty())
        return ConvertError{ConvertErrorKind::Input,
                            "environment: both an image (" + env.image +
                                ") and the analytic sky were asked for; choose one"};

    if (!(s.lights.cutoffLux > 0) || !std::isfinite(s.lights.cutoffLux))
        return ConvertError{ConvertErrorKind::Input,
                            "light cut-off " + std::to_string(s.lights.cutoffLux) +
                                " lux: not a positive finite illuminance"};

    // The output never replaces a file the conversion reads: checked here for the files named
    // so far, and before writing for every file the import read (a glTF's buffers and images).
    in.outputs = {{s.output, "the output"}, {s.depfile, "the dependency file"}};
    in.outputs.insert(in.outputs.end(), s.alsoWrites.begin(), s.alsoWrites.end());
    const std::vector<RoleFile> named = {{s.input, "the input"},
                                         {in.sidecar, "the sidecar"},
                                         {env.image, "the environment image"},
                                         {s.cameraPath, "the camera path"}};
    if (Status st = checkOutputs(named, in.outputs); !isOk(st)) return outputError(st.message);
    if (Status st = checkInputs(named); !isOk(st)) // the sidecar's environment image
        return ConvertError{ConvertErrorKind::Input, st.message};
    return in;
}

Result<ConvertSummary, ConvertError> convertScene(const ConvertSettings& s,
                                                  const ProgressFn& progress) {
    ConvertSummary sum;
    StageClock clock(sum.stages);
    const Progress report{progress};
    auto inputs = checkSettingsAndLoadSidecar(s);
    if (!inputs) return inputs.error();

    clock.start("import");
    auto imported = importSource(s, report, sum);
    if (!imported) return imported.error();
    IrScene& scene = *imported;
    clock.stop();
    // Overlaps materials and meshes; joins at return at the latest.
    const std::future<void> decoderLoad = startImageDecoderLoad(scene, inputs->env);

    clock.start("materials");
    auto resolved = resolveSceneMaterials(scene, *inputs, sum);
    if (!resolved) return resolved.error();
    ResolvedMaterials& materials = *resolved;
    clock.stop();

    clock.start("meshes");
    if (auto r = dropMeshesWithoutTriangles(s, scene, materials, sum); !r) return r.error();
    auto meshes = processSceneMeshes(s, scene, materials, report, sum);
    if (!meshes) return meshes.error();
    clock.stop();

    clock.start("textures");
    auto textures = processSceneTextures(s, scene, materials, report, sum);
    if (!textures) return textures.error();
    clock.stop();

    clock.start("scene");
    auto graph = completeSceneGraph(s, scene, *meshes, sum);
    if (!graph) return graph.error();
    clock.stop();

    auto environment = bakeSceneEnvironment(s, inputs->env, scene, *graph, clock, report, sum);
    if (!environment) return environment.error();

    clock.start("shaders");
    auto plan = planSceneShaders(s, scene, *meshes, materials, environment->get() != nullptr, report, sum);
    if (!plan) return plan.error();
    clock.stop();

    clock.start("write");
    SceneBuilder b;
    const ContainerParts parts{*plan,   *textures, materials, environment->get(),
                               *meshes, scene,     *graph};
    if (auto r = assembleContainer(s, parts, b, sum); !r) return r.error();
    if (auto r = writeContainer(s, b.scene, inputs->outputs, sum); !r) return r.error();
    clock.stop();

    countContainer(b.scene, sum);
    if (!s.depfile.empty())
        if (auto d = writeDepfile(s, sum.dependencies); !d) return d.error();
    return sum;
}

} // namespace pnb::converter
