// pnb-make-sample: writes the bundled box-room scene to a .pnb file.
//
//   pnb-make-sample OUT.pnb [--subdivisions N] [--texture-size N] [--environment]
//
// Exit codes: 0 ok, 2 usage error, 4 output error. The options are one pnb_cli table, which also
// prints --help.

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "pnb/writer.h"
#include "pnb_assets/box_room.h"
#include "pnb_cli/options.h"

namespace {

// A handler storing a number from 1 to 4096 into `field`. strtol without an end check, as this
// tool has always read it: "12abc" is 12 (only the fuzz seed script and tests call it).
pnb::cli::Handler oneTo4096(uint32_t& field) {
    return [&field](const char* text) {
        const long v = std::strtol(text, nullptr, 10);
        if (v < 1 || v > 4096) return false;
        field = uint32_t(v);
        return true;
    };
}

std::vector<pnb::cli::Option> options(pnb::assets::BoxRoomOptions& o, bool& help) {
    return {
        pnb::cli::valued("", "--subdivisions", "N", "quads per box face edge, 1..4096 (default 1)",
                         oneTo4096(o.boxSubdivisions)),
        pnb::cli::valued("", "--texture-size", "N",
                         "checker texture texels a side, 1..4096 (default 64)",
                         oneTo4096(o.textureSize)),
        pnb::cli::flag("", "--environment",
                       "add a tiny constant environment (ENVM chunk): a format sample",
                       [&o](const char*) { return o.environment = true; }),
        pnb::cli::flag("", "-h, --help", "print this help and exit",
                       [&help](const char*) {
                           help = true;
                           return pnb::cli::Verdict::stopHere();
                       }),
    };
}

// This tool's wording of a parse error: a value out of range names its range; anything else,
// a flag's value or an option at the end without one included, is an unexpected argument.
void reportParseError(const pnb::cli::ParseError& e) {
    using Kind = pnb::cli::ParseError::Kind;
    if (e.kind == Kind::BadValue) {
        std::fprintf(stderr, "Error: %s takes a number from 1 to 4096\n", e.option.c_str());
        return;
    }
    const std::string arg = e.kind == Kind::Positional      ? e.value
                            : e.kind == Kind::FlagWithValue ? e.option + "=" + e.value
                                                            : e.option;
    std::fprintf(stderr, "Error: unexpected argument '%s' (see --help)\n", arg.c_str());
}

} // namespace

int main(int argc, char** argv) {
    std::string out;
    pnb::assets::BoxRoomOptions options;
    bool help = false;
    const std::vector<pnb::cli::Option> table = ::options(options, help);
    // One output file; a second one, "-" or "" is refused.
    auto output = [&out](const char* arg) {
        if (!*arg || *arg == '-' || !out.empty()) return false;
        out = arg;
        return true;
    };
    if (auto e = pnb::cli::parse(table, output, argc, argv)) {
        reportParseError(*e);
        return 2;
    }
    if (help) {
        std::printf("usage: pnb-make-sample OUT.pnb [--subdivisions N] [--texture-size N] "
                    "[--environment]\n\n%s",
                    pnb::cli::helpText(table, {.column = 20}).c_str());
        return 0;
    }
    if (out.empty()) {
        std::fprintf(stderr, "Error: no output file (usage: pnb-make-sample OUT.pnb)\n");
        return 2;
    }
    pnb::SceneBuilder builder;
    pnb::assets::buildBoxRoom(builder, options);
    auto writer = pnb::Writer::create(out);
    if (!writer) {
        std::fprintf(stderr, "Error: %s\n", writer.error().describe().c_str());
        return 4;
    }
    pnb::Status s = pnb::writeScene(*writer, builder.scene);
    if (pnb::isOk(s)) s = writer->commit();
    if (!pnb::isOk(s)) {
        std::fprintf(stderr, "Error: %s\n", s.describe().c_str());
        return 4;
    }
    std::printf("wrote %s (%llu bytes)\n", out.c_str(), (unsigned long long)writer->size());
    return 0;
}
