// pnb-flip: FLIP and relative MSE of a test image against a reference image (pnb_reference's
// flip.h and image_error.h), the error map in magma and the figures as JSON.
//
//   pnb-flip TEST REFERENCE [--hdr|--ldr] [--exposure X] [--ppd P] [--out DIR]
//
// Float files (EXR, HDR, float TIFF) are linear radiance; integer files (PNG, 8/16-bit) are
// sRGB-encoded display images. Default mode: --hdr when both are float, else --ldr. --ldr of float
// files shows both through the player's tone map at --exposure (pnb-judge's frame_flip_ldr);
// --hdr of integer files decodes them to linear first. relMSE is always of the linear values.
// Writes DIR/flip.png (magma, black = 0 to pale yellow = 1), DIR/flip.json; with --hdr also
// DIR/flip_exposure.png (grey: which exposure gave each pixel's error, dark = shortest).
//
// Exit codes: 0 ok, 1 usage, 2 input error, 4 output error.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "pnb_cli/options.h"
#include "pnb_reference/flip.h"
#include "pnb_reference/image_error.h"
#include "reference_io.h"

namespace {

using namespace pnb::reference_tool;
namespace ref = pnb::reference;

struct Settings {
    std::vector<std::string> inputs; // TEST, REFERENCE
    std::optional<bool> hdr;         // unset: from the files
    std::optional<double> exposure;
    double ppd = ref::defaultPixelsPerDegree();
    std::string outDir = ".";
    std::string usageError;
};

struct Image {
    int width = 0, height = 0;
    bool linear = false; // a float file: linear radiance
    std::vector<glm::vec3> rgb;
};

Expected<Image> readImage(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string why = OIIO::geterror();
        return Failure{kExitInput, path + ": not a readable image (" +
                                       (why.empty() ? "unknown error" : why) + ")"};
    }
    const OIIO::ImageSpec& spec = in->spec();
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    const auto base = OIIO::TypeDesc::BASETYPE(spec.format.basetype);
    img.linear = base == OIIO::TypeDesc::FLOAT || base == OIIO::TypeDesc::HALF ||
                 base == OIIO::TypeDesc::DOUBLE;
    std::vector<float> all(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    if (spec.depth > 1 || spec.nchannels < 1 ||
        !in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()))
        return Failure{kExitInput, path + ": could not be decoded (" + in->geterror() + ")"};
    const size_t pixels = size_t(spec.width) * size_t(spec.height), n = size_t(spec.nchannels);
    img.rgb.resize(pixels);
    for (size_t p = 0; p < pixels; ++p)
        for (size_t c = 0; c < 3; ++c)
            img.rgb[p][int(c)] = all[p * n + (n >= 3 ? c : 0)]; // grey: one channel
    return img;
}

std::optional<int> parseCommandLine(int argc, char** argv, Settings& s) {
    using pnb::cli::flag;
    using pnb::cli::valued;
    bool help = false;
    auto number = [&s](const char* a, const char* what, double& out) {
        char* end = nullptr;
        out = std::strtod(a, &end);
        if (end == a || *end != '\0' || !std::isfinite(out) || out <= 0)
            s.usageError = std::string(what) + " must be a positive number, not " + a;
        return true;
    };
    const std::vector<pnb::cli::Option> table = {
        flag("", "--hdr",
             "HDR-FLIP: the maximum of LDR-FLIP over the reference's exposure range (EG 2021)",
             [&s](const char*) {
                 s.hdr = true;
                 return true;
             }),
        flag("", "--ldr",
             "LDR-FLIP of the displayed images (float files: the player's tone map at --exposure)",
             [&s](const char*) {
                 s.hdr = false;
                 return true;
             }),
        valued("", "--exposure", "X", "the player's exposure for --ldr of float files (default 1)",
               [&s, number](const char* a) {
                   double v = 0;
                   number(a, "--exposure", v);
                   s.exposure = v;
                   return true;
               }),
        valued("", "--ppd", "P",
               "pixels per degree of the observer (default 67.02: 0.7 m from a 0.7 m, 3840-px "
               "monitor)",
               [&s, number](const char* a) { return number(a, "--ppd", s.ppd); }),
        valued("", "--out", "DIR", "where flip.png and flip.json go (default .)",
               [&s](const char* a) {
                   s.outDir = a;
                   return true;
               }),
        flag("", "-h, --help", "this text",
             [&help](const char*) {
                 help = true;
                 return pnb::cli::Verdict::stopHere();
             }),
    };
    auto positional = [&s](const char* a) {
        s.inputs.emplace_back(a);
        return pnb::cli::Verdict(true);
    };
    std::string error;
    if (auto e = pnb::cli::parse(table, positional, argc, argv)) error = pnb::cli::describe(*e);
    if (help) {
        std::printf(
            "usage: pnb-flip TEST REFERENCE [--hdr|--ldr] [--exposure X] [--ppd P] [--out DIR]\n\n"
            "FLIP (Andersson et al. 2020, 2021) and relative MSE (eps %.2g) of TEST against "
            "REFERENCE.\n"
            "Float files are linear radiance, integer files sRGB display images. See "
            "docs/REFERENCE.md.\n\n"
            "options:\n%s\nexit codes: 0 ok, 1 usage, 2 input error, 4 output error\n",
            ref::kRelMseEpsilon, pnb::cli::helpText(table, {.column = 22}).c_str());
        return kExitOk;
    }
    if (error.empty() && !s.usageError.empty()) error = s.usageError;
    if (error.empty() && s.inputs.size() != 2)
        error = "need TEST and REFERENCE, got " + std::to_string(s.inputs.size()) + " files";
    if (error.empty()) return std::nullopt;
    std::fprintf(stderr, "Error: %s (see --help)\n", error.c_str());
    return kExitUsage;
}

nlohmann::json summaryJson(const ref::ErrorSummary& s) {
    return {{"mean", s.mean},
            {"weighted_median", s.weightedMedian},
            {"weighted_quartile1", s.weightedQuartile1},
            {"weighted_quartile3", s.weightedQuartile3},
            {"min", s.min},
            {"max", s.max}};
}

int run(const Settings& s) {
    Expected<Image> test = readImage(s.inputs[0]), reference = readImage(s.inputs[1]);
    if (!test) return fail(test.error());
    if (!reference) return fail(reference.error());
    if (test->width != reference->width || test->height != reference->height)
        return fail(Failure{kExitInput, s.inputs[0] + " is " + std::to_string(test->width) + "x" +
                                            std::to_string(test->height) + ", " + s.inputs[1] +
                                            " " + std::to_string(reference->width) + "x" +
                                            std::to_string(reference->height)});
    const uint32_t w = uint32_t(test->width), h = uint32_t(test->height);
    const bool floats = test->linear && reference->linear;
    const bool hdr = s.hdr.value_or(floats);
    // Integer files hold sRGB-encoded display values: decode to display-linear.
    for (Image* img : {&*test, &*reference})
        if (!img->linear)
            for (glm::vec3& c : img->rgb)
                c = {ref::srgbToLinear(c.x), ref::srgbToLinear(c.y), ref::srgbToLinear(c.z)};

    nlohmann::json j = {{"test", s.inputs[0]},
                        {"reference", s.inputs[1]},
                        {"width", w},
                        {"height", h},
                        {"ppd", s.ppd}};
    std::vector<float> map;
    std::string what;
    if (hdr) {
        const ref::HdrFlipResult r = ref::hdrFlip(test->rgb, reference->rgb, w, h, s.ppd);
        map = r.error;
        what = "HDR-FLIP over " + std::to_string(r.exposures.count) + " exposures [" +
               std::to_string(r.exposures.start) + ", " + std::to_string(r.exposures.stop) +
               "] stops";
        j["mode"] = "hdr";
        j["exposures"] = {
            {"start", r.exposures.start}, {"stop", r.exposures.stop}, {"count", r.exposures.count}};
        std::vector<uint8_t> grey(r.exposureIndex.size());
        for (size_t p = 0; p < grey.size(); ++p)
            grey[p] = uint8_t(std::lround(255.0 * r.exposureIndex[p] /
                                          std::max(1.0, double(r.exposures.count - 1))));
        if (auto ok = writeImage(s.outDir + "/flip_exposure.png", int(w), int(h), 1,
                                 OIIO::TypeDesc::UINT8, grey.data());
            !ok)
            return fail(ok.error());
    } else if (floats) {
        const double exposure = s.exposure.value_or(1.0);
        map = ref::playerLdrFlip(test->rgb, reference->rgb, w, h, exposure, s.ppd);
        what = "LDR-FLIP through the player's tone map at exposure " + std::to_string(exposure);
        j["mode"] = "ldr";
        j["exposure"] = exposure;
    } else {
        map = ref::ldrFlip(test->rgb, reference->rgb, w, h, s.ppd);
        what = "LDR-FLIP of the sRGB display images";
        j["mode"] = "ldr";
    }
    const ref::ErrorSummary summary = ref::summarizeError(map);
    const ref::RelativeMse rel = ref::relativeMse(test->rgb, reference->rgb);
    j["flip"] = summaryJson(summary);
    j["relmse"] = {{"mean", rel.mean}, {"epsilon", ref::kRelMseEpsilon}, {"pixels", rel.pixels}};
    j["error_map"] = {{"file", "flip.png"},
                      {"colour_map", "magma, 9 stops: black-purple = 0, pale yellow = 1"}};

    std::printf("pnb-flip: %s, %.2f ppd, %ux%u\n", what.c_str(), s.ppd, w, h);
    std::printf(
        "flip: mean %.6f  weighted median %.6f  weighted quartiles %.6f %.6f  min %.6f  max %.6f\n",
        summary.mean, summary.weightedMedian, summary.weightedQuartile1, summary.weightedQuartile3,
        summary.min, summary.max);
    std::printf("relmse: %.6g (eps %.2g, %llu pixels)\n", rel.mean, ref::kRelMseEpsilon,
                static_cast<unsigned long long>(rel.pixels));
    const std::vector<uint8_t> rgb = ref::magmaImage(map);
    if (auto ok = writeImage(s.outDir + "/flip.png", int(w), int(h), 3, OIIO::TypeDesc::UINT8,
                             rgb.data());
        !ok)
        return fail(ok.error());
    if (auto ok = writeText(s.outDir + "/flip.json", j.dump(2) + "\n"); !ok)
        return fail(ok.error());
    return kExitOk;
}

} // namespace

int main(int argc, char** argv) {
    Settings settings;
    if (auto done = parseCommandLine(argc, argv, settings)) return *done;
    std::error_code ec;
    std::filesystem::create_directories(settings.outDir, ec);
    return run(settings);
}
