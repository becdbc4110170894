// Node transforms (pnb/node_transform.h): T * R * S with a normalised quaternion, parents first,
// in double, column-major.
#include <cmath>

#include <gtest/gtest.h>

#include "pnb/node_transform.h"

namespace pnb::test {

namespace {

// m * (x, y, z, 1)
std::array<double, 3> apply(const Matrix4d& m, double x, double y, double z) {
    std::array<double, 3> out{};
    for (int r = 0; r < 3; ++r) out[size_t(r)] = m[0 * 4 + r] * x + m[1 * 4 + r] * y + m[2 * 4 + r] * z + m[12 + r];
    return out;
}

TEST(NodeTransform, TranslatesRotatesThenScales) {
    Node n;
    n.translation = {10, 20, 30};
    const double h = std::sqrt(0.5);
    n.rotation = {0, float(h), 0, float(h)}; // 90 degrees about +Y: +X goes to -Z
    n.scale = {2, 3, 4};
    auto p = apply(nodeLocalMatrix(n), 1, 1, 1); // scaled (2, 3, 4), rotated (4, 3, -2)
    EXPECT_NEAR(p[0], 14, 1e-6);
    EXPECT_NEAR(p[1], 23, 1e-6);
    EXPECT_NEAR(p[2], 28, 1e-6);

    // A quaternion that is not unit length is normalised; a zero one is the identity.
    n.rotation = {0, float(3 * h), 0, float(3 * h)};
    auto q = apply(nodeLocalMatrix(n), 1, 1, 1);
    EXPECT_NEAR(q[0], 14, 1e-6);
    EXPECT_NEAR(q[2], 28, 1e-6);
    n.rotation = {0, 0, 0, 0};
    auto r = apply(nodeLocalMatrix(n), 1, 1, 1);
    EXPECT_EQ(r, (std::array<double, 3>{12, 23, 34}));
}

TEST(NodeTransform, WorldMatricesComposeParentsFirstInDouble) {
    NodeGraph g;
    Node root, child, grandchild;
    root.translation = {1e7f, 0, -1e7f};
    root.scale = {1e-6f, 1e-6f, 1e-6f};
    child.parent = 0;
    child.translation = {1000, 0, 0};
    grandchild.parent = 1;
    grandchild.translation = {0.5f, 0, 0};
    g.nodes = {root, child, grandchild};
    auto world = nodeWorldMatrices(g);
    ASSERT_EQ(world.size(), 3u);
    // 1e7 + 1e-6 * 1000.5: representable in double to ~2e-9, lost entirely in float.
    auto p = apply(world[2], 0, 0, 0);
    EXPECT_NEAR(p[0], 1e7 + double(1e-6f) * 1000.5, 4e-9);
    EXPECT_NEAR(p[2], -1e7, 4e-9);
    EXPECT_EQ(world[0], nodeLocalMatrix(root));
    EXPECT_EQ(world[1], multiply(world[0], nodeLocalMatrix(child)));
}

} // namespace

} // namespace pnb::test
