// Node transforms in double (see pnb/node_transform.h).
#include "pnb/node_transform.h"

#include <cmath>

namespace pnb {

Matrix4d nodeLocalMatrix(const Node& n) {
    double x = n.rotation.x, y = n.rotation.y, z = n.rotation.z, w = n.rotation.w;
    const double length = std::sqrt(x * x + y * y + z * z + w * w);
    if (length > 0 && std::isfinite(length)) {
        x /= length, y /= length, z /= length, w /= length;
    } else {
        x = y = z = 0, w = 1;
    }
    // Rotation columns of a unit quaternion, each scaled by that axis' scale.
    const double sx = n.scale.x, sy = n.scale.y, sz = n.scale.z;
    return {(1 - 2 * (y * y + z * z)) * sx, 2 * (x * y + w * z) * sx, 2 * (x * z - w * y) * sx, 0,
            2 * (x * y - w * z) * sy, (1 - 2 * (x * x + z * z)) * sy, 2 * (y * z + w * x) * sy, 0,
            2 * (x * z + w * y) * sz, 2 * (y * z - w * x) * sz, (1 - 2 * (x * x + y * y)) * sz, 0,
            double(n.translation.x), double(n.translation.y), double(n.translation.z), 1};
}

Matrix4d multiply(const Matrix4d& a, const Matrix4d& b) {
    Matrix4d m{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            double sum = 0;
            for (int k = 0; k < 4; ++k) sum += a[k * 4 + r] * b[c * 4 + k];
            m[c * 4 + r] = sum;
        }
    return m;
}

std::vector<MeshInstance> meshInstances(const NodeGraph& graph, const std::vector<Matrix4d>& world) {
    std::vector<MeshInstance> out;
    size_t next = 0; // graph.instances is in node order (readScene checks it)
    for (size_t i = 0; i < graph.nodes.size() && i < world.size(); ++i) {
        if (graph.nodes[i].mesh == kNone) continue;
        while (next < graph.instances.size() && graph.instances[next].node < i) ++next;
        if (next < graph.instances.size() && graph.instances[next].node == i) {
            for (const InstanceTransform& t : graph.instances[next].transforms) {
                Node local;
                local.translation = t.translation;
                local.rotation = t.rotation;
                local.scale = t.scale;
                out.push_back({uint32_t(i), multiply(world[i], nodeLocalMatrix(local))});
            }
        } else {
            out.push_back({uint32_t(i), world[i]});
        }
    }
    return out;
}

std::vector<Matrix4d> nodeWorldMatrices(const NodeGraph& graph) {
    std::vector<Matrix4d> world(graph.nodes.size());
    for (size_t i = 0; i < graph.nodes.size(); ++i) {
        const Node& n = graph.nodes[i];
        const Matrix4d local = nodeLocalMatrix(n);
        world[i] = n.parent != kNone && n.parent < i ? multiply(world[n.parent], local) : local;
    }
    return world;
}

} // namespace pnb
