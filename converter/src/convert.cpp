// The conversion pipeline (convert.h): import → materials → meshes → textures → scene graph →
// shaders → write. Each stage lives in its own file; this one sequences them, adds the defaults
// a scene lacks, and assembles the container in streamable order.

#include "pnb_converter/convert.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <optional>
#include <set>

#include "parallel_for.h"
#include "pnb/compression_memo.h"
#include "pnb/mesh_levels.h"
#include "pnb/output_guard.h"
#include "pnb/scene_builder.h"
#include "pnb/user_cache_directory.h"
#include "pnb/writer.h"
#include "pnb_converter/camera_path.h"
#include "pnb_converter/environment.h"
#include "pnb_converter/importers.h"
#include "pnb_converter/material_resolve.h"
#include "pnb_converter/shader_permutations.h"
#include "pnb_converter/shader_validation_cache.h"

namespace pnb::converter {

namespace {

namespace fs = std::filesystem;

constexpr const char* kGenerator = "pnb-convert 0.1";

// Default sun when a scene has no directional light: 50° elevation, from 30° azimuth. Its
// intensity matches the player's default exposure (1.0) for mid-grey surfaces.
constexpr float kSunElevationRadians = 0.8726646f;
constexpr float kSunAzimuthRadians = 0.5235988f;
constexpr float kSunIntensityLux = 3.0f;

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

// Column-major 4x4 in double: world transforms of deep hierarchies far from the origin keep
// their precision until the final float bounds.
struct Mat4d {
    double m[16];
};

Mat4d trs(const Vec3& t, const Vec4& q, const Vec3& s) {
    double x = q.x, y = q.y, z = q.z, w = q.w;
    double n = std::sqrt(x * x + y * y + z * z + w * w);
    if (n > 0) x /= n, y /= n, z /= n, w /= n;
    else x = y = z = 0, w = 1;
    Mat4d r{};
    r.m[0] = (1 - 2 * (y * y + z * z)) * s.x;
    r.m[1] = (2 * (x * y + z * w)) * s.x;
    r.m[2] = (2 * (x * z - y * w)) * s.x;
    r.m[4] = (2 * (x * y - z * w)) * s.y;
    r.m[5] = (1 - 2 * (x * x + z * z)) * s.y;
    r.m[6] = (2 * (y * z + x * w)) * s.y;
    r.m[8] = (2 * (x * z + y * w)) * s.z;
    r.m[9] = (2 * (y * z - x * w)) * s.z;
    r.m[10] = (1 - 2 * (x * x + y * y)) * s.z;
    r.m[12] = t.x;
    r.m[13] = t.y;
    r.m[14] = t.z;
    r.m[15] = 1;
    return r;
}

Mat4d multiply(const Mat4d& a, const Mat4d& b) {
    Mat4d r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row)
            for (int k = 0; k < 4; ++k) r.m[c * 4 + row] += a.m[k * 4 + row] * b.m[c * 4 + k];
    return r;
}

Aabb transformBounds(const Mat4d& m, const Aabb& b) {
    Aabb out;
    if (b.min.x > b.max.x) return out;
    for (int i = 0; i < 8; ++i) {
        double p[3] = {(i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                       (i & 4) ? b.max.z : b.min.z};
        double r[3];
        for (int k = 0; k < 3; ++k)
            r[k] = m.m[k] * p[0] + m.m[4 + k] * p[1] + m.m[8 + k] * p[2] + m.m[12 + k];
        out.grow({float(r[0]), float(r[1]), float(r[2])});
    }
    return out;
}

// A sphere through a transform: the centre moves, the radius grows by the largest axis scale,
// so the result still contains everything the original did.
Sphere transformSphere(const Mat4d& m, const Sphere& s) {
    if (!(s.radius > 0)) return {};
    double c[3];
    for (int k = 0; k < 3; ++k)
        c[k] = m.m[k] * s.center.x + m.m[4 + k] * s.center.y + m.m[8 + k] * s.center.z +
               m.m[12 + k];
    double maxScale = 0;
    for (int col = 0; col < 3; ++col)
        maxScale = std::max(maxScale, std::sqrt(m.m[col * 4] * m.m[col * 4] +
                                                 m.m[col * 4 + 1] * m.m[col * 4 + 1] +
                                                 m.m[col * 4 + 2] * m.m[col * 4 + 2]));
    return {{float(c[0]), float(c[1]), float(c[2])}, float(s.radius * maxScale)};
}

// The world bounds of a node's mesh: of every EXT_mesh_gpu_instancing copy when it has them.
Aabb instancedBounds(const Mat4d& node, const std::vector<InstanceTransform>& instances,
                     const Aabb& mesh) {
    if (instances.empty()) return transformBounds(node, mesh);
    Aabb out;
    for (const InstanceTransform& t : instances) {
        const Aabb b = transformBounds(multiply(node, trs(t.translation, t.rotation, t.scale)), mesh);
        if (b.min.x > b.max.x) continue;
        out.grow(b.min);
        out.grow(b.max);
    }
    return out;
}

// A sphere holding every copy's sphere: centred on their centres' box, as large as the farthest.
Sphere instancedSphere(const Mat4d& node, const std::vector<InstanceTransform>& instances,
                       const Sphere& mesh) {
    if (instances.empty()) return transformSphere(node, mesh);
    std::vector<Sphere> copies;
    Aabb centres;
    for (const InstanceTransform& t : instances) {
        const Sphere s = transformSphere(multiply(node, trs(t.translation, t.rotation, t.scale)), mesh);
        if (!(s.radius > 0)) continue;
        copies.push_back(s);
        centres.grow(s.center);
    }
    if (copies.empty()) return {};
    const Vec3 c{(centres.min.x + centres.max.x) / 2, (centres.min.y + centres.max.y) / 2,
                 (centres.min.z + centres.max.z) / 2};
    double radius = 0;
    for (const Sphere& s : copies) {
        const double dx = s.center.x - c.x, dy = s.center.y - c.y, dz = s.center.z - c.z;
        radius = std::max(radius, std::sqrt(dx * dx + dy * dy + dz * dz) + s.radius);
    }
    return {c, float(radius)};
}

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
    if (!needs.gi) sum.omitted.push_back("GI programs: gi.enabled is not true (pnb-convert --gi)");
    if (!needs.ibl)
        sum.omitted.push_back(
            "environment (no --environment or --sky): no sky light, IBL programs, cube map or SH");
}

// The node that places light `light` (the first one, as the player takes it), or -1.
int nodeOfLight(const IrScene& scene, size_t light) {
    for (size_t i = 0; i < scene.nodes.size(); ++i)
        if (scene.nodes[i].light == int(light)) return int(i);
    return -1;
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

Result<ConvertSummary, ConvertError> convertScene(const ConvertSettings& s,
                                                  const ProgressFn& progress) {
    ConvertSummary sum;
    StageClock clock(sum.stages);
    auto report = [&](const char* stage, size_t done, size_t total) {
        if (progress) progress(stage, done, total);
    };

    // The sidecar first: it may name the environment (the command line's wins).
    MaterialOverrides overrides;
    std::string sidecar = s.sidecar;
    if (sidecar.empty() && !s.noSidecar && fs::exists(defaultSidecarPath(s.input)))
        sidecar = defaultSidecarPath(s.input);
    // Inputs are regular files: a FIFO or a device named here would block the read forever.
    const std::vector<RoleFile> given = {{s.input, "the input"},
                                         {s.noSidecar ? "" : sidecar, "the sidecar"},
                                         {s.environment.image, "the environment image"},
                                         {s.cameraPath, "the camera path"}};
    if (Status st = checkInputs(given); !isOk(st))
        return ConvertError{ConvertErrorKind::Input, st.message};
    if (!sidecar.empty() && !s.noSidecar) {
        auto loaded = loadSidecar(sidecar);
        if (!loaded) return loaded.error();
        overrides = std::move(*loaded);
    }
    EnvironmentSettings env = s.environment;
    if (!env.any() && overrides.environment) {
        env.image = overrides.environment->image;
        env.sky = overrides.environment->sky;
        if (overrides.environment->turbidity) env.skyTurbidity = *overrides.environment->turbidity;
        if (overrides.environment->groundAlbedo) env.skyGroundAlbedo = *overrides.environment->groundAlbedo;
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
    std::vector<RoleFile> outputs = {{s.output, "the output"}, {s.depfile, "the dependency file"}};
    outputs.insert(outputs.end(), s.alsoWrites.begin(), s.alsoWrites.end());
    const std::vector<RoleFile> named = {{s.input, "the input"},
                                         {s.noSidecar ? "" : sidecar, "the sidecar"},
                                         {env.image, "the environment image"},
                                         {s.cameraPath, "the camera path"}};
    if (Status st = checkOutputs(named, outputs); !isOk(st)) return outputError(st.message);
    if (Status st = checkInputs(named); !isOk(st)) // the sidecar's environment image
        return ConvertError{ConvertErrorKind::Input, st.message};

    // [SECTION] import
    clock.start("import");
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
    { // the files the textures will be read from (a glTF or MTL may name a FIFO too)
        std::vector<RoleFile> read;
        for (const std::string& d : scene.dependencies) read.push_back({d, "a file the scene names"});
        for (const IrImage& img : scene.images) read.push_back({img.path, "an image the scene names"});
        if (Status st = checkInputs(read); !isOk(st))
            return ConvertError{ConvertErrorKind::Input, s.input + ": " + st.message};
    }
    clock.stop();

    // The image decoder module's load (dynamic linking of OpenImageIO), when an image needs it,
    // overlaps materials and meshes; processTextures waits for it if it is not done by then. The
    // future joins at return.
    std::future<void> decoderLoad;
    if (std::any_of(scene.images.begin(), scene.images.end(), imageNeedsDecoderModule) ||
        (!env.image.empty() && imageNeedsDecoderModule(IrImage{"environment", env.image, {}, {}})))
        decoderLoad = std::async(std::launch::async, loadImageDecoder);

    // [SECTION] materials
    clock.start("materials");
    if (!sidecar.empty() && !s.noSidecar) sum.dependencies.push_back(sidecar);
    auto resolvedResult = resolveMaterials(scene, overrides);
    if (!resolvedResult) return resolvedResult.error();
    ResolvedMaterials& materials = *resolvedResult;
    for (const std::string& w : materials.warnings) sum.warnings.push_back(w);
    clock.stop();

    // [SECTION] meshes
    clock.start("meshes");
    // Meshes left without primitives by the importer (only points or lines, which we do not
    // draw) are dropped and their node references cleared: nothing is written for them.
    std::vector<int> meshRemap(scene.meshes.size(), -1);
    {
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
    }
    std::vector<std::optional<ProcessedMesh>> meshes(scene.meshes.size());
    std::vector<MeshStats> meshStats(scene.meshes.size());
    std::vector<std::optional<ConvertError>> meshErrors(scene.meshes.size());
    report("meshes", 0, scene.meshes.size());
    parallelFor(scene.meshes.size(), s.jobs, [&](size_t i) {
        auto r = processMesh(scene.meshes[i], materials.meshNeeds[i], s.mesh, meshStats[i]);
        if (r) meshes[i] = std::move(*r);
        else meshErrors[i] = r.error();
    });
    for (size_t i = 0; i < scene.meshes.size(); ++i) {
        if (meshErrors[i]) return *meshErrors[i]; // the first failing mesh, deterministically
        const MeshStats& st = meshStats[i];
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
            sum.warnings.push_back("mesh '" + scene.meshes[i].name +
                                   "': a normal map needs tangents but a primitive has no UVs; "
                                   "its tangents are arbitrary");
        if (st.nonFiniteTriangles)
            sum.warnings.push_back("mesh '" + scene.meshes[i].name + "': dropped " +
                                   std::to_string(st.nonFiniteTriangles) +
                                   " triangles with non-finite positions");
    }
    report("meshes", scene.meshes.size(), scene.meshes.size());
    clock.stop();

    // [SECTION] textures
    clock.start("textures");
    report("textures", 0, materials.textures.size());
    TextureSettings textureSettings = s.texture;
    textureSettings.jobs = s.jobs;
    auto texturesResult = processTextures(materials.textures, textureSettings);
    if (!texturesResult) return texturesResult.error();
    std::vector<ProcessedTexture>& textures = *texturesResult;
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
    clock.stop();

    // [SECTION] scene graph: lights, cameras, nodes, defaults
    clock.start("scene");
    bool hasSun = std::any_of(scene.lights.begin(), scene.lights.end(),
                              [](const IrLight& l) { return l.type == LightType::Directional; });
    // The default environment goes with a source that has no light of its own (before the
    // default sun): a scene that lights itself (a lamp in a closed room) keeps its look.
    const bool sourceHasLights = !scene.lights.empty();
    std::vector<bool> generatedLight(scene.lights.size(), false);
    // World bounds first: the default camera and path frame them.
    std::vector<Mat4d> world(scene.nodes.size());
    Aabb sceneBounds;
    std::vector<Aabb> nodeBounds(scene.nodes.size());
    std::vector<Sphere> nodeSpheres(scene.nodes.size());
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const IrNode& n = scene.nodes[i];
        Mat4d local = trs(n.translation, n.rotation, n.scale);
        world[i] = n.parent >= 0 ? multiply(world[size_t(n.parent)], local) : local;
        if (n.mesh >= 0 && size_t(n.mesh) < meshes.size()) {
            nodeBounds[i] = instancedBounds(world[i], n.instances, meshes[size_t(n.mesh)]->bounds);
            nodeSpheres[i] = instancedSphere(world[i], n.instances, meshes[size_t(n.mesh)]->boundingSphere);
            if (nodeBounds[i].min.x <= nodeBounds[i].max.x) {
                sceneBounds.grow(nodeBounds[i].min);
                sceneBounds.grow(nodeBounds[i].max);
            }
        }
    }
    Vec3 center{0, 0, 0};
    float radius = 1;
    if (sceneBounds.min.x <= sceneBounds.max.x) {
        center = {(sceneBounds.min.x + sceneBounds.max.x) / 2,
                  (sceneBounds.min.y + sceneBounds.max.y) / 2,
                  (sceneBounds.min.z + sceneBounds.max.z) / 2};
        Vec3 e{sceneBounds.max.x - center.x, sceneBounds.max.y - center.y,
               sceneBounds.max.z - center.z};
        radius = std::max(std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z), 1e-3f);
    }
    if (!hasSun) {
        IrLight sun;
        sun.name = "default-sun";
        sun.type = LightType::Directional;
        sun.color = {1.0f, 0.97f, 0.92f};
        sun.intensity = kSunIntensityLux;
        scene.lights.push_back(sun);
        generatedLight.push_back(true);
        Vec3 toSun{std::cos(kSunElevationRadians) * std::sin(kSunAzimuthRadians),
                   std::sin(kSunElevationRadians),
                   std::cos(kSunElevationRadians) * std::cos(kSunAzimuthRadians)};
        IrNode node;
        node.name = "default-sun";
        node.translation = {center.x + toSun.x * 2 * radius, center.y + toSun.y * 2 * radius,
                            center.z + toSun.z * 2 * radius};
        node.rotation = lookAtRotation(node.translation, center); // shines down its -Z
        node.light = int(scene.lights.size() - 1);
        scene.nodes.push_back(node);
        world.push_back(trs(node.translation, node.rotation, node.scale));
        nodeBounds.emplace_back();
        nodeSpheres.emplace_back();
        sum.defaultSun = true; // a summary line (ConvertSummary::added), not a warning
    }
    if (scene.cameras.empty()) {
        // Where the default orbit starts (camera_path.h "framing"): the bounding sphere inside
        // the frustum with a 10 % margin, near and far planes from the sphere.
        const Framing framing = frameBounds(sceneBounds);
        IrCamera cam;
        cam.name = "default-camera";
        cam.yfovRadians = kDefaultYfovRadians;
        cam.znear = framing.znear;
        cam.zfar = framing.zfar;
        scene.cameras.push_back(cam);
        IrNode node;
        node.name = "default-camera";
        node.translation = framingPosition(framing, 0.0f);
        node.rotation = lookAtRotation(node.translation, framing.center);
        node.camera = 0;
        scene.nodes.push_back(node);
        world.push_back(trs(node.translation, node.rotation, node.scale));
        nodeBounds.emplace_back();
        nodeSpheres.emplace_back();
        sum.defaultCamera = true;
    }
    // After the default sun, before anything reads the lights: ranges, shadow flags and the
    // kMaxLights cap (which remaps node.light) are decided here, once.
    processLights(scene, generatedLight, s.lights, sum.warnings);
    std::vector<PathSpec> paths;
    if (!s.cameraPath.empty()) {
        auto p = loadCameraPath(s.cameraPath);
        if (!p) return p.error();
        paths.push_back(std::move(*p));
        sum.dependencies.push_back(s.cameraPath);
    } else {
        paths.push_back(defaultCameraPath(sceneBounds));
        sum.defaultPath = true;
    }
    clock.stop();

    // [SECTION] environment: after the lights, since the sky follows the scene's sun (the
    // default one if the converter added it)
    std::optional<BakedEnvironment> ownEnvironment;
    const BakedEnvironment* environment = nullptr;
    float sunIlluminance = 0;
    if (!env.any() && s.defaultEnvironment && !sourceHasLights) {
        // The neutral studio (environment.h "default-studio"), baked once per process.
        clock.start("environment");
        environment = &defaultStudioEnvironment(s.jobs);
        sum.defaultEnvironment = true;
        clock.stop();
    }
    if (env.any()) {
        clock.start("environment");
        report("environment", 0, 1); // the bake can take a while (--specular-size 2048)
        const auto environmentStart = std::chrono::steady_clock::now();
        RadianceImage radiance;
        std::string envName;
        EnvironmentSource source = EnvironmentSource::Image;
        std::optional<PreethamSkyParams> sky;
        if (!env.image.empty()) {
            auto loaded = loadRadianceImage(env.image, s.texture.maxMemoryBytes);
            if (!loaded) return loaded.error();
            radiance = std::move(*loaded);
            for (std::string& w : radiance.warnings) sum.warnings.push_back(std::move(w));
            envName = fs::path(env.image).filename().string();
            sum.dependencies.push_back(env.image);
        } else {
            // The sun: the first directional light that casts shadows, else the first
            // directional (every directional casts shadows, processLights, so the two agree
            // today). Towards the sun is its node's +Z axis: lights shine down -Z.
            int sunLight = -1;
            for (size_t i = 0; i < scene.lights.size() && sunLight < 0; ++i)
                if (scene.lights[i].type == LightType::Directional) sunLight = int(i);
            PreethamSkyParams p;
            p.turbidity = env.skyTurbidity;
            p.groundAlbedo = glm::dvec3(env.skyGroundAlbedo);
            if (sunLight >= 0) {
                const IrLight& l = scene.lights[size_t(sunLight)];
                if (int node = nodeOfLight(scene, size_t(sunLight)); node >= 0) {
                    const Mat4d& m = world[size_t(node)];
                    glm::dvec3 z(m.m[8], m.m[9], m.m[10]);
                    if (glm::length(z) > 0) p.sunDirection = glm::normalize(z);
                }
                sunIlluminance = l.intensity;
            }
            // The model is in physical units (a clear sky is ~10^4 nits), a scene's sun in any
            // (the default sun is 3 lux): bake it beside its physical sun, whose light the
            // ground below the horizon reflects too, in the light's colour, then scale the
            // whole sky by (the scene's sun) / (that physical sun). Sky and sun then keep their
            // physical ratio under one exposure (FORMAT.md "ENVM").
            const double physicalSun = lighting::preethamSunIlluminance(p.turbidity, p.sunDirection);
            const glm::dvec3 colour = sunLight >= 0 ? glm::dvec3(scene.lights[size_t(sunLight)].color.x,
                                                                 scene.lights[size_t(sunLight)].color.y,
                                                                 scene.lights[size_t(sunLight)].color.z)
                                                    : glm::dvec3(1.0);
            p.sunIlluminance = colour * physicalSun;
            sky = p;
            radiance = bakePreethamSky(p, env.skyWidth);
            const float scale = float(double(sunIlluminance) / physicalSun);
            for (float& v : radiance.rgb) v *= scale;
            envName = "preetham";
            source = EnvironmentSource::AnalyticSky;
        }
        auto baked = bakeEnvironment(radiance, env, source, envName, s.jobs,
                                     sky ? &*sky : nullptr);
        if (!baked) return baked.error();
        if (sky) baked->envm.sunIlluminance = sunIlluminance; // the light's lux, not a channel
        // The summary's time is the whole stage: loading or baking the sky image too.
        baked->summary.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - environmentStart).count();
        ownEnvironment = std::move(*baked);
        environment = &*ownEnvironment;
        report("environment", 1, 1);
        clock.stop();
    }

    // [SECTION] shaders
    clock.start("shaders");
    SceneShaderNeeds needs;
    needs.ibl = environment != nullptr;
    // Any shadow-casting light, sun or lamp: point and spot shadows use the same SHADOWS define.
    // (The default sun makes this true for every scene today; it stays right without it.)
    const bool shadowLight = std::any_of(scene.lights.begin(), scene.lights.end(),
                                         [](const IrLight& l) { return l.castsShadows; });
    for (const Material& m : materials.materials) {
        needs.shadows |= shadowLight && m.castsShadows;
        needs.maskedCasters |= shadowLight && m.castsShadows && m.alphaMode == AlphaMode::Mask;
    }
    for (const auto& [key, value] : s.renderSettings)
        if (key == "gi.enabled") needs.gi = value == "true"; // the last assignment wins
    ShaderPlan plan = planShaders(materials.materials, materials.features, needs);
    if (s.validateShaders) {
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
    }
    for (const ProgramVariant& v : plan.programs) sum.programs.push_back(describeVariant(v));
    describeOmissions(materials, plan, needs, sum);
    clock.stop();

    // [SECTION] assemble
    clock.start("write");
    SceneBuilder b;
    Scene& out = b.scene;
    out.info.name = b.intern(fs::path(s.input).stem().string());
    out.info.generator = b.intern(kGenerator);
    out.info.source = b.intern(fs::path(s.input).filename().string());
    out.info.bounds = sceneBounds;
    for (const auto& [key, value] : s.renderSettings)
        out.settings.entries.push_back({b.intern(key), b.intern(value)});

    if (auto r = appendShaderPrograms(plan, builtinShaderFiles(), b); !r) return r.error();
    for (size_t i = 0; i < textures.size(); ++i) {
        ProcessedTexture& t = textures[i];
        TextureDesc desc = t.desc;
        desc.name = b.intern(materials.textures[i].name);
        out.textures.push_back(desc);
        for (uint32_t level = 0; level < t.levels.size(); ++level)
            out.textureMips.push_back({uint32_t(i), level, std::max(1u, desc.width >> level),
                                       std::max(1u, desc.height >> level), Blob(t.levels[level])});
        sum.textureBytes += [&] {
            uint64_t n = 0;
            for (const auto& l : t.levels) n += l.size();
            return n;
        }();
        if (t.psnrDb > 0)
            sum.minTexturePsnrDb =
                sum.minTexturePsnrDb == 0 ? t.psnrDb : std::min(sum.minTexturePsnrDb, t.psnrDb);
    }
    // The environment's textures follow the materials' (whose indices materials already hold).
    if (environment) {
        sum.environment = appendEnvironment(b, *environment, environment->summary.name);
        // The default one is baked once per process: this conversion's time is its stage's.
        if (sum.defaultEnvironment)
            for (const StageTiming& t : sum.stages)
                if (t.stage == "environment") sum.environment->seconds = t.seconds;
    }
    std::set<uint16_t> layers;
    for (size_t i = 0; i < materials.materials.size(); ++i) {
        Material m = materials.materials[i];
        m.name = b.intern(materials.names[i]);
        m.program = plan.materialProgram[i];
        out.materials.push_back(m);
        if (m.shadingPath == ShadingPath::Deferred) {
            ++sum.deferredMaterials;
            layers.insert(m.layerPriority);
        } else {
            ++sum.forwardMaterials;
        }
    }
    sum.deferredLayers.assign(layers.begin(), layers.end());
    for (size_t i = 0; i < meshes.size(); ++i) {
        const ProcessedMesh& pm = *meshes[i];
        Mesh m = toContainerMesh(
            pm, b.intern(pm.name.empty() ? "mesh" + std::to_string(i) : pm.name));
        for (const OwnedStream& st : pm.streams) sum.meshBytes += st.bytes.size();
        sum.meshBytes += pm.indices.size();
        for (Submesh& sm : m.submeshes)
            if (sm.material == kNone) sm.material = uint32_t(materials.defaultMaterial);
        sum.submeshes += m.submeshes.size();
        if (s.mesh.proxies && hasLevelChains(m)) {
            // Coarse first: the proxy for the first frame, the detail once it is drawn.
            out.meshes.push_back(buildCoarseProxy(m, b));
            out.meshDetails.push_back({uint32_t(i), m});
        } else {
            out.meshes.push_back(m);
        }
    }
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const IrLight& l = scene.lights[i];
        out.lights.lights.push_back(Light{b.intern(l.name), l.type, l.color, l.intensity, l.range,
                                          l.innerConeRadians, l.outerConeRadians, l.castsShadows,
                                          generatedLight[i]});
    }
    for (const IrCamera& c : scene.cameras)
        out.cameras.cameras.push_back(Camera{b.intern(c.name), c.projection, c.yfovRadians,
                                             c.aspectRatio, c.znear, c.zfar, c.xmag, c.ymag});
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const IrNode& n = scene.nodes[i];
        Node node;
        node.name = b.intern(n.name);
        node.parent = n.parent >= 0 ? uint32_t(n.parent) : kNone;
        node.translation = n.translation;
        node.rotation = n.rotation;
        node.scale = n.scale;
        node.mesh = n.mesh >= 0 ? uint32_t(n.mesh) : kNone;
        node.light = n.light >= 0 ? uint32_t(n.light) : kNone;
        node.camera = n.camera >= 0 ? uint32_t(n.camera) : kNone;
        node.worldBounds = nodeBounds[i];
        node.worldSphere = nodeSpheres[i];
        out.nodes.nodes.push_back(node);
        if (!n.instances.empty() && node.mesh != kNone) {
            out.nodes.instances.push_back(NodeInstances{uint32_t(i), n.instances});
            sum.instances += n.instances.size();
        }
    }
    for (const PathSpec& p : paths)
        out.cameraPaths.push_back(CameraPath{b.intern(p.name), p.interpolation, p.loop, p.keys});

    // The format library re-checks every cross-reference before anything reaches the disk.
    if (Status st = validateScene(out); !isOk(st))
        return ConvertError{ConvertErrorKind::Input,
                            s.input + ": internal consistency check failed: " + st.message};

    WriteOptions wo;
    wo.checksums = s.checksums;
    // Shared by every conversion of the process: a batch compresses the shader sources, which
    // most inputs share, once (compression_memo.h; the bytes written are the same).
    static const auto memo = std::make_shared<CompressionMemo>();
    wo.compressionMemo = memo;
    wo.lock = s.outputLock;
    std::vector<RoleFile> read;
    for (const std::string& d : sum.dependencies) read.push_back({d, "a file the conversion read"});
    if (Status st = checkOutputs(read, outputs); !isOk(st)) return outputError(st.message);
    auto writer = Writer::create(s.output, wo);
    if (!writer) return outputError(writer.error().message);
    Status st = writeScene(*writer, out, s.compressBulk ? Compression::Zstd : Compression::None);
    if (isOk(st)) st = writer->commit();
    if (!isOk(st)) return outputError(st.message);
    sum.outputBytes = writer->size();
    clock.stop();

    sum.meshes = out.meshes.size();
    sum.nodes = out.nodes.nodes.size();
    sum.materials = out.materials.size();
    sum.textures = out.textures.size();
    sum.lights = out.lights.lights.size();
    sum.cameras = out.cameras.cameras.size();
    sum.cameraPaths = out.cameraPaths.size();
    if (!s.depfile.empty()) {
        auto d = writeDepfile(s, sum.dependencies);
        if (!d) return d.error();
    }
    return sum;
}

} // namespace pnb::converter
