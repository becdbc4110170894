// The posed-frame check (posed_frame.h).
#include "posed_frame.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "pnb/animation_pose.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_player/renderer.h"
#include "render_fixture.h"

namespace pnb::player::test {

namespace {

double distance(Vec3 a, Vec3 b) {
    return std::sqrt(double(a.x - b.x) * (a.x - b.x) + double(a.y - b.y) * (a.y - b.y) + double(a.z - b.z) * (a.z - b.z));
}

std::vector<float> readBack(GLuint buffer, size_t wordOffset, size_t floats) {
    std::vector<float> out(floats);
    if (floats) glGetNamedBufferSubData(buffer, GLintptr(wordOffset * 4), GLsizeiptr(floats * 4), out.data());
    return out;
}

} // namespace

PosedFrameCheck checkPosedFrame(const std::string& pnbPath, double time, const std::string& clip) {
    PosedFrameCheck out;
    auto container = Container::open(pnbPath);
    if (!container) return {container.error().message};
    auto cpu = readScene(*container);
    if (!cpu) return {cpu.error().message};
    auto gpu = loadScene(pnbPath);
    if (!gpu) return {gpu.error().message};
    RenderSettings s = settingsForCurrentDriver();
    s.animClip = clip;
    s.animTime = float(time);
    s.animPlay = false;
    s.warmUp = false;
    auto renderer = Renderer::create(**gpu, s);
    if (!renderer) return {renderer.error().message};
    const Aabb& b = cpu->info.bounds;
    const glm::dvec3 centre(0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y), 0.5 * (b.min.z + b.max.z));
    const double radius = std::max(1e-3, distance(b.min, b.max));
    if (auto r = (*renderer)->render(lookAt(centre + glm::dvec3(0, 0.3, 1.5) * radius, centre), 64, 64); !r)
        return {r.error().message};
    glFinish();
    const GpuScene& g = **gpu;
    if (!g.animation) return {"the container has no animation"};

    std::optional<uint32_t> clipIndex;
    if (clip != "none") clipIndex = uint32_t(std::stoul(clip));
    const Pose pose = poseAt(*cpu, clipIndex, time);
    const std::vector<Matrix4d> world = nodeWorldMatrices(pose.graph);
    for (const DeformedNode& d : g.animation->deformed) {
        const DeformedVertices want = deformVertices(*cpu, d.node, pose, world);
        const GLuint posed = g.meshes[d.posedMesh].buffer.id();
        const std::vector<float> positions = readBack(posed, 0, size_t(d.vertexCount) * 3);
        Aabb extent;
        for (const Vec3& p : want.positions) extent.grow(p);
        const double scale = std::max(1e-6, distance(extent.min, extent.max));
        for (size_t v = 0; v < want.positions.size(); ++v)
            out.positionError = std::max(out.positionError,
                                         distance(want.positions[v], {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]}) / scale);
        if (!want.normals.empty()) {
            const std::vector<float> normals = readBack(posed, d.posedNormal, size_t(d.vertexCount) * 3);
            for (size_t v = 0; v < want.normals.size(); ++v)
                out.normalError = std::max(out.normalError,
                                           distance(want.normals[v], {normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]}));
        }
        if (!want.tangents.empty()) {
            const std::vector<float> tangents = readBack(posed, d.posedTangent, size_t(d.vertexCount) * 4);
            for (size_t v = 0; v < want.tangents.size(); ++v) {
                const Vec4& t = want.tangents[v];
                out.tangentError = std::max({out.tangentError, distance({t.x, t.y, t.z}, {tangents[4 * v], tangents[4 * v + 1], tangents[4 * v + 2]}),
                                             std::abs(double(t.w) - tangents[4 * v + 3])});
            }
        }
        for (const DrawItem& item : g.items)
            if (item.node == d.node) {
                for (size_t v = 0; v < d.vertexCount; ++v)
                    out.worldPositions.emplace_back(item.world * glm::dvec4(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2], 1.0));
                break;
            }
        // Every posed vertex, placed in the world, inside the bounds of each of the node's items.
        const glm::dmat4 drawing = glm::make_mat4(drawingMatrix(*cpu, d.node, world).data());
        for (const DrawItem& item : g.items) {
            if (item.node != d.node) continue;
            const glm::dvec3 slack = 1e-5 * (item.boundsMax - item.boundsMin) + glm::dvec3(1e-6);
            for (const Vec3& p : want.positions) {
                const glm::dvec3 w = glm::dvec3(drawing * glm::dvec4(p.x, p.y, p.z, 1.0));
                if (glm::any(glm::lessThan(w, item.boundsMin - slack)) || glm::any(glm::greaterThan(w, item.boundsMax + slack)))
                    ++out.outsideBounds;
            }
        }
        ++out.deformedNodes;
        out.vertices += want.positions.size();
    }
    return out;
}

} // namespace pnb::player::test
