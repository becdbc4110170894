// pnb-reference's files (reference_io.h): frame.json and the dumped EXR buffers in, images and
// JSON out.
#include "reference_io.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "pnb/atomic_file.h"

namespace pnb::reference_tool {

namespace fs = std::filesystem;

int fail(const Failure& f) {
    std::fprintf(stderr, "Error: %s\n", f.message.c_str());
    return f.exitCode;
}

Expected<Frame> readFrameJson(const std::string& path) {
    auto fail = [&](const std::string& why) { return Failure{kExitInput, path + ": " + why}; };
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return fail("missing (the player writes it with --dump)");
    std::ifstream in(path, std::ios::binary);
    nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) return fail("not a valid JSON object");

    auto vec3 = [&](const char* key, double out[3]) -> std::optional<Failure> {
        auto it = j.find(key);
        if (it == j.end() || !it->is_array() || it->size() != 3)
            return fail(std::string("\"") + key + "\" must be an array of 3 numbers");
        for (size_t i = 0; i < 3; ++i) {
            if (!(*it)[i].is_number()) return fail(std::string("\"") + key + "\" must hold numbers");
            out[i] = (*it)[i].get<double>();
            if (!std::isfinite(out[i])) return fail(std::string("\"") + key + "\" must be finite");
        }
        return std::nullopt;
    };
    auto dimension = [&](const char* key, int& out) -> std::optional<Failure> {
        auto it = j.find(key);
        if (it == j.end() || !it->is_number_integer() || it->get<int64_t>() < 1 ||
            it->get<int64_t>() > 65536)
            return fail(std::string("\"") + key + "\" must be an integer in 1..65536");
        out = int(it->get<int64_t>());
        return std::nullopt;
    };

    Frame f;
    double camera[3], light[3];
    if (auto e = vec3("camera_position", camera)) return *e;
    if (auto it = j.find("shadow_light_index"); it != j.end()) {
        // An index into LGHT; whether it names a point or spot light is checked against the
        // scene once it is read.
        if (!it->is_number_integer() || it->get<int64_t>() < 0 ||
            it->get<int64_t>() > int64_t(UINT32_MAX))
            return fail("\"shadow_light_index\" must be an integer >= 0 (an index into the scene's "
                        "lights), not " +
                        it->dump());
        f.shadowLightIndex = uint32_t(it->get<int64_t>());
    }
    if (auto e = dimension("width", f.width)) return *e;
    if (auto e = dimension("height", f.height)) return *e;
    f.cameraPosition = {camera[0], camera[1], camera[2]};
    if (!f.shadowLightIndex) { // the sun: its direction is the light
        if (auto e = vec3("toward_light", light)) return *e;
        glm::dvec3 l(light[0], light[1], light[2]);
        double length = glm::length(l);
        if (!(length > 1e-12)) return fail("\"toward_light\" must not be zero");
        f.towardLight = glm::vec3(l / length);
    }
    auto optionalNumber = [&](const char* key, std::optional<double>& out) -> std::optional<Failure> {
        auto it = j.find(key);
        if (it == j.end()) return std::nullopt;
        if (!it->is_number() || !std::isfinite(it->get<double>()))
            return fail(std::string("\"") + key + "\" must be a finite number");
        out = it->get<double>();
        return std::nullopt;
    };
    if (auto e = optionalNumber("ibl_rotation_degrees", f.iblRotationDegrees)) return *e;
    if (auto e = optionalNumber("ibl_intensity", f.iblIntensity)) return *e;
    for (auto [key, out] : {std::pair{"yfov", &f.yfov}, {"aspect", &f.aspect}, {"xmag", &f.xmag}, {"ymag", &f.ymag},
                            {"exposure", &f.exposure}})
        if (auto e = optionalNumber(key, *out)) return *e;
    if (auto it = j.find("projection"); it != j.end()) {
        if (!it->is_string() || (*it != "perspective" && *it != "orthographic"))
            return fail("\"projection\" must be \"perspective\" or \"orthographic\"");
        f.projection = it->get<std::string>();
    }
    if (auto it = j.find("camera_world_from_view"); it != j.end()) {
        glm::dmat3 m(1.0);
        bool ok = it->is_array() && it->size() == 3;
        for (size_t c = 0; ok && c < 3; ++c) {
            const auto& column = (*it)[c];
            ok = column.is_array() && column.size() == 3;
            for (size_t r = 0; ok && r < 3; ++r) {
                ok = column[r].is_number() && std::isfinite(column[r].get<double>());
                if (ok) m[int(c)][int(r)] = column[r].get<double>();
            }
        }
        if (!ok) return fail("\"camera_world_from_view\" must be 3 columns of 3 finite numbers");
        f.worldFromView = m;
    }
    if (auto it = j.find("anim"); it != j.end()) {
        const std::string what = "\"anim\" must be an object with \"enabled\" (a boolean), \"clip\" (an integer "
                                 ">= 0 or null), \"clip_name\" (a string) and \"time\" (a finite number)";
        if (!it->is_object()) return fail(what);
        Frame::Animation a;
        if (auto e = it->find("enabled"); e != it->end()) {
            if (!e->is_boolean()) return fail(what);
            a.enabled = e->get<bool>();
        }
        if (auto c = it->find("clip"); c != it->end() && !c->is_null()) {
            if (!c->is_number_integer() || c->get<int64_t>() < 0 || c->get<int64_t>() > int64_t(UINT32_MAX))
                return fail(what + ", not clip " + c->dump());
            a.clip = uint32_t(c->get<int64_t>());
        }
        if (auto n = it->find("clip_name"); n != it->end() && !n->is_null()) {
            if (!n->is_string()) return fail(what);
            a.clipName = n->get<std::string>();
        }
        if (auto t = it->find("time"); t != it->end()) {
            if (!t->is_number() || !std::isfinite(t->get<double>())) return fail(what + ", not time " + t->dump());
            a.time = t->get<double>();
        }
        f.anim = a;
    }
    return f;
}

Expected<FloatImage> readExr(const std::string& path, const std::vector<std::string>& wanted,
                             size_t required, const Frame& frame) {
    auto fail = [&](const std::string& why) { return Failure{kExitInput, path + ": " + why}; };
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return fail("missing (the player writes it with --dump)");
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string why = OIIO::geterror();
        return fail("not a readable image (" + (why.empty() ? std::string("unknown error") : why) + ")");
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width != frame.width || spec.height != frame.height || spec.depth > 1)
        return fail(std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                    " does not match frame.json's " + std::to_string(frame.width) + "x" +
                    std::to_string(frame.height));
    if (size_t(spec.nchannels) < required)
        return fail("has " + std::to_string(spec.nchannels) + " channels, expected at least " +
                    std::to_string(required));
    std::vector<float> all(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data())) {
        std::string why = in->geterror();
        return fail("could not be decoded (" + (why.empty() ? std::string("unknown error") : why) + ")");
    }
    in->close();

    FloatImage img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = int(std::min(wanted.size(), size_t(spec.nchannels)));
    std::vector<int> source(size_t(img.channels));
    for (int c = 0; c < img.channels; ++c) {
        int named = spec.channelindex(wanted[size_t(c)]);
        source[size_t(c)] = named >= 0 ? named : c;
    }
    const size_t pixels = size_t(img.width) * size_t(img.height);
    img.pixels.resize(pixels * size_t(img.channels));
    for (size_t p = 0; p < pixels; ++p)
        for (int c = 0; c < img.channels; ++c)
            img.pixels[p * size_t(img.channels) + size_t(c)] =
                all[p * size_t(spec.nchannels) + size_t(source[size_t(c)])];
    return img;
}
Expected<bool> writeImage(const std::string& path, int width, int height, int channels,
                          OIIO::TypeDesc type, const void* pixels) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput memory(bytes);
    auto out = OIIO::ImageOutput::create(path, &memory);
    if (!out || !out->supports("ioproxy"))
        return Failure{kExitOutput, path + ": OpenImageIO cannot write this format to memory"};
    OIIO::ImageSpec spec(width, height, channels, type);
    if (channels == 1) spec.channelnames = {"Y"};
    if (type == OIIO::TypeDesc::FLOAT) spec.attribute("compression", "zip");
    if (!out->open(path, spec) || !out->write_image(type, pixels) || !out->close())
        return Failure{kExitOutput, path + ": encoding failed (" + out->geterror() + ")"};
    pnb::Status s = pnb::writeFileAtomic(path, bytes);
    if (!pnb::isOk(s)) return Failure{kExitOutput, s.describe()};
    return true;
}

Expected<bool> writeText(const std::string& path, const std::string& text) {
    pnb::Status s = pnb::writeFileAtomic(
        path, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    if (!pnb::isOk(s)) return Failure{kExitOutput, s.describe()};
    return true;
}

} // namespace pnb::reference_tool
