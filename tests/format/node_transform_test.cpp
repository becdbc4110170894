// Node transforms (pnb/node_transform.h): T * R * S with a normalised quaternion, parents first,
// in double, column-major.
#include <cmath>

#include <gtest/gtest.h>

#include "pnb/node_transform.h"
#include "pnb/texture_transform.h"

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


// EXT_mesh_gpu_instancing (NODE version 2): a node with instances is drawn once per instance, at
// world(node) * TRS_k, and not at the node itself; other nodes once.
TEST(NodeTransform, MeshInstancesPlaceEveryCopyUnderItsNode) {
    NodeGraph g;
    Node parent;
    parent.translation = {10, 0, 0};
    Node instanced;
    instanced.parent = 0;
    instanced.mesh = 0;
    instanced.scale = {2, 2, 2};
    Node plain;
    plain.mesh = 1;
    plain.translation = {0, 5, 0};
    g.nodes = {parent, instanced, plain};
    NodeInstances in;
    in.node = 1;
    in.transforms.resize(3);
    in.transforms[1].translation = {1, 0, 0};
    in.transforms[2].translation = {0, 0, 1};
    in.transforms[2].rotation = {0, 0.70710678f, 0, 0.70710678f}; // 90 degrees about +Y
    g.instances = {in};
    const std::vector<MeshInstance> copies = meshInstances(g, nodeWorldMatrices(g));
    ASSERT_EQ(copies.size(), 4u);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(copies[size_t(k)].node, 1u);
    EXPECT_EQ(copies[3].node, 2u);
    // world(node 1) = translate(10,0,0) * scale 2; copy 1 is translated by 1 before that scale.
    auto o = apply(copies[0].world, 0, 0, 0);
    EXPECT_DOUBLE_EQ(o[0], 10.0);
    o = apply(copies[1].world, 0, 0, 0);
    EXPECT_DOUBLE_EQ(o[0], 12.0);
    // copy 2: rotated 90 degrees about Y, so its local +X goes to -Z, then +1 z, scaled by 2.
    o = apply(copies[2].world, 1, 0, 0);
    EXPECT_NEAR(o[0], 10.0, 1e-6);
    EXPECT_NEAR(o[2], 0.0, 1e-6);
    o = apply(copies[3].world, 0, 0, 0);
    EXPECT_DOUBLE_EQ(o[1], 5.0);
}

// KHR_texture_transform's own matrix: a rotation of +90 degrees sends u to -v (u' = c u + s v,
// v' = -s u + c v); offset last, scale first. The player's GLSL slotUv is the same formula.
TEST(TextureTransform, RotationRunsAsTheExtensionDefines) {
    const float quarter = 1.5707963f;
    Vec2 r = textureTransformUv({0, 0}, {1, 1}, quarter, {1, 0});
    EXPECT_NEAR(r.x, 0.0f, 1e-6f);
    EXPECT_NEAR(r.y, -1.0f, 1e-6f);
    r = textureTransformUv({0, 0}, {1, 1}, quarter, {0, 1});
    EXPECT_NEAR(r.x, 1.0f, 1e-6f);
    EXPECT_NEAR(r.y, 0.0f, 1e-6f);
    r = textureTransformUv({0.5f, 0.25f}, {2, 3}, 0, {1, 1});
    EXPECT_FLOAT_EQ(r.x, 2.5f);
    EXPECT_FLOAT_EQ(r.y, 3.25f);
    // The extension's example order: scale, then rotate, then offset.
    r = textureTransformUv({1, 0}, {2, 1}, quarter, {1, 0});
    EXPECT_NEAR(r.x, 1.0f, 1e-6f);
    EXPECT_NEAR(r.y, -2.0f, 1e-6f);
}

} // namespace

} // namespace pnb::test
