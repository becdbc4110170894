// obj_parse.h — the OBJ text into geometry arrays and an event list, in parallel. Internal.
//
// Why: tinyobjloader's LoadObj parsed the 1M-triangle benchmark OBJ on one thread, through a
// std::string per line, its own approximate float parser and per-face vectors, into arrays
// that the importer then copied again (docs/CONVERTER.md, "Issue 30"). This parser splits the
// text into chunks at line boundaries, counts what each chunk holds, then parses the chunks on
// `jobs` threads (numbers with std::from_chars) straight into arrays of their final size
// (obj_parse.cpp says how).
//
// What it accepts is a strict subset of what tinyobjloader reads, on which it gives
// tinyobjloader's result (import_obj.cpp's header block is the contract; the ObjParseEquivalence
// tests compare the two): lines "v x y z" and "v x y z r g b", "vn x y z", "vt u v [w]",
// "f" with 3 or more corners in the forms v, v/vt, v//vn, v/vt/vn (negative = relative; at most
// 9 digits), "l" and "p" with corners in those forms (the importer only counts them),
// "usemtl name", "mtllib ...", "o ...", "g names...", comments, blank lines, "s", "vp", the
// "t" and "vw" extensions (which the importer ignores) and other lines tinyobjloader ignores; "\n" or "\r\n" line ends. Polygons are
// triangulated as tinyobjloader does: a quad along its shorter diagonal, a larger polygon (an
// n-gon, as Blender's exporter writes by default) by tinyobjloader's own ear clipping, step for
// step in its float arithmetic (obj_parse.cpp, earClip). Numbers follow tinyobjloader's
// grammar ([+-] digits [. digits] [e [+-] digits]); they are rounded correctly, where
// tinyobjloader's own conversion is approximate (a value may differ from it in the last bit).
// A number too large for a float is ±Inf, one too small is ±0, as with tinyobjloader.
//
// Everything else returns nullopt, and the importer reads the file with tinyobjloader instead:
// errors (a zero or unparsable index, a position index out of range: tinyobjloader's messages
// and line numbers stay the contract), faces of fewer than 3 corners, "l"/"p" without a corner
// or with two blanks after "p" (tinyobjloader reads its first corner twice), face corners
// tinyobjloader reads leniently ("1x" as 1), a lone "\r" or a NUL byte
// (tinyobjloader's line splitting differs), a quad or n-gon naming a position defined after
// it, an n-gon its ear clipping gives no triangle. Numbers in "v", "vt" and "vn" lines that
// tinyobjloader reads leniently ("v 1 2" with a default z, "1x" as 1, words as 0) are read by
// it, those lines alone (ObjParseOptions::lenient), without it the whole file is.
//
// The output is the same for every job count and chunk size (each chunk writes its own slots;
// the chunk size depends on the text's size only).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "huge_pages.h"

namespace pnb::converter {

// One face corner, zero-based (tinyobjloader's index_t values): vt/vn -1 when absent; vt/vn
// may be out of range (the importer drops that stream with a warning), v never is.
struct ObjCorner {
    int32_t v, vt, vn;
};

using ObjFloats = std::vector<float, LargeAllocator<float>>;
using ObjCorners = std::vector<ObjCorner, LargeAllocator<ObjCorner>>;

// The triangles of the file in order, three corners each, in blocks (one per parsed chunk, and
// one more after each n-gon whose ear clipping gave fewer than n - 2 triangles, whose unused
// slots lie between two blocks). Triangle t is block b's triangle t - start[b], at
// corners[offset[b] + 3 * (t - start[b])].
struct ObjTriangles {
    ObjCorners corners;
    std::vector<uint64_t> offset; // first corner of each block
    std::vector<uint64_t> start;  // first triangle of each block; then the total

    uint64_t count() const { return start.empty() ? 0 : start.back(); }

    // Calls fn(const ObjCorner&) for every corner of triangles [begin, end), in order.
    template <class Fn> void forEachCorner(uint64_t begin, uint64_t end, Fn&& fn) const {
        size_t b = size_t(std::upper_bound(start.begin(), start.end(), begin) - start.begin());
        b = b > 0 ? b - 1 : 0;
        for (; b < offset.size() && start[b] < end; ++b) {
            const uint64_t from = std::max(begin, start[b]) - start[b];
            const uint64_t to = std::min(end, start[b + 1]) - start[b];
            const ObjCorner* c = corners.data() + offset[b];
            for (uint64_t i = from * 3; i < to * 3; ++i) fn(c[i]);
        }
    }
};

// What the importer builds its meshes from, whichever parser read the file.
struct ObjGeometry {
    ObjFloats positions; // xyz
    ObjFloats colors;    // rgb per position, or empty (not every "v" line had one)
    ObjFloats texcoords; // uv, OBJ orientation
    ObjFloats normals;   // xyz
    ObjTriangles triangles;
};

// A line that changes what the following faces belong to, in file order.
struct ObjEvent {
    enum class Kind : uint8_t {
        MtlLib, // text: the rest of the line after "mtllib " (tinyobjloader splits it)
        UseMtl, // text: the material name (its first word)
        Group,  // "g": text: the names joined by one space
        Object, // "o": text: the rest of the line after "o "
        Lines,  // "l" lines (count: how many, one element each), dropped by the importer
        Points, // "p" lines (count: their vertices, one point each), dropped likewise
    };
    Kind kind;
    uint64_t triangle; // triangles before this line
    std::string text;
    uint64_t count = 0; // Lines, Points
};

struct ObjParse {
    ObjGeometry geometry;
    std::vector<ObjEvent> events;
};

// What tinyobjloader reads from "v", "vt" and "vn" lines that the strict grammar refuses.
struct ObjLenientNumbers {
    std::vector<float> positions, colors, texcoords, normals; // colors: empty unless every
                                                              // "v" line had one
};

struct ObjParseOptions {
    unsigned jobs = 0;     // threads (parallel_for.h: 0 = all cores)
    size_t chunkBytes = 0; // bytes per chunk (0 = chosen by size; tests force small chunks)
    // Reads `lines` ("v", "vt" and "vn" lines the strict grammar refuses, each ended by "\n")
    // as tinyobjloader does (import_obj_tinyobj.cpp): its defaults for missing numbers ("v 1 2"
    // has z = 0), a "w" ignored, "1x" as 1, a word as 0. Called once per chunk that has such
    // lines, on its thread; false or unset: such a line sends the whole file to tinyobjloader.
    std::function<bool(std::string_view lines, ObjLenientNumbers& out)> lenient;
};

// nullopt: the text needs tinyobjloader (see above); `why`, if given, says what was found.
std::optional<ObjParse> parseObjText(std::string_view text, const ObjParseOptions& options,
                                     std::string* why = nullptr);

} // namespace pnb::converter
