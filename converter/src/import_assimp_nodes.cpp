// converter/src/import_assimp_nodes.cpp — node transforms (matrix → TRS, the file's axes →
// +Y up) and the lights and cameras hung from nodes. A step of the assimp importer
// (import_assimp_internal.h): everything here is about where things are, not what they are.
//
// Index: [SECTION] math, [SECTION] axes, [SECTION] lights and cameras
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "import_assimp_internal.h"
#include "import_paths.h"

namespace pnb::converter::assimp_detail {

using namespace import_detail;

// [SECTION] math

bool finite(const aiMatrix4x4& m) {
    for (unsigned row = 0; row < 4; ++row) {
        for (unsigned col = 0; col < 4; ++col) {
            if (!std::isfinite(m[row][col])) return false;
        }
    }
    return true;
}

namespace {

aiVector3D normalizedOr(aiVector3D v, aiVector3D fallback) {
    const float len = v.Length();
    return len > 1e-12f && std::isfinite(len) ? v / len : fallback;
}

// Unit quaternion (xyzw) of a rotation matrix given by its columns. Shepperd's method: divide by
// the largest of the four candidates, so near-180-degree rotations stay accurate.
Vec4 quaternionFromColumns(const aiVector3D& x, const aiVector3D& y, const aiVector3D& z) {
    const float m00 = x.x, m10 = x.y, m20 = x.z;
    const float m01 = y.x, m11 = y.y, m21 = y.z;
    const float m02 = z.x, m12 = z.y, m22 = z.z;
    const float trace = m00 + m11 + m22;
    Vec4 q;
    if (trace > 0) {
        const float s = std::sqrt(trace + 1.0f) * 2.0f;
        q = {(m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25f * s};
    } else if (m00 > m11 && m00 > m22) {
        const float s = std::sqrt(1.0f + m00 - m11 - m22) * 2.0f;
        q = {0.25f * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s};
    } else if (m11 > m22) {
        const float s = std::sqrt(1.0f + m11 - m00 - m22) * 2.0f;
        q = {(m01 + m10) / s, 0.25f * s, (m12 + m21) / s, (m02 - m20) / s};
    } else {
        const float s = std::sqrt(1.0f + m22 - m00 - m11) * 2.0f;
        q = {(m02 + m20) / s, (m12 + m21) / s, 0.25f * s, (m10 - m01) / s};
    }
    const float len = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!(len > 0) || !std::isfinite(len)) return {0, 0, 0, 1};
    // One sign for equal rotations keeps the output deterministic for equal inputs.
    const float sign = q.w < 0 ? -1.0f : 1.0f;
    return {sign * q.x / len, sign * q.y / len, sign * q.z / len, sign * q.w / len};
}

} // namespace

// Column lengths are the scale; a negative determinant (mirroring) goes into scale.x so the
// rotation stays proper. assimp's matrices are row-major with column vectors (a4,b4,c4 =
// translation).
Trs decompose(aiMatrix4x4 m) {
    Trs out;
    // Loaders that invert or multiply matrices (ASE) leave a bottom row like (0 0 0 0.99999994):
    // a homogeneous factor, divided out exactly. Only a non-zero d1..d3 is a real projection.
    const float w = m.d4;
    out.exact = w != 0 && std::abs(m.d1) + std::abs(m.d2) + std::abs(m.d3) <= 1e-6f * std::abs(w);
    if (w != 0 && std::isfinite(1.0f / w) && w != 1.0f) {
        for (unsigned row = 0; row < 3; ++row) {
            for (unsigned col = 0; col < 4; ++col) m[row][col] /= w;
        }
    }
    out.translation = {m.a4, m.b4, m.c4};
    aiVector3D cx(m.a1, m.b1, m.c1), cy(m.a2, m.b2, m.c2), cz(m.a3, m.b3, m.c3);
    float sx = cx.Length(), sy = cy.Length(), sz = cz.Length();
    const float det = cx * (cy ^ cz); // triple product
    if (det < 0) sx = -sx;
    out.scale = {sx, sy, sz};
    if (std::abs(sx) < 1e-20f || sy < 1e-20f || sz < 1e-20f) return out; // no rotation to find
    cx /= sx;
    cy /= sy;
    cz /= sz;
    const float kOrthoTolerance = 1e-3f;
    if (std::abs(cx * cy) > kOrthoTolerance || std::abs(cy * cz) > kOrthoTolerance ||
        std::abs(cz * cx) > kOrthoTolerance) {
        out.exact = false;
    }
    out.rotation = quaternionFromColumns(cx, cy, cz);
    return out;
}

namespace {

// Rotation taking the IR's local -Z (where lights shine and cameras look) to `forward` and +Y
// towards `up`. A zero forward means -Z; an up parallel to forward is replaced.
Vec4 lookRotation(aiVector3D forward, aiVector3D up) {
    const aiVector3D f = normalizedOr(forward, aiVector3D(0, 0, -1));
    const aiVector3D z = -f;
    aiVector3D u = normalizedOr(up, aiVector3D(0, 1, 0));
    if (std::abs(u * f) > 0.999f) {
        u = std::abs(f.y) < 0.9f ? aiVector3D(0, 1, 0) : aiVector3D(1, 0, 0);
    }
    const aiVector3D x = normalizedOr(u ^ z, aiVector3D(1, 0, 0));
    const aiVector3D y = z ^ x;
    return quaternionFromColumns(x, y, z);
}

} // namespace

// [SECTION] axes

// Basis change from the file's axes to +Y-up right-handed (header block), or nullopt when the
// file says nothing or already is +Y-up.
std::optional<aiMatrix4x4> axisConversion(Context& ctx) {
    const aiMetadata* meta = ctx.scene->mMetaData;
    auto getInt = [&](const char* key) -> std::optional<int32_t> {
        int32_t v = 0;
        if (meta != nullptr && meta->Get(std::string(key), v)) return v;
        return std::nullopt;
    };
    const auto up = getInt("UpAxis"), upSign = getInt("UpAxisSign");
    const auto front = getInt("FrontAxis"), frontSign = getInt("FrontAxisSign");
    const auto coord = getInt("CoordAxis"), coordSign = getInt("CoordAxisSign");
    aiMatrix4x4 m;
    if (up && upSign && front && frontSign && coord && coordSign) {
        const int32_t axes[3] = {*coord, *up, *front};
        const int32_t signs[3] = {*coordSign, *upSign, *frontSign};
        bool valid = true, used[3] = {false, false, false};
        for (int i = 0; i < 3; ++i) {
            valid = valid && axes[i] >= 0 && axes[i] <= 2 && !used[axes[i]] &&
                    (signs[i] == 1 || signs[i] == -1);
            if (valid) used[axes[i]] = true;
        }
        if (!valid) {
            ctx.warn(format("axis metadata (up %d%+d, front %d%+d, coord %d%+d) is not a basis; "
                            "ignored", *up, *upSign, *front, *frontSign, *coord, *coordSign));
            return std::nullopt;
        }
        // Row i of the basis change picks the file axis that becomes IR axis i (x = coord/right,
        // y = up, z = front).
        m = aiMatrix4x4(0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
        for (int row = 0; row < 3; ++row) m[row][axes[row]] = float(signs[row]);
        m.d4 = 1;
    } else {
        aiString sourceFormat;
        const bool blender = meta != nullptr &&
                             meta->Get(std::string("SourceAsset_Format"), sourceFormat) &&
                             std::strncmp(sourceFormat.C_Str(), "Blender 3D", 10) == 0;
        if (!blender) return std::nullopt;
        // Blender: +Z up, -Y front → IR y = z, z = -y.
        m = aiMatrix4x4(1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1);
    }
    if (m.IsIdentity()) return std::nullopt;
    if (m.Determinant() < 0) {
        ctx.warn("the file's axes are left-handed; the root node mirrors them (negative scale)");
    }
    return m;
}

// [SECTION] lights and cameras

namespace {

// The node a light or camera hangs from: assimp names it after the light/camera. When the
// source also gives a local position/orientation, a child node carries it, because the IR's
// lights and cameras sit at their node's origin looking down -Z.
int attachmentNode(Context& ctx, const std::map<std::string, int>& nodeByName,
                   const std::string& name, const aiVector3D& position, const Vec4& rotation,
                   bool isLight) {
    int parent = -1;
    if (auto it = nodeByName.find(name); it != nodeByName.end()) {
        parent = it->second;
    } else {
        ctx.warn(format("%s '%s' has no node; placed at the origin", isLight ? "light" : "camera",
                        name.c_str()));
    }
    const bool identity = position == aiVector3D(0, 0, 0) &&
                          std::abs(rotation.w) > 1.0f - 1e-6f;
    if (parent >= 0 && identity) {
        IrNode& node = ctx.out->nodes[size_t(parent)];
        if ((isLight ? node.light : node.camera) < 0) return parent;
    }
    IrNode child;
    child.name = name;
    child.parent = parent;
    child.translation = {position.x, position.y, position.z};
    child.rotation = rotation;
    ctx.out->nodes.push_back(std::move(child));
    return int(ctx.out->nodes.size() - 1);
}

} // namespace

void convertLights(Context& ctx, const std::map<std::string, int>& nodeByName) {
    bool unitsNoted = false;
    for (unsigned i = 0; i < ctx.scene->mNumLights; ++i) {
        const aiLight* src = ctx.scene->mLights[i];
        if (src == nullptr) continue;
        IrLight light;
        light.name = str(src->mName);
        const std::string what = format("light '%s'", light.name.c_str());
        switch (src->mType) {
        case aiLightSource_DIRECTIONAL: light.type = LightType::Directional; break;
        case aiLightSource_POINT: light.type = LightType::Point; break;
        case aiLightSource_SPOT: light.type = LightType::Spot; break;
        default:
            ctx.warn(what + ": ambient, area and undefined lights are not supported; dropped");
            continue;
        }
        // assimp's colour is colour x intensity; split it so the colour is at most 1.
        const aiColor3D& c = src->mColorDiffuse;
        const float peak = std::max({c.r, c.g, c.b});
        if (!std::isfinite(peak) || peak <= 0) {
            ctx.warn(what + ": black or invalid colour; imported with intensity 0");
            light.intensity = 0;
        } else {
            light.color = {c.r / peak, c.g / peak, c.b / peak};
            light.intensity = peak;
        }
        if (!unitsNoted) {
            ctx.warn("lights: the source's intensities have no physical unit; copied as "
                     "lux/candela unchanged");
            unitsNoted = true;
        }
        if (light.type != LightType::Directional) {
            // 1 / (c + l d + q d^2): the range is where that falls to 1/256 (invisible in 8-bit
            // output). No distance term → unlimited range.
            const double kc = src->mAttenuationConstant, kl = src->mAttenuationLinear,
                         kq = src->mAttenuationQuadratic, target = 256.0;
            double range = 0;
            if (kq > 0) range = (-kl + std::sqrt(kl * kl - 4 * kq * (kc - target))) / (2 * kq);
            else if (kl > 0) range = (target - kc) / kl;
            if (std::isfinite(range) && range > 0) {
                light.range = float(range);
                ctx.warn(format("%s: attenuation (constant %g, linear %g, quadratic %g) "
                                "converted to range %g; the falloff becomes inverse-square",
                                what.c_str(), kc, kl, kq, range));
            }
        }
        if (light.type == LightType::Spot) {
            // assimp's cone angles are full angles; the IR's (glTF's) are half angles.
            float outer = src->mAngleOuterCone * 0.5f, inner = src->mAngleInnerCone * 0.5f;
            const float kHalfPi = 1.5707963f;
            if (!std::isfinite(outer) || outer <= 0) outer = 0.7853982f;
            if (!std::isfinite(inner) || inner < 0) inner = 0;
            if (outer > kHalfPi) {
                ctx.warn(format("%s: cone wider than 180 degrees clamped", what.c_str()));
                outer = kHalfPi;
            }
            light.outerConeRadians = outer;
            light.innerConeRadians = std::min(inner, outer);
        }
        const bool needsDirection = light.type != LightType::Point;
        const Vec4 rotation = needsDirection ? lookRotation(src->mDirection, src->mUp)
                                             : Vec4{0, 0, 0, 1};
        const aiVector3D position = light.type == LightType::Directional ? aiVector3D(0, 0, 0)
                                                                         : src->mPosition;
        const int node = attachmentNode(ctx, nodeByName, light.name, position, rotation, true);
        ctx.out->lights.push_back(std::move(light));
        ctx.out->nodes[size_t(node)].light = int(ctx.out->lights.size() - 1);
    }
}

void convertCameras(Context& ctx, const std::map<std::string, int>& nodeByName) {
    for (unsigned i = 0; i < ctx.scene->mNumCameras; ++i) {
        const aiCamera* src = ctx.scene->mCameras[i];
        if (src == nullptr) continue;
        IrCamera camera;
        camera.name = str(src->mName);
        const std::string what = format("camera '%s'", camera.name.c_str());
        const float aspect = std::isfinite(src->mAspect) && src->mAspect > 0 ? src->mAspect : 0;
        camera.aspectRatio = aspect;
        if (std::isfinite(src->mOrthographicWidth) && src->mOrthographicWidth > 0) {
            camera.projection = Projection::Orthographic;
            camera.xmag = src->mOrthographicWidth;
            camera.ymag = aspect > 0 ? src->mOrthographicWidth / aspect : src->mOrthographicWidth;
        } else {
            // assimp documents mHorizontalFOV as the half angle, but its Collada, FBX and Blend
            // loaders store the full angle (Blender's default camera arrives as 0.8576 rad =
            // 49.1 degrees, its full horizontal FOV), so it is taken as full.
            float hfov = src->mHorizontalFOV;
            if (!std::isfinite(hfov) || hfov <= 0 || hfov >= 3.14159f) {
                ctx.warn(format("%s: invalid field of view %g; using 0.8 rad", what.c_str(), hfov));
                hfov = 0.8f;
            }
            if (aspect > 0) {
                camera.yfovRadians = 2.0f * std::atan(std::tan(hfov * 0.5f) / aspect);
            } else {
                ctx.warn(what + ": no aspect ratio; the vertical field of view is taken equal to "
                                "the horizontal one");
                camera.yfovRadians = hfov;
            }
        }
        camera.znear = std::isfinite(src->mClipPlaneNear) && src->mClipPlaneNear > 0
                           ? src->mClipPlaneNear : 0.1f;
        camera.zfar = std::isfinite(src->mClipPlaneFar) && src->mClipPlaneFar > camera.znear
                          ? src->mClipPlaneFar : 0; // 0 = infinite
        const Vec4 rotation = lookRotation(src->mLookAt, src->mUp);
        const int node =
            attachmentNode(ctx, nodeByName, camera.name, src->mPosition, rotation, false);
        ctx.out->cameras.push_back(std::move(camera));
        ctx.out->nodes[size_t(node)].camera = int(ctx.out->cameras.size() - 1);
    }
}

} // namespace pnb::converter::assimp_detail
