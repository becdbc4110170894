// import_obj_internal.h — the OBJ importer's two readers and what they hand to the mesh
// building in import_obj.cpp. Internal (tests use importObjWith to compare the readers).
//
// A file is read by the parallel parser (obj_parse.h) when it stays in that parser's subset,
// else by tinyobjloader (import_obj_tinyobj.cpp), which also gives every error message. Both
// produce an ObjRead; everything after (materials, vertex numbering, streams, warnings) is
// one code path.
#pragma once

#include <tiny_obj_loader.h>

#include <cstddef>
#include <cstdint>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

#include "obj_parse.h"
#include "pnb/error.h"
#include "pnb_converter/scene_ir.h"

namespace pnb::converter {

// An istream buffer over bytes we already hold, without copying them into a stringbuf (read
// only): the OBJ for LoadObj, an MTL for LoadMtl.
class MemoryBuffer : public std::streambuf {
public:
    explicit MemoryBuffer(std::string_view bytes) {
        char* begin = const_cast<char*>(bytes.data()); // streambuf's get area is not const
        setg(begin, begin, begin + bytes.size());
    }
};

// Triangles [begin, end) of ObjGeometry::triangles with one material (an index into
// ObjRead::materials, or -1).
struct ObjRun {
    uint64_t begin, end;
    int material;
};

// One tinyobjloader shape: an "o"/"g" object's faces, as runs of one material each.
struct ObjShape {
    std::string name; // "" before any "o"/"g" line
    std::vector<ObjRun> runs;
    size_t points = 0, lines = 0; // dropped with a warning
};

struct ObjRead {
    ObjGeometry geometry;
    std::vector<ObjShape> shapes;
    std::vector<tinyobj::material_t> materials;
};

// The OBJ through tinyobjloader's LoadObj, with `mtl` reading the MTL files. `text` is the
// file's bytes, which it edits (blanks "vw" lines). Errors and tinyobjloader's warnings become
// the importer's (import_obj.cpp's header block); MTL warnings are the reader's.
Result<ObjRead, ConvertError> readObjWithTinyobj(const std::string& path, char* text,
                                                size_t size, tinyobj::MaterialReader& mtl,
                                                IrScene& out);

// ObjParseOptions::lenient: LoadObj on those "v"/"vt"/"vn" lines alone (no line of another
// kind is passed, so nothing else in the file can change what it reads from them).
bool readNumberLinesWithTinyobj(std::string_view lines, ObjLenientNumbers& out);

struct ObjImportOptions {
    unsigned jobs = 0;        // threads (parallel_for.h: 0 = all cores)
    size_t chunkBytes = 0;    // obj_parse's chunk size (0 = its choice; tests force small)
    bool tinyobjOnly = false; // read with tinyobjloader even when the fast parser could
};

enum class ObjReader { Fast, Tinyobj };

// importObj with options; `used`, if given, says which reader read the file.
Result<IrScene, ConvertError> importObjWith(const std::string& path,
                                            const ObjImportOptions& options,
                                            ObjReader* used = nullptr);

} // namespace pnb::converter
