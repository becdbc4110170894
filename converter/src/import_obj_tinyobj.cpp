// import_obj_tinyobj.cpp — the OBJ importer's second reader: tinyobjloader's LoadObj, for the
// files the parallel parser leaves to it (obj_parse.h: errors, extensions, lenient face text),
// and for the "v"/"vt"/"vn" lines with lenient numbers in the files it reads. Its errors and
// warnings are the importer's contract (import_obj.cpp's header block); the result is an ObjRead
// like the fast parser's.
#include <tiny_obj_loader.h>

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <istream>
#include <sstream>

#include "import_obj_internal.h"
#include "import_paths.h"

namespace pnb::converter {

namespace {

using namespace import_detail;

static_assert(sizeof(tinyobj::real_t) == sizeof(float),
              "Debian's libtinyobjloader.so is built with float; the streams are copied as such");

// Blanks every "vw" line (tinyobjloader's skin-weight extension, which the importer ignores)
// in place, keeping the line count: tinyobjloader converts a vw joint id to int without a range
// check, which is undefined for a huge number (found by the obj_import fuzzer: "vw 6e21 ...").
void blankSkinWeightLines(char* bytes, size_t size) {
    const std::string_view text(bytes, size);
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find_first_of("\r\n", pos); // tinyobjloader ends a line at either
        if (end == std::string_view::npos) end = text.size();
        size_t at = pos;
        while (at < end && (text[at] == ' ' || text[at] == '\t')) ++at;
        if (end - at > 2 && text[at] == 'v' && text[at + 1] == 'w' &&
            (text[at + 2] == ' ' || text[at + 2] == '\t'))
            std::fill(bytes + pos, bytes + end, ' ');
        pos = end + 1;
    }
}

// The first line of `text` with a face index outside `vertexCount` positions (tinyobjloader's
// rules: k > 0 is k - 1, k < 0 counts back from the vertices read so far), or 0. Only called
// once something is known to be wrong. (Point and line indices are not checked: those elements
// are dropped.)
size_t lineOfBadIndex(std::string_view text, size_t vertexCount) {
    size_t line = 0, seen = 0, pos = 0;
    while (pos < text.size()) {
        size_t end = text.find_first_of("\r\n", pos); // tinyobjloader ends a line at either
        if (end == std::string_view::npos) end = text.size();
        std::string_view l = text.substr(pos, end - pos);
        pos = end + 1;
        ++line;
        while (!l.empty() && (l.front() == ' ' || l.front() == '\t')) l.remove_prefix(1);
        if (l.size() < 2 || (l[1] != ' ' && l[1] != '\t')) continue;
        if (l[0] == 'v') {
            ++seen;
            continue;
        }
        if (l[0] != 'f') continue;
        const std::string s(l.substr(2));
        const char* p = s.c_str();
        while (*p != '\0') {
            p += std::strspn(p, " \t\r");
            if (*p == '\0') break;
            const long k = std::strtol(p, nullptr, 10);
            const long index = k > 0 ? k - 1 : long(seen) + k;
            if (index < 0 || size_t(index) >= vertexCount) return line;
            p += std::strcspn(p, " \t\r");
        }
    }
    return 0;
}

// Line `number` (1-based) of `text`, shortened for a message.
std::string lineText(std::string_view text, size_t number) {
    size_t pos = 0;
    for (size_t line = 1; line < number && pos < text.size(); ++line) {
        const size_t end = text.find('\n', pos);
        pos = end == std::string_view::npos ? text.size() : end + 1;
    }
    std::string_view l = text.substr(std::min(pos, text.size()));
    l = l.substr(0, std::min(l.find_first_of("\r\n"), size_t(80)));
    std::string out;
    for (char c : l) out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
    return out;
}

} // namespace

bool readNumberLinesWithTinyobj(std::string_view lines, ObjLenientNumbers& out) {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    MemoryBuffer buffer(lines);
    std::istream stream(&buffer);
    if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, nullptr,
                          /*triangulate=*/true, /*default_vcols_fallback=*/false))
        return false;
    out.positions.assign(attrib.vertices.begin(), attrib.vertices.end());
    out.colors.assign(attrib.colors.begin(), attrib.colors.end());
    out.texcoords.assign(attrib.texcoords.begin(), attrib.texcoords.end());
    out.normals.assign(attrib.normals.begin(), attrib.normals.end());
    return true;
}

Result<ObjRead, ConvertError> readObjWithTinyobj(const std::string& path, char* bytes,
                                                size_t size, tinyobj::MaterialReader& mtl,
                                                IrScene& out) {
    auto inputError = [&](std::string message) {
        return ConvertError{ConvertErrorKind::Input, path + ": " + message};
    };
    blankSkinWeightLines(bytes, size);
    const std::string_view text(bytes, size);
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    ObjRead read;
    std::string warn, err;
    bool parsed;
    {
        MemoryBuffer buffer(text);
        std::istream stream(&buffer);
        parsed = tinyobj::LoadObj(&attrib, &shapes, &read.materials, &warn, &err, &stream, &mtl,
                                  /*triangulate=*/true, /*default_vcols_fallback=*/false);
    }
    if (!parsed) {
        // tinyobjloader: "Failed parse `f' line(e.g. zero value for face index. line 5.)"
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        const size_t at = err.rfind("line ");
        const size_t line = at == std::string::npos ? 0 : std::strtoul(&err[at + 5], nullptr, 10);
        if (line > 0 && err.rfind("Failed parse `", 0) == 0 && err.size() > 15) {
            return inputError(format("line %zu: malformed '%c' element (an index is 0 or not "
                                     "a number): \"%s\"",
                                     line, err[14], lineText(text, line).c_str()));
        }
        return inputError(err.empty() ? std::string("not a valid OBJ file") : err);
    }
    const size_t vertexCount = attrib.vertices.size() / 3;
    auto badIndex = [&]() {
        const size_t line = lineOfBadIndex(text, vertexCount);
        return inputError(line > 0 ? format("line %zu: vertex index out of range 1..%zu", line,
                                            vertexCount)
                                   : format("vertex index out of range 1..%zu", vertexCount));
    };
    // tinyobjloader only warns about out-of-range indices (and skips such a polygon).
    {
        std::istringstream lines(warn);
        std::string line;
        bool degenerateNoted = false;
        while (std::getline(lines, line)) {
            if (line.empty() || line == ".") continue;
            if (line.find("Vertex indices out of bounds") != std::string::npos ||
                line.find("invalid vertex index") != std::string::npos) {
                return badIndex();
            }
            // Normal/texcoord index problems are reported per mesh.
            if (line.find("indices out of bounds") != std::string::npos) continue;
            if (line.find("Degenerated face") != std::string::npos) {
                if (!degenerateNoted) {
                    out.warnings.push_back("faces with fewer than 3 vertices dropped");
                    degenerateNoted = true;
                }
                continue;
            }
            // "material [ 'name' ] not found in .mtl"
            if (line.rfind("material [ '", 0) == 0) {
                const size_t close = line.rfind("' ]");
                const std::string name =
                    close != std::string::npos && close > 12 ? line.substr(12, close - 12) : line;
                out.warnings.push_back(format("usemtl '%s': no MTL file read defines it; its "
                                              "faces use the default material",
                                              name.c_str()));
                continue;
            }
            if (line.find("Failed to load material file") != std::string::npos) continue;
            out.warnings.push_back(line);
        }
    }

    // Into an ObjRead: the streams moved, the shapes' triangles joined in one block.
    size_t corners = 0;
    for (const tinyobj::shape_t& shape : shapes) corners += shape.mesh.indices.size();
    ObjCorners block;
    block.reserve(corners);
    for (const tinyobj::shape_t& shape : shapes) {
        const tinyobj::mesh_t& mesh = shape.mesh;
        ObjShape s;
        s.name = shape.name;
        s.lines = shape.lines.num_line_vertices.size();
        s.points = shape.points.indices.size();
        const size_t faces = mesh.num_face_vertices.size();
        if (mesh.indices.size() != faces * 3 || mesh.material_ids.size() != faces) {
            return inputError(format("object '%s': inconsistent triangulation",
                                     shape.name.c_str()));
        }
        const uint64_t first = block.size() / 3;
        for (const tinyobj::index_t& idx : mesh.indices) {
            if (idx.vertex_index < 0 || size_t(idx.vertex_index) >= vertexCount) return badIndex();
            block.push_back(ObjCorner{idx.vertex_index, idx.texcoord_index, idx.normal_index});
        }
        for (size_t begin = 0; begin < faces;) {
            size_t end = begin + 1;
            while (end < faces && mesh.material_ids[end] == mesh.material_ids[begin]) ++end;
            s.runs.push_back(ObjRun{first + begin, first + end, mesh.material_ids[begin]});
            begin = end;
        }
        read.shapes.push_back(std::move(s));
    }
    ObjGeometry& g = read.geometry;
    g.positions.assign(attrib.vertices.begin(), attrib.vertices.end());
    g.colors.assign(attrib.colors.begin(), attrib.colors.end());
    g.texcoords.assign(attrib.texcoords.begin(), attrib.texcoords.end());
    g.normals.assign(attrib.normals.begin(), attrib.normals.end());
    g.triangles.offset = {0};
    g.triangles.start = {0, block.size() / 3};
    g.triangles.corners = std::move(block);
    return read;
}

} // namespace pnb::converter
