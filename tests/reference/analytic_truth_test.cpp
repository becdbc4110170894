// The reference checks itself: scenes whose exact shadow is known (a box floating over a plane, a
// thin pole standing on it, a slab with a slit), at unit scales 1e-6 ... 1e6, 1e7 from the origin,
// and sun elevations 0.5 ... 90 degrees, traced by ShadowTracer alone and compared with the
// analytic answer (a ray against the boxes' exact extents, in double). Exact for every sample
// farther than a pixel's footprint from the shadow boundary, whatever the unit of length.
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/glm.hpp>

#include "pnb_assets/scene_transform.h"
#include "pnb_reference/shadow_tracer.h"
#include "reference_test_util.h"

namespace pnb::reference::test {

namespace {

struct Box {
    glm::dvec3 lo, hi;
};

// The objects in the scene's own unit; every extent is exact in float, so the container holds
// exactly these boxes (up to the unit-root's float scale, applied to the truth below too).
const std::vector<Box>& objects() {
    static const std::vector<Box> boxes = {
        {{-41, 2, -1}, {-39, 4, 1}},             // a box floating 2 above the plane
        {{-0.0625, 0, -0.0625}, {0.0625, 8, 0.0625}}, // a thin pole standing on it
        {{35, 3, -5}, {39.875, 3.25, 5}},        // a slab 3 above it, with a slit 0.25 wide
        {{40.125, 3, -5}, {45, 3.25, 5}},        //   between x = 39.875 and 40.125
    };
    return boxes;
}

gltf::Document analyticScene() {
    gltf::Document doc;
    doc.materials.push_back(material("stone"));
    // A 4096-wide ground: long enough for the 0.5-degree shadows (3.25 / tan 0.5 deg = 372).
    pnb::test::addObject(doc, "ground", pnb::test::quad(4096, 4096, 0), {0, 0, 0}, kFaceUp);
    int k = 0;
    for (const Box& b : objects()) {
        glm::dvec3 size = b.hi - b.lo, centre = (b.lo + b.hi) * 0.5;
        pnb::test::addObject(doc, "object-" + std::to_string(k++),
                             pnb::test::box(float(size.x), float(size.y), float(size.z), 0),
                             {float(centre.x), float(centre.y), float(centre.z)});
    }
    return doc;
}

// Does the ray p + t l (t > 0) meet the box? Slab test in double.
bool rayHitsBox(glm::dvec3 p, glm::dvec3 l, const Box& b) {
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (l[a] == 0) {
            if (p[a] < b.lo[a] || p[a] > b.hi[a]) return false;
            continue;
        }
        double ta = (b.lo[a] - p[a]) / l[a], tb = (b.hi[a] - p[a]) / l[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    return t1 > t0;
}

bool analyticShadow(glm::dvec3 p, glm::dvec3 l, const std::vector<Box>& boxes) {
    for (const Box& b : boxes)
        if (rayHitsBox(p, l, b)) return true;
    return false;
}

glm::dvec3 towardSun(double elevationDegrees, double azimuthDegrees) {
    const double e = elevationDegrees * std::numbers::pi / 180, a = azimuthDegrees * std::numbers::pi / 180;
    return {std::cos(e) * std::cos(a), std::sin(e), -std::cos(e) * std::sin(a)};
}

struct Counts {
    size_t shadowed = 0, lit = 0, boundary = 0, wrong = 0;
};

// Samples the ground around every object's shadow and on the objects' tops; compares the tracer
// with the analytic answer. `unit` = the container's root scale, `origin` its translation.
Counts compare(const Scene& scene, double unit, glm::dvec3 origin, double elevation, double azimuth) {
    // The truth sees the boxes the container holds: unit scale (as the float the node stores)
    // and origin applied in double.
    std::vector<Box> world;
    for (const Box& b : objects()) world.push_back({origin + unit * b.lo, origin + unit * b.hi});
    const glm::dvec3 eye = origin + unit * glm::dvec3(0, 6, 60); // the tracer's origin
    auto tracer = ShadowTracer::build(scene, eye);
    EXPECT_TRUE(tracer.ok());
    if (!tracer.ok()) return {};
    const glm::dvec3 l = towardSun(elevation, azimuth);

    // Deterministic samples (a 64-bit LCG) on the ground in each object's shadow region and
    // around it, and on each object's top face.
    std::vector<glm::dvec3> points;
    uint64_t state = 0x9E3779B97F4A7C15ull;
    auto uniform = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) / double(1ull << 53);
    };
    // Ground samples in each object's shadow frame: along the shadow (biased towards the
    // object, where a low sun's long shadow has its sharpest edges) and across it, a little
    // wider than the object, so about half fall in the shadow at every elevation.
    glm::dvec2 along(-l.x, -l.z);
    along = glm::length(along) > 1e-9 ? glm::normalize(along) : glm::dvec2(1, 0);
    const glm::dvec2 across(-along.y, along.x);
    const double tanElevation = std::tan(elevation * std::numbers::pi / 180);
    for (const Box& b : objects()) {
        const glm::dvec2 centre((b.lo.x + b.hi.x) * 0.5, (b.lo.z + b.hi.z) * 0.5);
        const double radius = 0.5 * glm::length(glm::dvec2(b.hi.x - b.lo.x, b.hi.z - b.lo.z));
        const double length = b.hi.y / std::max(tanElevation, 1e-9) + 2 * radius;
        for (int i = 0; i < 3000; ++i) {
            const double u = uniform(), v = uniform();
            const glm::dvec2 g = centre + (u * u * length) * along + ((2 * v - 1) * 1.5 * radius) * across;
            points.push_back({g.x, 0, g.y});
        }
        for (int i = 0; i < 200; ++i)
            points.push_back({b.lo.x + uniform() * (b.hi.x - b.lo.x), b.hi.y,
                              b.lo.z + uniform() * (b.hi.z - b.lo.z)});
    }
    std::vector<glm::vec3> relative;
    std::vector<glm::dvec3> worldPoints;
    for (const glm::dvec3& p : points) {
        worldPoints.push_back(origin + unit * p);
        relative.push_back(glm::vec3(worldPoints.back() - eye));
    }
    std::vector<float> vis(points.size());
    (*tracer)->visibility(relative, glm::vec3(l), vis);

    Counts counts;
    for (size_t i = 0; i < points.size(); ++i) {
        const glm::dvec3 p = worldPoints[i];
        // A pixel's footprint here: 1/1000 of the distance from the eye (a 60-degree view ~1000
        // pixels across). Samples whose verdict changes within it are on the boundary.
        const double footprint = 1e-3 * glm::length(p - eye);
        const bool truth = analyticShadow(p, l, world);
        bool boundary = false;
        for (glm::dvec3 d : {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0)})
            for (double sign : {-1.0, 1.0})
                boundary |= analyticShadow(p + sign * footprint * d, l, world) != truth;
        // Inside a box (the pole's foot, the slab's faces): not a visible surface point.
        for (const Box& b : world)
            boundary |= glm::all(glm::greaterThan(p, b.lo)) && glm::all(glm::lessThan(p, b.hi));
        if (boundary) {
            ++counts.boundary;
            continue;
        }
        (truth ? counts.shadowed : counts.lit)++;
        if (vis[i] != (truth ? 0.0f : 1.0f)) {
            if (counts.wrong++ < 3)
                ADD_FAILURE() << "unit " << unit << " origin " << origin.x << " elevation " << elevation
                              << ": point (" << points[i].x << ", " << points[i].y << ", " << points[i].z
                              << ") in the unit's scene: tracer " << vis[i] << ", truth "
                              << (truth ? "shadowed" : "lit");
        }
    }
    return counts;
}

TEST(ReferenceAnalytic, ExactAtEveryScaleOriginAndElevation) {
    TempDir dir("analytic");
    struct Placement {
        double unit;
        glm::dvec3 origin;
    };
    const std::vector<Placement> placements = {
        {1e-6, {0, 0, 0}}, {1e-3, {0, 0, 0}}, {1, {0, 0, 0}}, {1e3, {0, 0, 0}}, {1e6, {0, 0, 0}},
        {1, {1e7, 0, -1e7}}, {1e-3, {1e7, 0, 1e7}}, {1e3, {-1e7, 1e7, 1e7}}};
    for (const Placement& at : placements) {
        gltf::Document doc = analyticScene();
        assets::SceneTransform t;
        t.unitScale = at.unit;
        t.origin = {float(at.origin.x), float(at.origin.y), float(at.origin.z)};
        ASSERT_EQ(assets::applySceneTransform(doc, t), "");
        auto loaded = loadPnb(pnb::test::convertDocument(dir.str(), doc, "scene", "", false));
        ASSERT_TRUE(loaded);
        for (double elevation : {0.5, 3.0, 15.0, 45.0, 89.9, 90.0}) {
            SCOPED_TRACE(testing::Message() << "unit " << at.unit << ", origin " << at.origin.x << " "
                                            << at.origin.y << " " << at.origin.z << ", sun "
                                            << elevation << " degrees");
            Counts c = compare(loaded->scene, double(float(at.unit)), at.origin, elevation, 30.0);
            EXPECT_EQ(c.wrong, 0u);
            // Enough decided samples on both sides (the thin pole's shadow is mostly within a
            // footprint of its edges, so about a quarter of all samples are boundary ones).
            EXPECT_GT(c.shadowed, 400u);
            EXPECT_GT(c.lit, 1000u);
            EXPECT_LT(c.boundary, (c.shadowed + c.lit) / 2);
        }
    }
}

} // namespace

} // namespace pnb::reference::test
