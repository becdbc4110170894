#include <gtest/gtest.h>

#include <cmath>

#include "pnb_converter/mtl_to_pbr.h"

namespace {

using namespace pnb;
using converter::MtlParameters;

Material convert(const MtlParameters& p) {
    Material m;
    converter::applyMtlToPbr(p, m);
    return m;
}

TEST(MtlToPbr, SpecularExponentMapsToRoughness) {
    MtlParameters p;
    p.ns = 2.0f; // alpha = sqrt(2/4) -> roughness = 0.5^(1/4)
    EXPECT_NEAR(convert(p).roughnessFactor, std::pow(0.5f, 0.25f), 1e-6f);
    p.ns = 1000.0f;
    float shiny = convert(p).roughnessFactor;
    p.ns = 10.0f;
    EXPECT_LT(shiny, convert(p).roughnessFactor) << "higher exponent, smoother surface";
    p.ns.reset();
    EXPECT_EQ(convert(p).roughnessFactor, 1.0f);
    p.pr = 0.3f; // the PBR extension wins
    p.ns = 1000.0f;
    EXPECT_FLOAT_EQ(convert(p).roughnessFactor, 0.3f);
}

TEST(MtlToPbr, OpacityComesFromDissolveOrTransparency) {
    MtlParameters p;
    EXPECT_EQ(convert(p).alphaMode, AlphaMode::Opaque);
    p.tr = 0.25f;
    EXPECT_FLOAT_EQ(convert(p).baseColorFactor.w, 0.75f);
    EXPECT_EQ(convert(p).alphaMode, AlphaMode::Blend);
    p.d = 0.5f; // d wins over Tr
    EXPECT_FLOAT_EQ(convert(p).baseColorFactor.w, 0.5f);
}

TEST(MtlToPbr, HostileValuesAreClampedNotPropagated) {
    MtlParameters p;
    p.kd = {2.0f, -1.0f, NAN};
    p.ns = -5.0f;
    p.d = INFINITY;
    p.ke = {NAN, -3.0f, 4.0f};
    p.pm = 7.0f;
    Material m = convert(p);
    EXPECT_EQ(m.baseColorFactor.x, 1.0f);
    EXPECT_EQ(m.baseColorFactor.y, 0.0f);
    EXPECT_EQ(m.baseColorFactor.z, 0.0f);
    EXPECT_EQ(m.baseColorFactor.w, 1.0f) << "non-finite d is ignored";
    EXPECT_EQ(m.roughnessFactor, 1.0f);
    EXPECT_EQ(m.metallicFactor, 1.0f);
    EXPECT_EQ(m.emissiveFactor.x, 0.0f);
    EXPECT_EQ(m.emissiveFactor.y, 0.0f);
    EXPECT_EQ(m.emissiveFactor.z, 4.0f);
}

} // namespace
