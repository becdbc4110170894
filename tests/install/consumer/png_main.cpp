// Links pnb::player (the renderer library and its exported link interface: epoxy, GLFW, zlib,
// ...) and uses its GL-free PNG writer, so the test needs no GL context.
#include <cstdint>
#include <cstdio>
#include <vector>

#include "pnb_player/image_write.h"

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    std::vector<uint8_t> pixels = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
    pnb::player::ImageView image{2, 2, 3, pixels, {}};
    pnb::Status s = pnb::player::writePng(argv[1], image);
    if (!pnb::isOk(s)) {
        std::fprintf(stderr, "writePng: %s\n", s.describe().c_str());
        return 1;
    }
    std::printf("png=ok\n");
    return 0;
}
