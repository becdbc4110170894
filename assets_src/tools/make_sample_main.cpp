// pnb-make-sample: writes the bundled box-room scene to a .pnb file.
//
//   pnb-make-sample OUT.pnb [--subdivisions N] [--texture-size N] [--environment]
//
// Exit codes: 0 ok, 2 usage error, 4 output error.

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "pnb/writer.h"
#include "pnb_assets/box_room.h"

int main(int argc, char** argv) {
    std::string out;
    pnb::assets::BoxRoomOptions options;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if ((a == "--subdivisions" || a == "--texture-size") && i + 1 < argc) {
            long v = std::strtol(argv[++i], nullptr, 10);
            if (v < 1 || v > 4096) {
                std::fprintf(stderr, "Error: %s takes a number from 1 to 4096\n", a.c_str());
                return 2;
            }
            (a == "--subdivisions" ? options.boxSubdivisions : options.textureSize) = uint32_t(v);
        } else if (a == "--environment") {
            options.environment = true;
        } else if (a == "-h" || a == "--help") {
            std::printf("usage: pnb-make-sample OUT.pnb [--subdivisions N] [--texture-size N] [--environment]\n");
            return 0;
        } else if (!a.empty() && a[0] != '-' && out.empty()) {
            out = a;
        } else {
            std::fprintf(stderr, "Error: unexpected argument '%s' (see --help)\n", a.c_str());
            return 2;
        }
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
