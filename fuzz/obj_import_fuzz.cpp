// obj_import_fuzz — libFuzzer target for the OBJ/MTL importer (converter/src/import_obj.cpp).
//
// One input is an OBJ file, optionally followed by a line "#MTL" and an MTL file: both are
// written to a private temporary directory (importObj reads files, and the MTL is found through
// the same resolver as in real use: "mtllib f.mtl", or the <obj name>.mtl fallback), then
// imported. tinyobjloader is compiled into this target from Debian's header
// (tinyobjloader_impl.cpp) instead of linking libtinyobjloader.so, so its parser is
// instrumented too and coverage guides mutations through it.
//
// Findings: crashes, sanitizer reports, leaks; and the harness abort()s when an import that
// succeeds breaks what scene_ir.h promises (every index inside its primitive's vertices, streams
// of whole vertices, materials and images in range, parents before children), or when the
// parallel OBJ parser read the file (two jobs, tiny chunks) and the tinyobjloader reader gives
// another result (floats may differ by one ulp: import_obj.cpp's header block).
//
// Run it with `scripts/fuzz SECONDS obj_import`; reproduce a finding with
// `build/asan/fuzz/obj_import_fuzz FILE`.
#include <stdlib.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>
#include <string>
#include <string_view>

#include "import_obj_internal.h"
#include "pnb_converter/importers.h"

namespace {

const std::string& workDirectory() {
    static const std::string dir = [] {
        char pattern[] = "/tmp/pnb_obj_fuzz.XXXXXX";
        const char* made = ::mkdtemp(pattern);
        if (made == nullptr) std::abort();
        return std::string(made);
    }();
    return dir;
}

void writeFile(const std::string& path, std::string_view bytes) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) std::abort();
    if (!bytes.empty()) std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
}

void check(bool promise) {
    if (!promise) std::abort();
}

void checkScene(const pnb::converter::IrScene& scene) {
    for (const auto& mesh : scene.meshes) {
        check(!mesh.primitives.empty());
        for (const auto& p : mesh.primitives) {
            check(p.positions.size() % 3 == 0 && p.indices.size() % 3 == 0);
            const size_t n = p.vertexCount();
            for (uint32_t i : p.indices) check(i < n);
            check(p.normals.empty() || p.normals.size() == n * 3);
            check(p.uv0.empty() || p.uv0.size() == n * 2);
            check(p.colors.empty() || p.colors.size() == n * 4);
            check(p.material >= -1 && p.material < int(scene.materials.size()));
        }
    }
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const auto& node = scene.nodes[i];
        check(node.parent < int(i));
        check(node.mesh < int(scene.meshes.size()));
    }
    for (const auto& m : scene.materials) {
        for (const auto& t : m.textures) check(t.image >= -1 && t.image < int(scene.images.size()));
    }
}

// Within one ulp, or both NaN.
bool withinUlp(float a, float b) {
    if (a == b || (std::isnan(a) && std::isnan(b))) return true;
    if (!std::isfinite(a) || !std::isfinite(b) || std::signbit(a) != std::signbit(b)) return false;
    uint32_t x, y;
    std::memcpy(&x, &a, 4);
    std::memcpy(&y, &b, 4);
    return (x > y ? x - y : y - x) <= 1;
}

void checkClose(const std::vector<float>& a, const std::vector<float>& b) {
    check(a.size() == b.size());
    for (size_t i = 0; i < a.size(); ++i) check(withinUlp(a[i], b[i]));
}

// The two readers agree (names, structure, indices, streams, warnings, materials).
void checkSame(const pnb::converter::IrScene& a, const pnb::converter::IrScene& b) {
    check(a.warnings == b.warnings && a.dependencies == b.dependencies);
    check(a.nodes.size() == b.nodes.size() && a.meshes.size() == b.meshes.size());
    for (size_t i = 0; i < a.nodes.size(); ++i)
        check(a.nodes[i].name == b.nodes[i].name && a.nodes[i].mesh == b.nodes[i].mesh);
    check(a.materials.size() == b.materials.size());
    for (size_t i = 0; i < a.materials.size(); ++i) check(a.materials[i].name == b.materials[i].name);
    for (size_t m = 0; m < a.meshes.size(); ++m) {
        const auto &x = a.meshes[m], &y = b.meshes[m];
        check(x.name == y.name && x.primitives.size() == y.primitives.size());
        for (size_t p = 0; p < x.primitives.size(); ++p) {
            const auto &u = x.primitives[p], &v = y.primitives[p];
            check(u.indices == v.indices && u.material == v.material);
            checkClose(u.positions, v.positions);
            checkClose(u.normals, v.normals);
            checkClose(u.uv0, v.uv0);
            checkClose(u.colors, v.colors);
        }
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    const size_t split = input.find("\n#MTL\n");
    const std::string obj = workDirectory() + "/f.obj";
    const std::string mtl = workDirectory() + "/f.mtl";
    writeFile(obj, input.substr(0, split));
    if (split != std::string_view::npos) writeFile(mtl, input.substr(split + 6));
    else ::unlink(mtl.c_str());
    using namespace pnb::converter;
    ObjImportOptions fast;
    fast.jobs = 2;
    fast.chunkBytes = 1 + size % 61; // chunk boundaries everywhere
    ObjReader used = ObjReader::Tinyobj;
    auto result = importObjWith(obj, fast, &used);
    if (result) checkScene(*result);
    else check(result.error().message.find(obj) != std::string::npos); // names the file
    if (used == ObjReader::Fast) {
        ObjImportOptions reference;
        reference.tinyobjOnly = true;
        auto want = importObjWith(obj, reference);
        check(result.ok() == want.ok());
        if (result.ok()) checkSame(*result, *want);
    }
    return 0;
}
