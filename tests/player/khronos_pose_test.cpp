// The posed-frame target on real models: CesiumMan (a skin), Fox (a skin, three clips)
// and AnimatedMorphCube (morph targets), converted by pnb-convert, posed by the player on the GPU
// at a time inside a clip, and compared with the same instant computed on the CPU straight from
// the glTF (gltf_cpu_pose.h: tinygltf's accessors, independent of the converter and of
// pnb/animation_pose.h). The converter welds and reorders vertices, so the two are compared as
// point sets, both ways: every vertex the player drew lies on a vertex of the glTF's pose and
// every vertex of the glTF's pose was drawn. Skipped without ../shared/khronos.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>
#include <unistd.h>

#include "gltf_cpu_pose.h"
#include "pnb_converter/convert.h"
#include "posed_frame.h"

namespace pnb::player::test {

namespace {

namespace fs = std::filesystem;

fs::path khronosModel(const std::string& relative) {
    fs::path dir = PNB_KHRONOS_DIR;
    if (const char* env = std::getenv("PNB_KHRONOS_DIR")) dir = env;
    return dir / relative;
}

// The largest distance from a point of `from` to its nearest point of `to` (brute force: the
// models have a few thousand vertices).
double farthestNearest(const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to) {
    double worst = 0;
    for (const glm::dvec3& p : from) {
        double best = INFINITY;
        for (const glm::dvec3& q : to) best = std::min(best, glm::dot(p - q, p - q));
        worst = std::max(worst, best);
    }
    return std::sqrt(worst);
}

std::vector<glm::dvec3> unique(std::vector<glm::dvec3> v) {
    std::sort(v.begin(), v.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    });
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return v;
}

struct Model {
    const char* name;
    const char* file;
    int clip;
    double time;
};

void checkModel(const Model& m) {
    const fs::path model = khronosModel(m.file);
    if (!fs::exists(model)) GTEST_SKIP() << model << " not found (../shared/khronos): skipped";
    const fs::path dir = fs::temp_directory_path() / ("pnb-render-test-" + std::to_string(::getpid())) / "khronos-pose";
    fs::create_directories(dir);
    converter::ConvertSettings cs;
    cs.input = model.string();
    cs.output = (dir / (std::string(m.name) + ".pnb")).string();
    cs.jobs = 1;
    cs.validateShaders = false;
    cs.noSidecar = true;
    auto converted = converter::convertScene(cs);
    ASSERT_TRUE(converted.ok()) << converted.error().message;

    const PosedFrameCheck gpu = checkPosedFrame(cs.output, m.time, std::to_string(m.clip));
    ASSERT_EQ(gpu.error, "");
    ASSERT_GT(gpu.deformedNodes, 0u);
    std::string error;
    const std::vector<glm::dvec3> truth = unique(gltfPosedPositions(model.string(), m.clip, m.time, &error));
    ASSERT_EQ(error, "");
    ASSERT_FALSE(truth.empty());
    const std::vector<glm::dvec3> rest = unique(gltfPosedPositions(model.string(), -1, 0, &error));

    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::dvec3& p : truth) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const double size = glm::length(hi - lo);
    const std::vector<glm::dvec3> drawn = unique(gpu.worldPositions);
    const double drawnToTruth = farthestNearest(drawn, truth) / size;
    const double truthToDrawn = farthestNearest(truth, drawn) / size;
    // The pose moves the model: the same comparison against the rest pose fails by far.
    const double drawnToRest = farthestNearest(drawn, rest) / size;
    std::printf("%s at %.2f s of clip %d: %zu vertices drawn; farthest from the glTF's pose %.2e, glTF to drawn "
                "%.2e, drawn to the rest pose %.2e (of the model's size %.3g); GPU vs CPU library %.2e\n",
                m.name, m.time, m.clip, drawn.size(), drawnToTruth, truthToDrawn, drawnToRest, size, gpu.positionError);
    EXPECT_LT(drawnToTruth, 1e-4) << m.name << ": a drawn vertex is that far (of the model's size) from the glTF's pose";
    EXPECT_LT(truthToDrawn, 1e-4) << m.name << ": a vertex of the glTF's pose was not drawn";
    EXPECT_GT(drawnToRest, 1e-2) << m.name << ": the pose at " << m.time << " s does not differ from the rest pose";
    EXPECT_LT(gpu.positionError, 1e-5) << m.name << ": GPU against pnb::deformVertices";
    EXPECT_EQ(gpu.outsideBounds, 0u) << m.name;
}

} // namespace

TEST(KhronosPose, CesiumManWalksAsTheGltfSays) { checkModel({"CesiumMan", "CesiumMan/glTF-Binary/CesiumMan.glb", 0, 0.7}); }
TEST(KhronosPose, FoxRunsAsTheGltfSays) { checkModel({"Fox", "Fox/glTF-Binary/Fox.glb", 2, 0.35}); }
TEST(KhronosPose, AnimatedMorphCubeMorphsAsTheGltfSays) {
    checkModel({"AnimatedMorphCube", "AnimatedMorphCube/glTF/AnimatedMorphCube.gltf", 0, 1.25});
}

} // namespace pnb::player::test
