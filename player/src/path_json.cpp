// Camera-path keyframe JSON: the converter's schema, read and written by the player.
#include "pnb_player/path_json.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "pnb/atomic_file.h"

namespace pnb::player {

namespace {

using Json = nlohmann::json;

bool readVec(const Json& j, size_t n, double* out) {
    if (!j.is_array() || j.size() != n) return false;
    for (size_t i = 0; i < n; ++i) {
        if (!j[i].is_number()) return false;
        out[i] = j[i].get<double>();
        if (!std::isfinite(out[i])) return false;
    }
    return true;
}

// The converter's lookAtRotation (converter/src/camera_path.cpp): the camera looks down its local
// -Z with +Y up, or +Z up when the view is vertical.
glm::dquat lookAtRotation(const glm::dvec3& eye, const glm::dvec3& target) {
    glm::dvec3 forward = glm::normalize(target - eye);
    glm::dvec3 up = std::fabs(forward.y) > 0.999 ? glm::dvec3(0, 0, forward.y > 0 ? 1.0 : -1.0)
                                                 : glm::dvec3(0, 1, 0);
    glm::dvec3 z = -forward;
    glm::dvec3 x = glm::normalize(glm::cross(up, z));
    glm::dvec3 y = glm::cross(z, x);
    return glm::normalize(glm::quat_cast(glm::dmat3(x, y, z)));
}

// The shortest decimal that reads back as `f` ("0.1", not 0.10000000149011612): the file stays
// readable and reading it as float gives `f` exactly.
double shortest(float f) {
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf - 1, f);
    *r.ptr = '\0';
    return std::strtod(buf, nullptr);
}

} // namespace

PlayResult<ScenePath> readPathJson(const std::string& file) {
    auto fail = [&](const std::string& what) { return PlayError{PlayErrorKind::Input, file + ": " + what}; };
    std::ifstream in(file, std::ios::binary);
    if (!in) return fail("cannot open the camera path file");
    Json doc = Json::parse(in, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return fail("not a JSON object");
    ScenePath sp;
    CameraPath& p = sp.path;
    if (doc.contains("name") && !doc["name"].is_string()) return fail("name must be a string");
    sp.name = doc.value("name", std::string("path"));
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
        double pos[3], v[4];
        if (!k.contains("position") || !readVec(k["position"], 3, pos))
            return fail(where + ".position must be [x, y, z] of finite numbers");
        key.position = {float(pos[0]), float(pos[1]), float(pos[2])};
        glm::dvec3 eye(key.position.x, key.position.y, key.position.z);
        glm::dquat q;
        if (k.contains("target")) {
            if (!readVec(k["target"], 3, v)) return fail(where + ".target must be [x, y, z]");
            glm::dvec3 target{float(v[0]), float(v[1]), float(v[2])};
            if (target == eye) return fail(where + ".target equals the position");
            q = lookAtRotation(eye, target);
        } else if (k.contains("rotation")) {
            if (!readVec(k["rotation"], 4, v)) return fail(where + ".rotation must be [x, y, z, w]");
            q = glm::dquat(v[3], v[0], v[1], v[2]);
            if (!(glm::length(q) > 1e-6)) return fail(where + ".rotation has zero length");
            q = glm::normalize(q);
        } else {
            return fail(where + " needs a \"target\" or a \"rotation\"");
        }
        key.rotation = {float(q.x), float(q.y), float(q.z), float(q.w)};
        if (k.contains("yfov_degrees") && !k["yfov_degrees"].is_number())
            return fail(where + ".yfov_degrees must be a number");
        float fovDegrees = k.value("yfov_degrees", 45.8f);
        if (!(fovDegrees > 1 && fovDegrees < 179)) return fail(where + ".yfov_degrees out of (1, 179)");
        key.yfovRadians = fovDegrees * 3.14159265f / 180.0f;
        p.keys.push_back(key);
    }
    return sp;
}

std::string pathJsonText(const ScenePath& sp) {
    const CameraPath& p = sp.path;
    // One key per line, as the hand-written paths in assets_src/paths are laid out.
    std::string out = "{\n  \"name\": " + Json(sp.name).dump() + ",\n  \"interpolation\": \"" +
                      (p.interpolation == Interpolation::Linear ? "linear" : "catmull-rom") +
                      "\",\n  \"loop\": " + (p.loop ? "true" : "false") + ",\n  \"keys\": [";
    for (size_t i = 0; i < p.keys.size(); ++i) {
        const CameraKey& k = p.keys[i];
        // yfov_degrees: the converter multiplies by float pi/180, so store the float that gives
        // back the key's radians.
        nlohmann::ordered_json key = {{"time", shortest(k.timeSeconds)},
                    {"position", {shortest(k.position.x), shortest(k.position.y), shortest(k.position.z)}},
                    {"rotation", {shortest(k.rotation.x), shortest(k.rotation.y), shortest(k.rotation.z),
                                  shortest(k.rotation.w)}},
                    {"yfov_degrees", shortest(k.yfovRadians / (3.14159265f / 180.0f))}};
        out += std::string(i ? "," : "") + "\n    " + key.dump();
    }
    out += "\n  ]\n}\n";
    return out;
}

PlayResult<Done> writePathJson(const std::string& file, const ScenePath& path) {
    std::string text = pathJsonText(path);
    Status s = writeFileAtomic(file, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    if (!isOk(s)) return PlayError{PlayErrorKind::Io, s.describe()};
    return Done{};
}

} // namespace pnb::player
