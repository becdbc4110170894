// Camera-path keyframe files (pnb/path_json.h).
#include "pnb/path_json.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

namespace pnb {

namespace {

using Json = nlohmann::json;

bool readVec(const Json& j, size_t n, float* out) {
    if (!j.is_array() || j.size() != n) return false;
    for (size_t i = 0; i < n; ++i) {
        if (!j[i].is_number()) return false;
        out[i] = j[i].get<float>();
        if (!std::isfinite(out[i])) return false;
    }
    return true;
}

Vec3 sub(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 normalize(Vec3 v) {
    float l = std::sqrt(dot(v, v));
    return l > 0 ? Vec3{v.x / l, v.y / l, v.z / l} : Vec3{0, 0, -1};
}

// Quaternion of the rotation matrix with columns x, y, z (Shepperd's method).
Vec4 quatFromBasis(Vec3 x, Vec3 y, Vec3 z) {
    float trace = x.x + y.y + z.z;
    Vec4 q;
    if (trace > 0) {
        float s = std::sqrt(trace + 1.0f) * 2;
        q = {(y.z - z.y) / s, (z.x - x.z) / s, (x.y - y.x) / s, 0.25f * s};
    } else if (x.x > y.y && x.x > z.z) {
        float s = std::sqrt(1.0f + x.x - y.y - z.z) * 2;
        q = {0.25f * s, (y.x + x.y) / s, (z.x + x.z) / s, (y.z - z.y) / s};
    } else if (y.y > z.z) {
        float s = std::sqrt(1.0f + y.y - x.x - z.z) * 2;
        q = {(y.x + x.y) / s, 0.25f * s, (z.y + y.z) / s, (z.x - x.z) / s};
    } else {
        float s = std::sqrt(1.0f + z.z - x.x - y.y) * 2;
        q = {(z.x + x.z) / s, (z.y + y.z) / s, 0.25f * s, (x.y - y.x) / s};
    }
    float l = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return {q.x / l, q.y / l, q.z / l, q.w / l};
}

// The shortest decimal that reads back as `f` ("0.1", not 0.10000000149011612): the file stays
// readable and reading it as float gives `f` exactly.
double shortest(float f) {
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf - 1, f);
    *r.ptr = '\0';
    return std::strtod(buf, nullptr);
}

constexpr float kRadiansPerDegree = 3.14159265f / 180.0f;

} // namespace

Vec4 lookAtRotation(Vec3 eye, Vec3 target) {
    Vec3 forward = normalize(sub(target, eye));
    Vec3 up = std::fabs(forward.y) > 0.999f ? Vec3{0, 0, forward.y > 0 ? 1.0f : -1.0f}
                                            : Vec3{0, 1, 0};
    Vec3 z = {-forward.x, -forward.y, -forward.z}; // the camera looks down -Z
    Vec3 x = normalize(cross(up, z));
    Vec3 y = cross(z, x);
    return quatFromBasis(x, y, z);
}

Result<CameraPathFile> readCameraPathJson(const std::string& file) {
    auto fail = [&](const std::string& what) {
        return makeError(FormatError::BadPayload, 0, "%s: %s", file.c_str(), what.c_str());
    };
    std::ifstream in(file, std::ios::binary);
    if (!in)
        return makeError(FormatError::IoError, 0, "%s: cannot open the camera path file",
                         file.c_str());
    Json doc = Json::parse(in, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return fail("not a JSON object");
    CameraPathFile p;
    if (doc.contains("name") && !doc["name"].is_string()) return fail("name must be a string");
    p.name = doc.value("name", p.name);
    if (doc.contains("interpolation") && !doc["interpolation"].is_string())
        return fail("interpolation must be a string");
    std::string interpolation = doc.value("interpolation", std::string("catmull-rom"));
    if (interpolation == "linear") p.interpolation = Interpolation::Linear;
    else if (interpolation != "catmull-rom")
        return fail("interpolation '" + interpolation + "' is not linear or catmull-rom");
    if (doc.contains("loop") && !doc["loop"].is_boolean()) return fail("loop must be true/false");
    p.loop = doc.value("loop", false);
    if (!doc.contains("keys") || !doc["keys"].is_array() || doc["keys"].size() < 2)
        return fail("needs \"keys\": an array of at least two keyframes");
    for (size_t i = 0; i < doc["keys"].size(); ++i) {
        const Json& k = doc["keys"][i];
        std::string where = "keys[" + std::to_string(i) + "]";
        if (!k.is_object()) return fail(where + " is not an object");
        CameraKey key;
        if (!k.contains("time") || !k["time"].is_number())
            return fail(where + ".time is missing or not a number");
        key.timeSeconds = k["time"].get<float>();
        if (!std::isfinite(key.timeSeconds)) return fail(where + ".time is not finite");
        if (!p.keys.empty() && !(key.timeSeconds > p.keys.back().timeSeconds))
            return fail(where + ".time does not increase");
        if (!k.contains("position") || !readVec(k["position"], 3, &key.position.x))
            return fail(where + ".position must be [x, y, z] of finite numbers");
        if (k.contains("target")) {
            Vec3 target;
            if (!readVec(k["target"], 3, &target.x)) return fail(where + ".target must be [x, y, z]");
            if (dot(sub(target, key.position), sub(target, key.position)) == 0)
                return fail(where + ".target equals the position");
            key.rotation = lookAtRotation(key.position, target);
        } else if (k.contains("rotation")) {
            if (!readVec(k["rotation"], 4, &key.rotation.x))
                return fail(where + ".rotation must be [x, y, z, w]");
            Vec4& q = key.rotation;
            float l = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
            if (!(l > 1e-6f)) return fail(where + ".rotation has zero length");
            q = {q.x / l, q.y / l, q.z / l, q.w / l};
        } else {
            return fail(where + " needs a \"target\" or a \"rotation\"");
        }
        if (k.contains("yfov_degrees") && !k["yfov_degrees"].is_number())
            return fail(where + ".yfov_degrees must be a number");
        float fovDegrees = k.value("yfov_degrees", 45.8f);
        if (!(fovDegrees > 1 && fovDegrees < 179)) return fail(where + ".yfov_degrees out of (1, 179)");
        key.yfovRadians = fovDegrees * kRadiansPerDegree;
        p.keys.push_back(key);
    }
    return p;
}

std::string cameraPathJsonText(const CameraPathFile& p) {
    // One key per line, as the hand-written paths in assets_src/paths are laid out.
    std::string out = "{\n  \"name\": " + Json(p.name).dump() + ",\n  \"interpolation\": \"" +
                      (p.interpolation == Interpolation::Linear ? "linear" : "catmull-rom") +
                      "\",\n  \"loop\": " + (p.loop ? "true" : "false") + ",\n  \"keys\": [";
    for (size_t i = 0; i < p.keys.size(); ++i) {
        const CameraKey& k = p.keys[i];
        // yfov_degrees: the reader multiplies by float pi/180, so store the float that gives
        // back the key's radians.
        nlohmann::ordered_json key = {
            {"time", shortest(k.timeSeconds)},
            {"position", {shortest(k.position.x), shortest(k.position.y), shortest(k.position.z)}},
            {"rotation", {shortest(k.rotation.x), shortest(k.rotation.y), shortest(k.rotation.z),
                          shortest(k.rotation.w)}},
            {"yfov_degrees", shortest(k.yfovRadians / kRadiansPerDegree)}};
        out += std::string(i ? "," : "") + "\n    " + key.dump();
    }
    out += "\n  ]\n}\n";
    return out;
}

} // namespace pnb
