// The sun and light-placement rules the player and the reference share (pnb_lighting/scene_lights.h).
#include <cmath>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "pnb_lighting/scene_lights.h"

namespace pnb::lighting {
namespace {

Light light(LightType type, bool casts) {
    Light l;
    l.type = type;
    l.castsShadows = casts;
    return l;
}

int shadowing(const std::vector<Light>& ls) {
    return shadowingSunIndex(ls.size(), [&](size_t i) -> const Light& { return ls[i]; });
}
int bounced(const std::vector<Light>& ls) {
    return bouncedSunIndex(ls.size(), [&](size_t i) -> const Light& { return ls[i]; });
}

TEST(SceneLights, TheShadowingSunIsTheFirstDirectionalLightThatCastsShadows) {
    const std::vector<Light> ls{light(LightType::Point, true), light(LightType::Directional, false),
                                light(LightType::Spot, true), light(LightType::Directional, true),
                                light(LightType::Directional, true)};
    EXPECT_EQ(shadowing(ls), 3);
    EXPECT_EQ(bounced(ls), 3); // GI bounces the light the shadows follow
}

TEST(SceneLights, WithoutAShadowingSunGiBouncesTheFirstDirectionalLight) {
    const std::vector<Light> ls{light(LightType::Spot, true), light(LightType::Directional, false),
                                light(LightType::Directional, false)};
    EXPECT_EQ(shadowing(ls), -1);
    EXPECT_EQ(bounced(ls), 1);
    EXPECT_EQ(bounced({light(LightType::Point, true)}), -1);
    EXPECT_EQ(bounced({}), -1);
}

TEST(SceneLights, ALightShinesDownItsNodesMinusZ) {
    const glm::dvec3 identity = lightTravel(glm::dmat4(1.0));
    EXPECT_EQ(identity, glm::dvec3(0, 0, -1));
    // Turned 90 degrees about +Y, -Z becomes -X; scale and translation do not change the direction.
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(1e7, -3, 2));
    m = glm::rotate(m, glm::radians(90.0), glm::dvec3(0, 1, 0));
    m = glm::scale(m, glm::dvec3(1e-6, 4, 1e6));
    const glm::dvec3 d = lightTravel(m);
    EXPECT_NEAR(d.x, -1.0, 1e-12);
    EXPECT_NEAR(d.y, 0.0, 1e-12);
    EXPECT_NEAR(d.z, 0.0, 1e-12);
    // A zero-scale node has no direction: NaN, which every range or cone test rejects.
    const glm::dvec3 none = lightTravel(glm::scale(glm::dmat4(1.0), glm::dvec3(0.0)));
    EXPECT_TRUE(std::isnan(none.x) && std::isnan(none.y) && std::isnan(none.z));
}

} // namespace
} // namespace pnb::lighting
