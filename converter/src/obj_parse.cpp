// obj_parse.cpp — the parallel OBJ text parser (obj_parse.h says what it accepts and why).
//
// Three steps:
// 1. The text is cut into chunks at line ends and each chunk is parsed on its own (in
//    parallel) into its own attribute arrays, its faces (corners resolved against the chunk's
//    own counts) and its events. Anything outside the accepted subset stops the chunk with a
//    reason, and the whole parse returns nullopt.
// 2. Sequentially: the chunks' counts give each chunk's first position/uv/normal (its base), the
//    position indices are checked against the file's counts with each chunk's extremes (no pass
//    over the faces), and the attribute arrays are joined.
// 3. In parallel: faces that need the bases or the joined positions (relative indices, quads)
//    are finished in place. The chunks' corner arrays become ObjTriangles' blocks uncopied.
#include "obj_parse.h"

#include <sys/mman.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <new>

#include "parallel_for.h"

namespace pnb::converter {

namespace {

constexpr size_t kHugePage = size_t(2) << 20;

size_t roundToHugePages(size_t bytes) { return (bytes + kHugePage - 1) & ~(kHugePage - 1); }

} // namespace

void* allocateLarge(size_t bytes) {
    if (bytes < kHugePage) return ::operator new(bytes);
    // Aligned to 2 MiB, or the kernel cannot back the ends with huge pages: map one more, trim.
    const size_t size = roundToHugePages(bytes);
    void* raw = ::mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const uintptr_t start = reinterpret_cast<uintptr_t>(raw);
    const uintptr_t aligned = (start + kHugePage - 1) & ~uintptr_t(kHugePage - 1);
    if (aligned > start) ::munmap(raw, aligned - start);
    if (const size_t tail = start + size + kHugePage - (aligned + size); tail > 0)
        ::munmap(reinterpret_cast<void*>(aligned + size), tail);
    ::madvise(reinterpret_cast<void*>(aligned), size, MADV_HUGEPAGE); // a hint: may be refused
    return reinterpret_cast<void*>(aligned);
}

void adviseHugePages(const void* p, size_t bytes) {
    const uintptr_t start = reinterpret_cast<uintptr_t>(p);
    const uintptr_t first = (start + kHugePage - 1) & ~uintptr_t(kHugePage - 1);
    const uintptr_t last = (start + bytes) & ~uintptr_t(kHugePage - 1);
    if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

void freeLarge(void* p, size_t bytes) {
    if (bytes < kHugePage) ::operator delete(p);
    else ::munmap(p, roundToHugePages(bytes));
}

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

// Relative-index bits of a face: corner i's v, vt, vn are bits 3i, 3i+1, 3i+2.
constexpr uint16_t kRelativeV = 1, kRelativeVt = 2, kRelativeVn = 4;

// A face that step 3 finishes: relative indices get the chunk's bases, a quad is split.
struct Fixup {
    size_t corner;     // its first corner in the chunk's array
    uint16_t relative; // kRelative* << 3i for corner i
    bool quad;         // 4 corners written, 6 slots reserved
};

struct Chunk {
    const char* begin = nullptr;
    const char* end = nullptr;
    ObjFloats positions, colors, texcoords, normals;
    bool allColors = true; // every "v" line had a colour (else `colors` is dropped)
    ObjCorners corners;
    std::vector<Fixup> fixups;
    std::vector<ObjEvent> events; // triangle: the chunk's own count
    uint64_t triangles = 0;
    // Position index extremes, checked once the bases are known (step 2).
    int64_t maxAbsolute = -1;                                     // must be < file's count
    int64_t minRelative = 0;                                      // base + it must be >= 0
    int64_t maxQuadAhead = std::numeric_limits<int64_t>::min(); // must be < base
    std::string failure; // why tinyobjloader must read the file, if it must
};

class ChunkParser {
public:
    explicit ChunkParser(Chunk& c) : mC(c) {}

    void run() {
        // No reservations by guess: a huge page reserved is a huge page zeroed when first
        // touched, and doubling costs less than the guesses' waste did.
        for (const char* p = mC.begin; p < mC.end;) {
            const char* nl = static_cast<const char*>(std::memchr(p, '\n', size_t(mC.end - p)));
            const char* lineEnd = nl ? nl : mC.end;
            const char* e = lineEnd;
            if (e > p && e[-1] == '\r') --e;
            if (!line(p, e)) return;
            p = nl ? nl + 1 : mC.end;
        }
    }

private:
    bool fail(const char* why) {
        mC.failure = why;
        return false;
    }

    // tinyobjloader ends a line at "\n", "\r\n" or a lone "\r", and reads it up to a NUL.
    bool clean(const char* p, const char* e) {
        return std::memchr(p, '\r', size_t(e - p)) == nullptr &&
               std::memchr(p, '\0', size_t(e - p)) == nullptr;
    }

    bool line(const char* p, const char* e) {
        while (p < e && isBlank(*p)) ++p;
        if (p == e) return true;
        auto at = [&](size_t i) { return size_t(e - p) > i ? p[i] : '\0'; };
        auto startsWith = [&](std::string_view word) {
            return size_t(e - p) >= word.size() && std::memcmp(p, word.data(), word.size()) == 0;
        };
        const char c = *p;
        // The order of tinyobjloader's checks.
        if (c == 'v') {
            if (isBlank(at(1))) return vertex(p + 2, e);
            if (at(1) == 'n' && isBlank(at(2))) return numbers(p + 3, e, mC.normals, 3, 3);
            if (at(1) == 't' && isBlank(at(2))) return numbers(p + 3, e, mC.texcoords, 2, 3);
            if (at(1) == 'w' && isBlank(at(2))) return fail("a 'vw' line");
        }
        if ((c == 'l' || c == 'p') && isBlank(at(1))) return fail("points or lines");
        if (c == 'f' && isBlank(at(1))) return face(p + 2, e);
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
        if (c == 't' && isBlank(at(1))) return fail("a 't' line");
        // Comments, "s" and lines tinyobjloader ignores: only a lone "\r" would change them.
        if (std::memchr(p, '\r', size_t(e - p)) != nullptr) return fail("a lone carriage return");
        return true;
    }

    // Element by element: a range insert of 2 or 3 floats is a memmove call each.
    static void push(ObjFloats& to, const float* v, int n) {
        for (int i = 0; i < n; ++i) to.push_back(v[i]);
    }

    bool event(ObjEvent::Kind kind, std::string text) {
        mC.events.push_back(ObjEvent{kind, mC.triangles, std::move(text)});
        return true;
    }

    // Up to `max` numbers into vals; how many, or -1 if a token is not one.
    int readNumbers(const char* p, const char* e, float* vals, int max) {
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
        if (n != 3 && n != 6) return fail("a 'v' line without 3 or 6 numbers");
        push(mC.positions, v, 3);
        if (n == 6 && mC.allColors) {
            push(mC.colors, v + 3, 3);
        } else if (n == 3 && mC.allColors) {
            mC.allColors = false;
            mC.colors = {};
        }
        return true;
    }

    bool numbers(const char* p, const char* e, ObjFloats& out, int keep, int max) {
        float v[3];
        const int n = readNumbers(p, e, v, max);
        if (n < keep) return fail("a 'vn' or 'vt' line with too few numbers");
        push(out, v, keep); // tinyobjloader ignores a vt's w
        return true;
    }

    // One OBJ index of at most 9 digits, not 0, zero-based against `count` elements read so far
    // (tinyobjloader's fixIndex). Advances p.
    static bool index(const char*& p, const char* e, size_t count, int32_t& out, bool& relative) {
        bool negative = false;
        if (p < e && (*p == '+' || *p == '-')) negative = *p++ == '-';
        int32_t value = 0;
        const char* digits = p;
        while (p < e && isDigit(*p) && p - digits < 9) value = value * 10 + (*p++ - '0');
        if (p == digits || (p < e && isDigit(*p)) || value == 0) return false;
        relative = negative;
        out = negative ? int32_t(int64_t(count) - value) : value - 1;
        return true;
    }

    bool face(const char* p, const char* e) {
        ObjCorner c[4];
        uint16_t relative = 0;
        int n = 0;
        const size_t vCount = mC.positions.size() / 3, vtCount = mC.texcoords.size() / 2,
                     vnCount = mC.normals.size() / 3;
        for (;;) {
            while (p < e && isBlank(*p)) ++p;
            if (p == e) break;
            if (n == 4) return fail("a polygon with more than 4 corners");
            ObjCorner& k = c[n];
            k.vt = k.vn = -1;
            bool rel = false;
            const int shift = 3 * n;
            if (!index(p, e, vCount, k.v, rel)) return fail("an unusual face corner");
            if (rel) {
                relative |= uint16_t(kRelativeV << shift);
                mC.minRelative = std::min<int64_t>(mC.minRelative, k.v);
            } else {
                mC.maxAbsolute = std::max<int64_t>(mC.maxAbsolute, k.v);
            }
            if (p < e && *p == '/') {
                ++p;
                if (p < e && *p != '/') {
                    if (!index(p, e, vtCount, k.vt, rel)) return fail("an unusual face corner");
                    if (rel) relative |= uint16_t(kRelativeVt << shift);
                }
                if (p < e && *p == '/') {
                    ++p;
                    if (!index(p, e, vnCount, k.vn, rel)) return fail("an unusual face corner");
                    if (rel) relative |= uint16_t(kRelativeVn << shift);
                }
            }
            if (p < e && !isBlank(*p)) return fail("an unusual face corner");
            ++n;
        }
        if (n < 3) return fail("a face with fewer than 3 corners");
        const size_t first = mC.corners.size();
        for (int i = 0; i < n; ++i) mC.corners.push_back(c[i]);
        if (n == 4) {
            // tinyobjloader checks a quad's positions when it splits it, at the next usemtl/g/o
            // or the end: one defined after the quad is accepted only if it came before that.
            // Step 2 rejects any position defined after the quad (the check needs the base).
            for (int i = 0; i < 4; ++i) {
                if (!(relative & (kRelativeV << (3 * i)))) {
                    mC.maxQuadAhead = std::max<int64_t>(mC.maxQuadAhead, int64_t(c[i].v) -
                                                                             int64_t(vCount));
                }
            }
            mC.corners.push_back(c[0]); // two slots more: step 3 writes both triangles
            mC.corners.push_back(c[0]);
            mC.triangles += 2;
        } else {
            mC.triangles += 1;
        }
        if (n == 4 || relative != 0) mC.fixups.push_back(Fixup{first, relative, n == 4});
        return true;
    }

    Chunk& mC;
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

void append(ObjFloats& to, const ObjFloats& from) {
    to.insert(to.end(), from.begin(), from.end());
}

// tinyobjloader's quad split, in the same float arithmetic: along the shorter diagonal,
// (0 1 2)(0 2 3) if 0-2 is shorter, else (0 1 3)(1 2 3). Its library is built without FMA
// contraction, as this file is (no -march flags), so ties and NaNs go the same way.
void splitQuad(ObjCorner* c, const ObjFloats& positions) {
    const ObjCorner q[4] = {c[0], c[1], c[2], c[3]};
    const float* p0 = &positions[size_t(q[0].v) * 3];
    const float* p1 = &positions[size_t(q[1].v) * 3];
    const float* p2 = &positions[size_t(q[2].v) * 3];
    const float* p3 = &positions[size_t(q[3].v) * 3];
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

} // namespace

std::optional<ObjParse> parseObjText(std::string_view text, const ObjParseOptions& options,
                                     std::string* why) {
    // Chunk size depends on the text only, never on the job count.
    const size_t size = options.chunkBytes
                            ? options.chunkBytes
                            : std::clamp<size_t>(text.size() / 16, size_t(256) << 10, size_t(8) << 20);
    std::vector<Chunk> chunks = cut(text, size);

    // Step 1.
    parallelFor(chunks.size(), options.jobs, [&](size_t i) { ChunkParser(chunks[i]).run(); });
    auto refuse = [&](std::string reason) -> std::optional<ObjParse> {
        if (why) *why = std::move(reason);
        return std::nullopt;
    };
    for (const Chunk& c : chunks) {
        if (!c.failure.empty()) return refuse(c.failure);
    }

    // Step 2: bases, index checks, joined attributes.
    struct Base {
        int64_t v = 0, vt = 0, vn = 0;
    };
    std::vector<Base> bases(chunks.size());
    Base total;
    bool allColors = true;
    for (size_t i = 0; i < chunks.size(); ++i) {
        bases[i] = total;
        total.v += int64_t(chunks[i].positions.size() / 3);
        total.vt += int64_t(chunks[i].texcoords.size() / 2);
        total.vn += int64_t(chunks[i].normals.size() / 3);
        allColors &= chunks[i].allColors;
    }
    constexpr int64_t kMaxCount = std::numeric_limits<int32_t>::max();
    if (total.v > kMaxCount || total.vt > kMaxCount || total.vn > kMaxCount)
        return refuse("more elements than tinyobjloader's int indices reach");
    for (size_t i = 0; i < chunks.size(); ++i) {
        const Chunk& c = chunks[i];
        if (c.maxAbsolute >= total.v || bases[i].v + c.minRelative < 0)
            return refuse("a position index out of range");
        if (c.maxQuadAhead >= bases[i].v) return refuse("a quad naming a later position");
    }
    ObjParse out;
    ObjGeometry& g = out.geometry;
    g.positions.reserve(size_t(total.v) * 3);
    g.texcoords.reserve(size_t(total.vt) * 2);
    g.normals.reserve(size_t(total.vn) * 3);
    if (allColors && total.v > 0) g.colors.reserve(size_t(total.v) * 3);
    for (Chunk& c : chunks) {
        append(g.positions, c.positions);
        append(g.texcoords, c.texcoords);
        append(g.normals, c.normals);
        if (allColors) append(g.colors, c.colors);
        c.positions = c.texcoords = c.normals = c.colors = {};
    }

    // Step 3.
    parallelFor(chunks.size(), options.jobs, [&](size_t i) {
        Chunk& c = chunks[i];
        const Base& b = bases[i];
        for (const Fixup& f : c.fixups) {
            ObjCorner* k = &c.corners[f.corner];
            if (f.relative) {
                for (int j = 0; j < (f.quad ? 4 : 3); ++j) {
                    const unsigned bits = unsigned(f.relative >> (3 * j));
                    // In range of int32: the totals are (checked above), and so is the sum.
                    if (bits & kRelativeV) k[j].v = int32_t(b.v + k[j].v);
                    if (bits & kRelativeVt) k[j].vt = int32_t(b.vt + k[j].vt);
                    if (bits & kRelativeVn) k[j].vn = int32_t(b.vn + k[j].vn);
                }
            }
            if (f.quad) splitQuad(k, g.positions);
        }
        c.fixups = {};
    });

    ObjTriangles& t = g.triangles;
    uint64_t start = 0;
    for (size_t i = 0; i < chunks.size(); ++i) {
        for (ObjEvent& e : chunks[i].events) {
            e.triangle += start;
            out.events.push_back(std::move(e));
        }
        t.start.push_back(start);
        start += chunks[i].triangles;
        t.blocks.push_back(std::move(chunks[i].corners));
    }
    t.start.push_back(start);
    return out;
}

} // namespace pnb::converter
