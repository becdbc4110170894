// pnb-reference's command line (reference_cli.h): one option table (pnb_cli) parses it and
// prints --help.
#include "reference_cli.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "pnb_cli/options.h"
#include "reference_io.h"

namespace pnb::reference_tool {

namespace {

using pnb::cli::flag;
using pnb::cli::valued;

bool parseCount(const char* a, const char* option, long least, uint32_t& out, std::string& error) {
    char* end = nullptr;
    const long v = std::strtol(a, &end, 10);
    if (end == a || *end || v < least || v > 1000000000L)
        error = std::string(option) + " needs an integer >= " + std::to_string(least) + ", not " + a;
    else out = uint32_t(v);
    return true;
}

bool parseNonNegative(const char* a, const char* option, double& out, std::string& error) {
    char* end = nullptr;
    const double v = std::strtod(a, &end);
    if (end == a || *end || !std::isfinite(v) || v < 0) error = std::string(option) + " needs a number >= 0, not " + a;
    else out = v;
    return true;
}

// A value that cannot be used is kept in settings.usageError and reported once the whole command
// line is read (after, e.g., a second scene), as it always was.
std::vector<pnb::cli::Option> options(Settings& s, bool& help) {
    return {
        valued("", "--frame", "DIR",
               "the frame the player dumped: frame.json, position.exr, normal.exr, shadow.exr (required)",
               [&s](const char* a) { s.frameDir = a; return true; }),
        valued("", "--prefix", "P",
               "input names start with P (pnb-play --dump writes frameK_position.exr: --prefix frameK_)",
               [&s](const char* a) { s.prefix = a; return true; }),
        valued("", "--out", "DIR", "where to write the outputs (default: the --frame directory)",
               [&s](const char* a) { s.outDir = a; return true; }),
        flag("", "--indirect",
             "also the one-bounce diffuse irradiance (Monte Carlo): indirect_reference.exr, "
             "indirect_stderr.exr, and against the player's indirect.exr when dumped",
             [&s](const char*) { s.indirect = true; return true; }),
        valued("", "--samples", "N", "cosine-weighted rays per pixel for --indirect (default 256)",
               [&s](const char* a) {
                   s.indirectSettings.samples = uint32_t(std::max(1L, std::atol(a)));
                   return true;
               }),
        valued("", "--indirect-lights", "all|sun",
               "light the bounce with every light (default: the scene's truth) or the sun alone (what "
               "the player's GI models)",
               [&s](const char* a) {
                   s.indirectSettings.lights = std::string(a) == "sun" ? pnb::reference::IndirectLights::Sun
                                                                       : pnb::reference::IndirectLights::All;
                   return true;
               }),
        valued("", "--indirect-bounces", "N|converged",
               "diffuse bounces of --indirect's truth: 1 (default: one bounce, what the LPV models), "
               "up to N, or converged (unlimited, Russian roulette)",
               [&s](const char* a) {
                   auto n = pnb::reference::parseIndirectBounces(a);
                   if (n) s.indirectSettings.bounces = *n;
                   return n.has_value();
               }),
        valued("", "--seed", "S", "random seed of --indirect, --sky and --whole-frame (default 1)",
               [&s](const char* a) {
                   s.indirectSettings.seed = s.skySettings.seed = s.frameSettings.seed = uint64_t(std::atoll(a));
                   return true;
               }),
        flag("", "--sky",
             "also the sky-light irradiance (Monte Carlo, the ENVM environment hidden by the scene): "
             "sky_reference.exr, sky_stderr.exr, and against the player's sky.exr when dumped",
             [&s](const char*) { s.sky = true; return true; }),
        valued("", "--sky-samples", "N", "cosine-weighted rays per pixel for --sky (default 256)",
               [&s](const char* a) {
                   s.skySettings.samples = uint32_t(std::max(1L, std::atol(a)));
                   return true;
               }),
        valued("", "--sky-source", "image|sh",
               "the sky's radiance: the ENVM image (default: the truth) or the radiance of its irradiance "
               "SH (the player's unoccluded term exactly: isolates its sky-visibility error)",
               [&s](const char* a) {
                   const std::string v = a;
                   if (v == "image") s.skySettings.source = pnb::reference::SkySource::Image;
                   else if (v == "sh") s.skySettings.source = pnb::reference::SkySource::Sh;
                   else s.usageError = "--sky-source must be image or sh, not " + v;
                   return true;
               }),
        valued("", "--sky-visibility", "on|off",
               "trace what hides the sky (default on); off gives the unoccluded irradiance",
               [&s](const char* a) {
                   const std::string v = a;
                   if (v == "on" || v == "off") s.skySettings.visibility = v == "on";
                   else s.usageError = "--sky-visibility must be on or off, not " + v;
                   return true;
               }),
        valued("", "--sky-rotation-deg", "D",
               "the environment turned by D degrees about +Y (as sh9RotateY: +X towards -Z); default: "
               "frame.json's ibl_rotation_degrees, else 0",
               [&s](const char* a) {
                   char* end = nullptr;
                   const double v = std::strtod(a, &end);
                   if (end == a || *end || !std::isfinite(v))
                       s.usageError = std::string("--sky-rotation-deg needs a number, not ") + a;
                   else s.skyRotationDegrees = v;
                   return true;
               }),
        valued("", "--sky-intensity", "X",
               "the environment's radiance scale (the player's ibl.intensity); default: frame.json's "
               "ibl_intensity, else 1",
               [&s](const char* a) {
                   char* end = nullptr;
                   const double v = std::strtod(a, &end);
                   if (end == a || *end || !std::isfinite(v) || v < 0)
                       s.usageError = std::string("--sky-intensity needs a number >= 0, not ") + a;
                   else s.skyIntensity = v;
                   return true;
               }),
        valued("", "--anim-clip", "C",
               "trace the scene posed by clip C (an index, a clip's name, or none: the rest pose) instead of "
               "frame.json's \"anim\"",
               [&s](const char* a) { s.animClip = std::string(a); return true; }),
        valued("", "--anim-time", "T",
               "trace the scene posed at T seconds into the clip (looped as the player's clock loops it) instead "
               "of frame.json's \"anim\"; alone: frame.json's clip, else the first",
               [&s](const char* a) {
                   char* end = nullptr;
                   const double v = std::strtod(a, &end);
                   if (end == a || *end || !std::isfinite(v))
                       s.usageError = std::string("--anim-time needs a number, not ") + a;
                   else s.animTime = v;
                   return true;
               }),
        flag("", "--whole-frame",
             "instead of the shadow verdict: the whole frame path traced (needs frame.json only): "
             "whole_frame.exr (linear HDR), whole_frame_stderr.exr, whole_frame.png (tone mapped at "
             "frame.json's exposure) and metrics.json's \"whole_frame\"",
             [&s](const char*) { s.wholeFrame = true; return true; }),
        valued("", "--bounces", "N", "--whole-frame: indirect bounces after the first hit, 0 = direct light only (default 16)",
               [&s](const char* a) { return parseCount(a, "--bounces", 0, s.frameSettings.maxBounces, s.usageError); }),
        valued("", "--spp", "N", "--whole-frame: at most N samples per pixel (default 4096)",
               [&s](const char* a) { return parseCount(a, "--spp", 1, s.frameSettings.maxSamples, s.usageError); }),
        valued("", "--noise-target", "X",
               "--whole-frame: stop once the relative noise (mean stderr^2 / (mean^2 + 0.01)) is below X "
               "(default 0.003; 0: never)",
               [&s](const char* a) { return parseNonNegative(a, "--noise-target", s.frameSettings.noiseTarget, s.usageError); }),
        valued("", "--time-limit", "S", "--whole-frame: stop after the pass that passes S seconds (default 120; 0: none)",
               [&s](const char* a) { return parseNonNegative(a, "--time-limit", s.frameSettings.timeLimitSeconds, s.usageError); }),
        flag("", "-q, --quiet", "print errors only", [&s](const char*) { s.quiet = true; return true; }),
        flag("", "-h, --help", "print this help", [&help](const char*) {
            help = true;
            return pnb::cli::Verdict::stopHere();
        }),
    };
}

void printHelp(const std::vector<pnb::cli::Option>& table) {
    std::printf(
        "usage: pnb-reference SCENE.pnb --frame DIR [--prefix P] [--out DIR] [--indirect ...] "
        "[--sky ...] [--whole-frame ...] [-q]\n\n"
        "Ray traces (Embree) the true visibility of the shadowing light for every pixel of a\n"
        "frame dumped by `pnb-play --dump position,normal,shadow` (the directional light of\n"
        "frame.json's toward_light, or the point or spot light its shadow_light_index names),\n"
        "and compares the player's shadow factor with it. Writes visibility.exr,\n"
        "visibility.png and metrics.json, and shadow_diff.png when the frame has shadow.exr\n"
        "(and counts non-finite pixels of hdr.exr when present). With --indirect, also the "
        "one-bounce diffuse irradiance\n"
        "(Monte Carlo, with its standard error) and its comparison with the player's\n"
        "indirect.exr (`pnb-play --dump indirect`). With --sky, also the irradiance from the\n"
        "scene's environment (ENVM) with the scene hiding the sky, and its comparison with the\n"
        "player's sky.exr (`pnb-play --dump sky`). With --whole-frame, instead: the whole\n"
        "frame path traced (every light, the environment, emissive surfaces, glTF materials, N\n"
        "bounces; needs frame.json only), progressive until the noise target, --spp or the time\n"
        "limit; the defaults (16 bounces, relative noise 0.003, 120 s) converge box-room's\n"
        "480x270 frame on 2 cores within the limit. Every truth traces the scene posed at the\n"
        "frame's instant (frame.json's \"anim\": clip and clip time; --anim-clip/--anim-time\n"
        "override it). See docs/REFERENCE.md.\n\n"
        "options:\n");
    std::fputs(pnb::cli::helpText(table, {.column = 27}).c_str(), stdout);
    std::printf("\nexit codes: 0 ok, 1 usage, 2 input error, 3 unsupported scene data,\n"
                "            4 output error, 5 Embree failure\n");
}

int usageError(const std::string& sentence) {
    std::fprintf(stderr, "Error: %s\n", sentence.c_str());
    return kExitUsage;
}

} // namespace

std::optional<int> parseCommandLine(int argc, char** argv, Settings& settings) {
    bool help = false;
    const std::vector<pnb::cli::Option> table = options(settings, help);
    auto positional = [&settings](const char* arg) {
        if (!settings.scene.empty())
            return pnb::cli::Verdict::error("more than one scene given (" + settings.scene + ", " + arg + ")");
        settings.scene = arg;
        return pnb::cli::Verdict(true);
    };
    if (auto e = pnb::cli::parse(table, positional, argc, argv)) {
        using Kind = pnb::cli::ParseError::Kind;
        switch (e->kind) {
        case Kind::UnknownOption: return usageError("unknown option " + e->option + " (see --help)");
        case Kind::MissingValue: return usageError(e->option + " needs " + e->valueName);
        case Kind::Positional: return usageError(e->why);
        default: return usageError(pnb::cli::describe(*e) + " (see --help)");
        }
    }
    if (help) {
        printHelp(table);
        return kExitOk;
    }
    if (!settings.usageError.empty()) return usageError(settings.usageError + " (see --help)");
    if (settings.scene.empty() || settings.frameDir.empty())
        return usageError("need SCENE.pnb and --frame DIR (see --help)");
    return std::nullopt;
}

} // namespace pnb::reference_tool
