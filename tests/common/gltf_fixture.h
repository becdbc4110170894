// gltf_fixture.h — small glTF scenes built in test code and converted with the real converter,
// shared by the player and editor tests (header-only; link pnb_assets and pnb_converter).
#pragma once

#include <array>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "pnb/atomic_file.h"
#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/png_writer.h"
#include "pnb_converter/convert.h"

namespace pnb::test {

namespace gltf = pnb::assets::gltf;

// An RGB checker PNG: `a` and `b` colours in 8-texel squares.
inline std::vector<uint8_t> checkerPng(uint32_t size, std::array<uint8_t, 3> a, std::array<uint8_t, 3> b) {
    std::vector<uint8_t> pixels;
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const auto& c = ((x / 8 + y / 8) & 1) ? a : b;
            pixels.insert(pixels.end(), c.begin(), c.end());
        }
    return assets::encodePng(size, size, 3, pixels);
}

// A width x height quad in the XY plane facing +Z; with `uvs`, texture coordinates 0..1
// (glTF's v = 0 at the image's top row).
inline gltf::Primitive quad(float width, float height, uint32_t material, bool uvs = false) {
    gltf::Primitive p;
    float x = width * 0.5f, y = height * 0.5f;
    p.positions = {{-x, -y, 0}, {x, -y, 0}, {x, y, 0}, {-x, y, 0}};
    p.normals.assign(4, {0, 0, 1});
    if (uvs) p.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    p.indices = {0, 1, 2, 0, 2, 3};
    p.material = material;
    return p;
}

// An axis-aligned sx x sy x sz box centred at the origin, counter-clockwise from outside, no UVs.
inline gltf::Primitive box(float sx, float sy, float sz, uint32_t material) {
    gltf::Primitive p;
    p.material = material;
    const float h[3] = {sx * 0.5f, sy * 0.5f, sz * 0.5f};
    for (int axis = 0; axis < 3; ++axis) {
        for (int sign = -1; sign <= 1; sign += 2) {
            gltf::Float3 n{0, 0, 0};
            n[size_t(axis)] = float(sign);
            int u = (axis + 1) % 3, v = (axis + 2) % 3; // (u, v, axis) is right-handed
            auto base = uint32_t(p.positions.size());
            for (int c = 0; c < 4; ++c) {
                float su = (c == 1 || c == 2) ? 1.0f : -1.0f, sv = c >= 2 ? 1.0f : -1.0f;
                gltf::Float3 q{0, 0, 0};
                q[size_t(axis)] = float(sign) * h[axis];
                q[size_t(u)] = su * h[u];
                q[size_t(v)] = sv * h[v];
                p.positions.push_back(q);
                p.normals.push_back(n);
            }
            if (sign > 0) p.indices.insert(p.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
            else p.indices.insert(p.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
        }
    }
    return p;
}

// Adds a node with a one-primitive mesh; returns the node index.
inline uint32_t addObject(gltf::Document& doc, const std::string& name, gltf::Primitive primitive,
                          gltf::Float3 translation, gltf::Float4 rotation = {0, 0, 0, 1}) {
    doc.meshes.push_back({name, {std::move(primitive)}});
    gltf::Node node;
    node.name = name;
    node.mesh = int32_t(doc.meshes.size() - 1);
    node.translation = translation;
    node.rotation = rotation;
    doc.nodes.push_back(node);
    return uint32_t(doc.nodes.size() - 1);
}

// Adds a directional light ("sun", KHR_lights_punctual) of `intensity` lux on a node turned by
// `rotation` (it shines down the node's -Z; gltf::lookRotation(direction) aims it); returns the
// node's index.
inline uint32_t addSun(gltf::Document& doc, float intensity, gltf::Float4 rotation) {
    gltf::Light sun;
    sun.name = "sun";
    sun.intensity = intensity;
    doc.lights.push_back(sun);
    gltf::Node node;
    node.name = "sun";
    node.light = int32_t(doc.lights.size() - 1);
    node.rotation = rotation;
    doc.nodes.push_back(node);
    return uint32_t(doc.nodes.size() - 1);
}

// Writes doc as dir/name.glb (+ dir/name.sidecar.json if given), converts it to dir/name.pnb
// and returns that path. A conversion error fails the test.
inline std::string convertDocument(const std::string& dir, const gltf::Document& doc,
                                   const std::string& name, const std::string& sidecarJson = "",
                                   bool validateShaders = true,
                                   const converter::EnvironmentSettings& environment = {}) {
    std::string glb = dir + "/" + name + ".glb";
    auto bytes = gltf::encodeGlb(doc);
    EXPECT_TRUE(isOk(pnb::writeFileAtomic(glb, bytes)));
    converter::ConvertSettings s;
    s.input = glb;
    s.output = dir + "/" + name + ".pnb";
    s.jobs = 1;
    s.validateShaders = validateShaders;
    s.environment = environment;
    if (!sidecarJson.empty()) {
        s.sidecar = dir + "/" + name + ".sidecar.json";
        std::ofstream(s.sidecar) << sidecarJson;
    } else {
        s.noSidecar = true;
    }
    auto r = converter::convertScene(s);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return s.output;
}

} // namespace pnb::test
