// obj_parse.cpp — the parallel OBJ text parser (obj_parse.h says what it accepts and why).
//
// The text is cut into chunks at line ends (about 1/16 of it each, at least 256 KiB), then:
// 1. In parallel, each chunk counts its v, vt and vn lines and the corner slots its f lines
//    may need (3 for a triangle, 6 for a quad, 3 (n - 2) for an n-gon; faceSlots).
// 2. The counts give every chunk its first slot in each output array (its base) and the arrays
//    their final size, allocated once; in parallel, each chunk parses its lines straight into
//    its slots, relative indices resolved with its bases and every position index checked.
//    Anything outside the accepted subset stops the chunk with a reason, and the whole parse
//    returns nullopt.
// 3. In parallel, quads are split and n-gons ear-clipped as tinyobjloader does (their positions
//    may be in an earlier chunk). Its ear clipping can stop early and leave fewer than n - 2
//    triangles: those slots stay unused, the chunk's triangles continue in a new block after
//    them, and its later events move back by the triangles missing.
// No array grows, and nothing is copied to join the chunks: on this kind of VM, touching fresh
// memory costs more than parsing (docs/CONVERTER.md, "Issue 30").
#include "obj_parse.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "parallel_for.h"

namespace pnb::converter {

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t'; }
bool isDigit(char c) { return static_cast<unsigned char>(c - '0') < 10; }

// A number in tinyobjloader's grammar, [+-] (digits [. [digits]] | . digits) [(e|E) [+-] digits],
// filling the whole token: correctly rounded to float. false for anything else (tinyobjloader
// reads those leniently: a prefix, or 0); also for exponents beyond 9 digits, where
// tinyobjloader's own exponent overflows.
bool parseNumber(const char* b, const char* e, float& out) {
    const char* p = b;
    if (p < e && (*p == '+' || *p == '-')) ++p;
    const char* digits = p;
    while (p < e && isDigit(*p)) ++p;
    bool any = p != digits;
    if (p < e && *p == '.') {
        const char* frac = ++p;
        while (p < e && isDigit(*p)) ++p;
        any |= p != frac;
    }
    if (!any) return false;
    if (p < e && (*p == 'e' || *p == 'E')) {
        ++p;
        if (p < e && (*p == '+' || *p == '-')) ++p;
        const char* exp = p;
        while (p < e && isDigit(*p)) ++p;
        if (p == exp || p - exp > 9) return false;
    }
    if (p != e) return false;
    const char* from = *b == '+' ? b + 1 : b; // from_chars takes '-' only
    auto [end, ec] = std::from_chars(from, e, out);
    if (ec == std::errc() && end == e) return true;
    if (ec != std::errc::result_out_of_range) return false;
    // Beyond float's range: ±Inf for a large magnitude, ±0 for a small one (tinyobjloader's
    // double, converted). A value beyond double's range too is left to tinyobjloader.
    double d = 0;
    auto [dend, dec] = std::from_chars(from, e, d);
    if (dec != std::errc() || dend != e) return false;
    const float magnitude = std::fabs(d) >= 1 ? std::numeric_limits<float>::infinity() : 0.0f;
    out = *b == '-' ? -magnitude : magnitude;
    return true;
}

// The corner slots a face line may need (step 1): each of its corners follows a blank, so it
// has at most as many corners as blanks, and the slots for that many are enough (the chunk
// writes what its faces need, in order, and leaves the rest unused). Counted without telling
// words apart, a loop the compiler vectorises: telling them apart byte by byte cost a quarter
// of the benchmark OBJ's parse.
uint64_t faceSlots(const char* p, const char* e) {
    if (uint64_t(e - p) > std::numeric_limits<uint32_t>::max()) return 3 * uint64_t(e - p);
    uint32_t blanks = 0; // 32 bits: more lanes per vector than size_t
    for (; p < e; ++p) blanks += uint32_t(*p == ' ') + uint32_t(*p == '\t');
    return blanks <= 3 ? 3 : blanks == 4 ? 6 : 3 * (uint64_t(blanks) - 2);
}

// The line kinds that take room in the output arrays (step 1 counts them, step 2 fills them),
// classified as ChunkParser::line does.
enum class Kind { Other, V, Vt, Vn, F };

Kind kindOf(const char* p, const char* e) {
    while (p < e && isBlank(*p)) ++p;
    const size_t n = size_t(e - p);
    if (n >= 2 && *p == 'v') {
        if (isBlank(p[1])) return Kind::V;
        if (n >= 3 && isBlank(p[2])) return p[1] == 't' ? Kind::Vt : p[1] == 'n' ? Kind::Vn : Kind::Other;
    }
    if (n >= 2 && *p == 'f' && isBlank(p[1])) return Kind::F;
    return Kind::Other;
}

// Calls fn(begin, end) for each line of [p, end), its "\n" or "\r\n" removed.
template <class Fn> bool forEachLine(const char* p, const char* end, Fn&& fn) {
    while (p < end) {
        const char* nl = static_cast<const char*>(std::memchr(p, '\n', size_t(end - p)));
        const char* e = nl ? nl : end;
        const char* content = e > p && e[-1] == '\r' ? e - 1 : e;
        if (!fn(p, content)) return false;
        p = nl ? nl + 1 : end;
    }
    return true;
}

struct Counts {
    uint64_t v = 0, vt = 0, vn = 0, slots = 0; // slots: corners of the triangles faces make
};

// A polygon of more than 4 corners, ear-clipped in step 3 into its 3 (n - 2) slots.
struct Ngon {
    uint64_t slot;     // its first corner slot in ObjTriangles::corners
    uint64_t triangle; // the chunk's triangles before it
    uint32_t first, n; // its corners: Chunk::ngonCorners[first, first + n)
    uint32_t made = 0; // triangles the ear clipping gave (step 3)
};

struct Chunk {
    const char* begin = nullptr;
    const char* end = nullptr;
    Counts count; // its lines of each kind (step 1)
    Counts base;  // what the chunks before it hold: its first slot in each array
    bool allColors = true; // every "v" line had a colour (else ObjGeometry::colors is dropped)
    uint64_t corners = 0, triangles = 0; // written (an n-gon counted as n - 2 triangles)
    std::vector<size_t> quads;           // first corner of each quad, split in step 3
    std::vector<Ngon> ngons;             // triangulated in step 3
    std::vector<ObjCorner> ngonCorners;
    std::vector<ObjEvent> events;        // triangle: the chunk's own count until step 3
    std::string failure; // why tinyobjloader must read the file, if it must
    // "v"/"vt"/"vn" lines for ObjParseOptions::lenient, and the slots (the chunk's element
    // numbers) their values go to, by kind.
    std::string lenientLines;
    std::vector<uint64_t> lenientV, lenientVt, lenientVn;
};

// Step 2 for one chunk: parses its lines into the file's arrays at the chunk's slots.
class ChunkParser {
public:
    ChunkParser(Chunk& c, ObjGeometry& g, const Counts& total, const ObjParseOptions& options)
        : mC(c), mTotal(total), mOptions(options), mPositions(g.positions.data() + c.base.v * 3),
          mColors(g.colors.data() + c.base.v * 3), mTexcoords(g.texcoords.data() + c.base.vt * 2),
          mNormals(g.normals.data() + c.base.vn * 3),
          mCorners(g.triangles.corners.data() + c.base.slots) {}

    void run() {
        if (forEachLine(mC.begin, mC.end, [this](const char* p, const char* e) { return line(p, e); }))
            readLenientLines();
    }

private:
    bool fail(const char* why) {
        mC.failure = why;
        return false;
    }

    // tinyobjloader ends a line at "\n", "\r\n" or a lone "\r", and reads it up to a NUL.
    static bool clean(const char* p, const char* e) {
        return std::memchr(p, '\r', size_t(e - p)) == nullptr &&
               std::memchr(p, '\0', size_t(e - p)) == nullptr;
    }

    bool line(const char* p, const char* e) {
        switch (kindOf(p, e)) {
        case Kind::V: return vertex(p, e);
        case Kind::Vt: return numbers(p, e, mTexcoords, mVt, 2, 3);
        case Kind::Vn: return numbers(p, e, mNormals, mVn, 3, 3);
        case Kind::F: return face(p, e);
        case Kind::Other: break;
        }
        while (p < e && isBlank(*p)) ++p;
        if (p == e) return true;
        auto at = [&](size_t i) { return size_t(e - p) > i ? p[i] : '\0'; };
        auto startsWith = [&](std::string_view word) {
            return size_t(e - p) >= word.size() && std::memcmp(p, word.data(), word.size()) == 0;
        };
        const char c = *p;
        // The rest of tinyobjloader's checks, in its order.
        // "vw" (skin weights): the tinyobjloader reader blanks these lines before LoadObj
        // (import_obj_tinyobj.cpp), so both ignore them; below, with the lines it ignores.
        if ((c == 'l' || c == 'p') && isBlank(at(1))) return elements(p, e);
        if (startsWith("usemtl")) {
            const char* n = p + 6;
            if (n == e || !isBlank(*n) || !clean(n, e)) return fail("an unusual 'usemtl' line");
            while (n < e && isBlank(*n)) ++n;
            const char* nameEnd = n;
            while (nameEnd < e && !isBlank(*nameEnd)) ++nameEnd;
            if (nameEnd == n) return fail("'usemtl' without a name");
            return event(ObjEvent::Kind::UseMtl, std::string(n, nameEnd));
        }
        if (startsWith("mtllib") && isBlank(at(6))) {
            if (!clean(p, e)) return fail("an unusual 'mtllib' line");
            return event(ObjEvent::Kind::MtlLib, std::string(p + 7, e));
        }
        if (c == 'g' && isBlank(at(1))) {
            if (!clean(p, e)) return fail("an unusual 'g' line");
            std::string names;
            for (const char* n = p + 1;;) {
                while (n < e && isBlank(*n)) ++n;
                if (n == e) break;
                const char* nameEnd = n;
                while (nameEnd < e && !isBlank(*nameEnd)) ++nameEnd;
                if (!names.empty()) names += ' ';
                names.append(n, nameEnd);
                n = nameEnd;
            }
            if (names.empty()) return fail("'g' without a name"); // tinyobjloader warns
            return event(ObjEvent::Kind::Group, std::move(names));
        }
        if (c == 'o' && isBlank(at(1))) {
            if (!clean(p, e)) return fail("an unusual 'o' line");
            return event(ObjEvent::Kind::Object, std::string(p + 2, e));
        }
        // Comments, "s", "t" (tags, which LoadObj reads without an error and the importer
        // ignores), "vw" and lines tinyobjloader ignores: only a lone "\r" would change them.
        if (std::memchr(p, '\r', size_t(e - p)) != nullptr) return fail("a lone carriage return");
        return true;
    }

    bool event(ObjEvent::Kind kind, std::string text) {
        mC.events.push_back(ObjEvent{kind, mC.triangles, std::move(text)});
        return true;
    }

    // A "v"/"vt"/"vn" line the strict grammar refuses: kept for ObjParseOptions::lenient, its
    // element number taken. Without that reader, or with a "\r" or NUL in it (tinyobjloader
    // would split the line elsewhere), the file goes to tinyobjloader.
    bool lenient(const char* p, const char* e, std::vector<uint64_t>& slots, uint64_t& count,
                 const char* why) {
        if (!mOptions.lenient || !clean(p, e)) return fail(why);
        mC.lenientLines.append(p, e);
        mC.lenientLines += '\n';
        slots.push_back(count++);
        return true;
    }

    // The chunk's lenient lines through ObjParseOptions::lenient, once, into their slots.
    void readLenientLines() {
        if (mC.lenientLines.empty()) return;
        ObjLenientNumbers n;
        if (!mOptions.lenient(mC.lenientLines, n) || n.positions.size() != mC.lenientV.size() * 3 ||
            n.texcoords.size() != mC.lenientVt.size() * 2 ||
            n.normals.size() != mC.lenientVn.size() * 3 ||
            (!n.colors.empty() && n.colors.size() != n.positions.size())) {
            fail("'v', 'vt' or 'vn' lines tinyobjloader did not read as expected");
            return;
        }
        for (size_t i = 0; i < mC.lenientV.size(); ++i) {
            std::copy_n(&n.positions[i * 3], 3, mPositions + mC.lenientV[i] * 3);
            if (!n.colors.empty()) std::copy_n(&n.colors[i * 3], 3, mColors + mC.lenientV[i] * 3);
        }
        if (!mC.lenientV.empty() && n.colors.empty()) mC.allColors = false;
        for (size_t i = 0; i < mC.lenientVt.size(); ++i)
            std::copy_n(&n.texcoords[i * 2], 2, mTexcoords + mC.lenientVt[i] * 2);
        for (size_t i = 0; i < mC.lenientVn.size(); ++i)
            std::copy_n(&n.normals[i * 3], 3, mNormals + mC.lenientVn[i] * 3);
    }

    // An "l" or "p" line: its corners parsed as a face's (tinyobjloader's parse errors are
    // the importer's), their positions not checked (tinyobjloader does not: the importer drops
    // these elements, saying how many). Consecutive ones with no face between are one event.
    bool elements(const char* p, const char* e) {
        const bool points = *p == 'p';
        p += 2;
        // tinyobjloader reads the first corner from just after "p ": after two blanks, its
        // atoi skips the second but its scan does not, and the corner counts twice.
        if (points && p < e && isBlank(*p)) return fail("a 'p' line with two blanks");
        const uint64_t v = mC.base.v + mV, vt = mC.base.vt + mVt, vn = mC.base.vn + mVn;
        uint64_t corners = 0;
        bool unused = true;
        int32_t k = 0;
        for (;;) {
            while (p < e && isBlank(*p)) ++p;
            if (p == e) break;
            if (!index(p, e, v, k, unused, mTotal.v)) return fail("an unusual 'l' or 'p' corner");
            if (p < e && *p == '/') {
                ++p;
                if ((p == e || *p != '/') && !index(p, e, vt, k, unused, mTotal.vt))
                    return fail("an unusual 'l' or 'p' corner");
                if (p < e && *p == '/') {
                    ++p;
                    if (!index(p, e, vn, k, unused, mTotal.vn))
                        return fail("an unusual 'l' or 'p' corner");
                }
            }
            if (p < e && !isBlank(*p)) return fail("an unusual 'l' or 'p' corner");
            ++corners;
        }
        if (corners == 0) return fail("an 'l' or 'p' line without a corner");
        const ObjEvent::Kind kind = points ? ObjEvent::Kind::Points : ObjEvent::Kind::Lines;
        const uint64_t count = points ? corners : 1;
        if (!mC.events.empty() && mC.events.back().kind == kind &&
            mC.events.back().triangle == mC.triangles) {
            mC.events.back().count += count;
            return true;
        }
        mC.events.push_back(ObjEvent{kind, mC.triangles, {}, count});
        return true;
    }

    // The numbers after the line's keyword: up to `max` into vals; how many, or -1 if a token
    // is not one.
    static int readNumbers(const char* p, const char* e, float* vals, int max) {
        while (p < e && isBlank(*p)) ++p;
        while (p < e && !isBlank(*p)) ++p; // the keyword
        int n = 0;
        for (;;) {
            while (p < e && isBlank(*p)) ++p;
            if (p == e) return n;
            if (n == max) return -1;
            const char* t = p;
            while (p < e && !isBlank(*p)) ++p;
            if (!parseNumber(t, p, vals[n++])) return -1;
        }
    }

    bool vertex(const char* p, const char* e) {
        float v[6];
        const int n = readNumbers(p, e, v, 6);
        if (n != 3 && n != 6) return lenient(p, e, mC.lenientV, mV, "a 'v' line without 3 or 6 numbers");
        std::copy(v, v + 3, mPositions + mV * 3);
        if (n == 3) mC.allColors = false;
        else if (mC.allColors) std::copy(v + 3, v + 6, mColors + mV * 3);
        ++mV;
        return true;
    }

    bool numbers(const char* p, const char* e, float* out, uint64_t& count, int keep, int max) {
        float v[3];
        if (readNumbers(p, e, v, max) < keep) {
            return lenient(p, e, keep == 2 ? mC.lenientVt : mC.lenientVn, count,
                           "a 'vn' or 'vt' line with too few numbers");
        }
        std::copy(v, v + keep, out + count * uint64_t(keep)); // tinyobjloader ignores a vt's w
        ++count;
        return true;
    }

    // One OBJ index of at most 9 digits, not 0, zero-based among `total` elements of which
    // `seen` precede the line (tinyobjloader's fixIndex: k > 0 is k - 1, k < 0 is seen + k).
    // Advances p. `valid`: whether it lies in [0, total) (only positions must).
    static bool index(const char*& p, const char* e, uint64_t seen, int32_t& out, bool& valid,
                      uint64_t total) {
        bool negative = false;
        if (p < e && (*p == '+' || *p == '-')) negative = *p++ == '-';
        int64_t value = 0;
        const char* digits = p;
        while (p < e && isDigit(*p) && p - digits < 9) value = value * 10 + (*p++ - '0');
        if (p == digits || (p < e && isDigit(*p)) || value == 0) return false;
        const int64_t k = negative ? int64_t(seen) - value : value - 1;
        valid = k >= 0 && k < int64_t(total);
        out = int32_t(std::max<int64_t>(k, std::numeric_limits<int32_t>::min()));
        return true;
    }

    bool face(const char* p, const char* e) {
        while (p < e && isBlank(*p)) ++p;
        p += 2; // "f" and a blank
        mFace.clear();
        const uint64_t v = mC.base.v + mV, vt = mC.base.vt + mVt, vn = mC.base.vn + mVn;
        bool valid = true, unused = true;
        uint64_t latest = 0; // the largest position index
        for (;;) {
            while (p < e && isBlank(*p)) ++p;
            if (p == e) break;
            ObjCorner& k = mFace.emplace_back();
            k.vt = k.vn = -1;
            if (!index(p, e, v, k.v, valid, mTotal.v)) return fail("an unusual face corner");
            if (!valid) return fail("a position index out of range");
            latest = std::max(latest, uint64_t(k.v));
            if (p < e && *p == '/') {
                ++p;
                // "v/" ends nowhere (tinyobjloader rejects it), also at the line's end.
                if ((p == e || *p != '/') && !index(p, e, vt, k.vt, unused, mTotal.vt))
                    return fail("an unusual face corner");
                if (p < e && *p == '/') {
                    ++p;
                    if (!index(p, e, vn, k.vn, unused, mTotal.vn))
                        return fail("an unusual face corner");
                }
            }
            if (p < e && !isBlank(*p)) return fail("an unusual face corner");
        }
        const size_t n = mFace.size();
        if (n < 3) return fail("a face with fewer than 3 corners");
        if (mC.ngonCorners.size() + n > std::numeric_limits<uint32_t>::max())
            return fail("n-gons of over 2^32 corners in one chunk"); // Ngon's 32-bit fields
        // tinyobjloader splits a polygon when it flushes its faces, at the next usemtl/g/o or
        // the end, checking (quads) or reading (n-gons) positions it has read by then, so one
        // defined after the polygon may or may not pass: left to it.
        if (n > 3 && latest >= v) return fail("a polygon naming a later position");
        const size_t slot = size_t(mC.corners) + mC.base.slots;
        if (n == 3) {
            std::copy(mFace.begin(), mFace.end(), mCorners + mC.corners);
            mC.corners += 3;
            mC.triangles += 1;
        } else if (n == 4) {
            std::copy(mFace.begin(), mFace.end(), mCorners + mC.corners);
            mC.quads.push_back(slot);
            mC.corners += 6; // two slots more: step 3 writes both triangles
            mC.triangles += 2;
        } else {
            mC.ngons.push_back(Ngon{slot, mC.triangles, uint32_t(mC.ngonCorners.size()),
                                    uint32_t(n)});
            mC.ngonCorners.insert(mC.ngonCorners.end(), mFace.begin(), mFace.end());
            mC.corners += 3 * (n - 2);
            mC.triangles += n - 2;
        }
        return true;
    }

    Chunk& mC;
    const Counts& mTotal;
    const ObjParseOptions& mOptions;
    float* mPositions;
    float* mColors;
    float* mTexcoords;
    float* mNormals;
    ObjCorner* mCorners;
    uint64_t mV = 0, mVt = 0, mVn = 0; // elements written
    std::vector<ObjCorner> mFace;      // the face line's corners
};

// Chunks of about `size` bytes, each ending after a "\n" (the last at the end of the text).
std::vector<Chunk> cut(std::string_view text, size_t size) {
    std::vector<Chunk> chunks;
    const char* p = text.data();
    const char* end = p + text.size();
    while (p < end) {
        const char* stop = size_t(end - p) > size ? p + size : end;
        if (stop < end) {
            const char* nl = static_cast<const char*>(std::memchr(stop, '\n', size_t(end - stop)));
            stop = nl ? nl + 1 : end;
        }
        Chunk& c = chunks.emplace_back();
        c.begin = p;
        c.end = stop;
        p = stop;
    }
    return chunks;
}

// tinyobjloader's quad split, in the same float arithmetic: along the shorter diagonal,
// (0 1 2)(0 2 3) if 0-2 is shorter, else (0 1 3)(1 2 3). Its library is built without FMA
// contraction, as this file is (no -march flags), so ties and NaNs go the same way.
void splitQuad(ObjCorner* c, const float* positions) {
    const ObjCorner q[4] = {c[0], c[1], c[2], c[3]};
    const float* p0 = positions + size_t(q[0].v) * 3;
    const float* p1 = positions + size_t(q[1].v) * 3;
    const float* p2 = positions + size_t(q[2].v) * 3;
    const float* p3 = positions + size_t(q[3].v) * 3;
    const float e02x = p2[0] - p0[0], e02y = p2[1] - p0[1], e02z = p2[2] - p0[2];
    const float e13x = p3[0] - p1[0], e13y = p3[1] - p1[1], e13z = p3[2] - p1[2];
    const float sqr02 = e02x * e02x + e02y * e02y + e02z * e02z;
    const float sqr13 = e13x * e13x + e13y * e13y + e13z * e13z;
    if (sqr02 < sqr13) {
        const ObjCorner t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        std::copy(t, t + 6, c);
    } else {
        const ObjCorner t[6] = {q[0], q[1], q[3], q[1], q[2], q[3]};
        std::copy(t, t + 6, c);
    }
}

// tinyobjloader's pnpoly (W. R. Franklin's point-in-polygon test) on a triangle, in its float
// arithmetic: whether (tx, ty) is inside.
bool insideTriangle(const float* vx, const float* vy, float tx, float ty) {
    bool inside = false;
    for (int i = 0, j = 2; i < 3; j = i++) {
        if (((vy[i] > ty) != (vy[j] > ty)) &&
            (tx < (vx[j] - vx[i]) * (ty - vy[i]) / (vy[j] - vy[i]) + vx[i]))
            inside = !inside;
    }
    return inside;
}

// tinyobjloader's triangulation of a polygon of more than 4 corners (its built-in ear clipping:
// Debian's libtinyobjloader is built without TINYOBJLOADER_USE_MAPBOX_EARCUT), step for step
// and in the same float arithmetic, so that every triangle and corner order is its own:
// 1. The projection plane: at the first corner triple (k, k+1, k+2) whose cross product has a
//    component above FLT_EPSILON, drop the axis of its largest component (y z if x is largest,
//    x y if z is, else x z); y z when there is none.
// 2. Ear clipping from corner 0: the candidate (g, g+1, g+2) is an ear unless
//    cross(e0, e1) * (x0 y1 - y0 x1) / 2 < 0 (its convexity test, which depends on the origin)
//    or another remaining corner lies inside it; an ear is written as (g, g+1, g+2) and g+1
//    removed, else g moves on. It gives up after as many candidates as corners remain without
//    finding an ear; the last 3 corners are a triangle. So it may write fewer than n - 2.
// Writes the triangles' corners to `out` (room for 3 (n - 2)); returns how many triangles.
uint32_t earClip(const ObjCorner* face, uint32_t n, const float* positions, ObjCorner* out,
                 std::vector<ObjCorner>& remaining) {
    auto at = [&](const ObjCorner& c, size_t axis) { return positions[size_t(c.v) * 3 + axis]; };
    size_t axes[2] = {1, 2};
    for (uint32_t k = 0; k < n; ++k) {
        const ObjCorner &i0 = face[k % n], &i1 = face[(k + 1) % n], &i2 = face[(k + 2) % n];
        const float e0x = at(i1, 0) - at(i0, 0), e0y = at(i1, 1) - at(i0, 1),
                    e0z = at(i1, 2) - at(i0, 2);
        const float e1x = at(i2, 0) - at(i1, 0), e1y = at(i2, 1) - at(i1, 1),
                    e1z = at(i2, 2) - at(i1, 2);
        const float cx = std::fabs(e0y * e1z - e0z * e1y);
        const float cy = std::fabs(e0z * e1x - e0x * e1z);
        const float cz = std::fabs(e0x * e1y - e0y * e1x);
        const float epsilon = std::numeric_limits<float>::epsilon();
        if (cx > epsilon || cy > epsilon || cz > epsilon) {
            if (!(cx > cy && cx > cz)) {
                axes[0] = 0;
                if (cz > cx && cz > cy) axes[1] = 1;
            }
            break;
        }
    }
    remaining.assign(face, face + n);
    uint32_t made = 0;
    size_t guess = 0;
    size_t iterations = n, previousSize = n;
    while (remaining.size() > 3 && iterations > 0) {
        const size_t size = remaining.size();
        if (guess >= size) guess -= size;
        if (previousSize != size) {
            previousSize = size;
            iterations = size;
        } else {
            --iterations;
        }
        ObjCorner ind[3];
        float vx[3], vy[3];
        for (size_t k = 0; k < 3; ++k) {
            ind[k] = remaining[(guess + k) % size];
            vx[k] = at(ind[k], axes[0]);
            vy[k] = at(ind[k], axes[1]);
        }
        const float e0x = vx[1] - vx[0], e0y = vy[1] - vy[0];
        const float e1x = vx[2] - vx[1], e1y = vy[2] - vy[1];
        const float cross = e0x * e1y - e0y * e1x;
        const float area = (vx[0] * vy[1] - vy[0] * vx[1]) * 0.5f;
        if (cross * area < 0.0f) {
            ++guess;
            continue;
        }
        bool overlap = false;
        for (size_t other = 3; other < size && !overlap; ++other) {
            const ObjCorner& c = remaining[(guess + other) % size];
            overlap = insideTriangle(vx, vy, at(c, axes[0]), at(c, axes[1]));
        }
        if (overlap) {
            ++guess;
            continue;
        }
        std::copy(ind, ind + 3, out + size_t(made) * 3);
        ++made;
        remaining.erase(remaining.begin() + std::ptrdiff_t((guess + 1) % size));
    }
    if (remaining.size() == 3) {
        std::copy(remaining.begin(), remaining.end(), out + size_t(made) * 3);
        ++made;
    }
    return made;
}

} // namespace

std::optional<ObjParse> parseObjText(std::string_view text, const ObjParseOptions& options,
                                     std::string* why) {
    // The chunk size depends on the text only: the parse is the same for any job count (and
    // for any chunk size: tests force tiny ones).
    const size_t size = options.chunkBytes
                            ? options.chunkBytes
                            : std::clamp<size_t>(text.size() / 16, size_t(256) << 10, size_t(8) << 20);
    std::vector<Chunk> chunks = cut(text, size);
    auto refuse = [&](std::string reason) -> std::optional<ObjParse> {
        if (why) *why = std::move(reason);
        return std::nullopt;
    };

    // Step 1: count what each chunk holds, so that the arrays are allocated once at their
    // final size and each chunk writes its own part (no growth, no joining copies).
    parallelFor(chunks.size(), options.jobs, [&](size_t i) {
        Counts& n = chunks[i].count;
        forEachLine(chunks[i].begin, chunks[i].end, [&](const char* p, const char* e) {
            switch (kindOf(p, e)) {
            case Kind::V: ++n.v; break;
            case Kind::Vt: ++n.vt; break;
            case Kind::Vn: ++n.vn; break;
            case Kind::F: n.slots += faceSlots(p, e); break;
            case Kind::Other: break;
            }
            return true;
        });
    });
    Counts total;
    for (Chunk& c : chunks) {
        c.base = total;
        total.v += c.count.v;
        total.vt += c.count.vt;
        total.vn += c.count.vn;
        total.slots += c.count.slots;
    }
    constexpr uint64_t kMaxCount = uint64_t(std::numeric_limits<int32_t>::max());
    if (total.v > kMaxCount || total.vt > kMaxCount || total.vn > kMaxCount)
        return refuse("more elements than tinyobjloader's int indices reach");
    ObjParse out;
    ObjGeometry& g = out.geometry;
    // Not value-initialised (LargeAllocator): every element read is written first; slots an
    // n-gon's ear clipping leaves unused are never read.
    g.positions.resize(total.v * 3);
    g.colors.resize(total.v * 3);
    g.texcoords.resize(total.vt * 2);
    g.normals.resize(total.vn * 3);
    g.triangles.corners.resize(total.slots);

    // Step 2.
    parallelFor(chunks.size(), options.jobs, [&](size_t i) { ChunkParser(chunks[i], g, total, options).run(); });
    for (const Chunk& c : chunks) {
        if (!c.failure.empty()) return refuse(c.failure);
    }

    // Step 3: quads and n-gons (their positions may be another chunk's), block offsets,
    // events.
    parallelFor(chunks.size(), options.jobs, [&](size_t i) {
        Chunk& c = chunks[i];
        for (size_t q : c.quads) splitQuad(&g.triangles.corners[q], g.positions.data());
        std::vector<ObjCorner> remaining;
        for (Ngon& n : c.ngons) {
            n.made = earClip(&c.ngonCorners[n.first], n.n, g.positions.data(),
                             &g.triangles.corners[n.slot], remaining);
        }
    });
    for (const Chunk& c : chunks) {
        for (const Ngon& n : c.ngons) {
            // tinyobjloader would keep a shape of such faces even without triangles (at the
            // end of the file): rare enough to leave to it.
            if (n.made == 0) return refuse("a polygon tinyobjloader's ear clipping leaves empty");
        }
    }
    bool allColors = total.v > 0;
    ObjTriangles& t = g.triangles;
    uint64_t start = 0;
    for (Chunk& c : chunks) {
        allColors &= c.allColors;
        t.start.push_back(start);
        t.offset.push_back(c.base.slots);
        // An n-gon with fewer than n - 2 triangles ends the block after them; the chunk's
        // next triangles start a new one after its slots, and everything after it moves back.
        uint64_t missing = 0;
        size_t next = 0; // the next such n-gon
        auto skipWhole = [&] {
            while (next < c.ngons.size() && c.ngons[next].made == c.ngons[next].n - 2) ++next;
        };
        auto splitAtNext = [&] {
            const Ngon& n = c.ngons[next++];
            t.start.push_back(start + n.triangle - missing + n.made);
            t.offset.push_back(n.slot + 3 * uint64_t(n.n - 2));
            missing += n.n - 2 - n.made;
            skipWhole();
        };
        skipWhole();
        for (ObjEvent& e : c.events) {
            while (next < c.ngons.size() && c.ngons[next].triangle < e.triangle) splitAtNext();
            e.triangle += start - missing;
            out.events.push_back(std::move(e));
        }
        while (next < c.ngons.size()) splitAtNext();
        start += c.triangles - missing;
    }
    t.start.push_back(start);
    if (!allColors) g.colors = {};
    return out;
}

} // namespace pnb::converter
