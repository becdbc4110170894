// The installed-package consumer: opens the scene pnb_add_scene() converted at build time with
// the installed pnb::format and prints what it holds, one "key=value" per line, for
// tests/install/install_consumer_test.sh to compare.
#include <cstdio>

#include "pnb/reader.h"
#include "pnb/scene.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s SCENE.pnb\n", argv[0]);
        return 2;
    }
    auto container = pnb::Container::open(argv[1]);
    if (!container) {
        std::fprintf(stderr, "open: %s\n", container.error().describe().c_str());
        return 1;
    }
    if (pnb::Status s = container->verifyAll(); !pnb::isOk(s)) {
        std::fprintf(stderr, "verify: %s\n", s.describe().c_str());
        return 1;
    }
    auto scene = pnb::readScene(*container);
    if (!scene) {
        std::fprintf(stderr, "readScene: %s\n", scene.error().describe().c_str());
        return 1;
    }
    unsigned triangles = 0;
    for (const pnb::Mesh& mesh : scene->meshes)
        for (const pnb::Submesh& sub : mesh.submeshes)
            if (sub.lod == 0) triangles += sub.indexCount / 3;
    std::printf("chunks=%zu\n", container->chunks().size());
    std::printf("meshes=%zu\n", scene->meshes.size());
    std::printf("materials=%zu\n", scene->materials.size());
    std::printf("triangles=%u\n", triangles);
    return 0;
}
