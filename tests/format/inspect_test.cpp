// pnb-inspect through runInspect(): the box-room report's real content in text and JSON, escaping
// of hostile strings, and damaged files (flipped payload byte, truncation, wrong magic) that must
// give exit code 2 and a named error, never a crash.

#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "inspect.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/writer.h"
#include "pnb_assets/box_room.h"

namespace {

using namespace pnb;
namespace fs = std::filesystem;

struct Captured {
    int code = -1;
    std::string out, err;
};

Captured inspect(const InspectOptions& options) {
    char* outBuf = nullptr;
    char* errBuf = nullptr;
    size_t outSize = 0, errSize = 0;
    std::FILE* out = open_memstream(&outBuf, &outSize);
    std::FILE* err = open_memstream(&errBuf, &errSize);
    Captured r;
    r.code = runInspect(options, out, err);
    std::fclose(out);
    std::fclose(err);
    r.out.assign(outBuf, outSize);
    r.err.assign(errBuf, errSize);
    std::free(outBuf);
    std::free(errBuf);
    return r;
}

Captured inspect(const std::string& path, bool json = false, bool verify = false) {
    InspectOptions o = inspectDefaults();
    o.path = path;
    o.json = json;
    o.verify = verify;
    return inspect(o);
}

std::vector<char> readFile(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void writeFile(const fs::path& p, const std::vector<char>& bytes) {
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), std::streamsize(bytes.size()));
}

// The line of `text` after the line starting with `section` whose second column is `name`
// (the text tables print "#  name  ..."), split on spaces; empty if there is none.
std::vector<std::string> tableRow(const std::string& text, const std::string& section,
                                  const std::string& name) {
    std::istringstream in(text.substr(text.find("\n" + section) + 1));
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line) && !line.empty()) {
        std::istringstream words(line);
        std::vector<std::string> cells{std::istream_iterator<std::string>(words), {}};
        if (cells.size() > 1 && cells[1] == name) return cells;
    }
    return {};
}

// [SECTION] a strict JSON syntax checker (RFC 8259), so escaping is tested in-process

class JsonChecker {
public:
    explicit JsonChecker(const std::string& s) : mS(s) {}
    bool valid() {
        ws();
        if (!value()) return false;
        ws();
        return mPos == mS.size();
    }

private:
    const std::string& mS;
    size_t mPos = 0;

    char peek() const { return mPos < mS.size() ? mS[mPos] : '\0'; }
    bool eat(char c) {
        if (peek() != c) return false;
        ++mPos;
        return true;
    }
    void ws() {
        while (peek() == ' ' || peek() == '\n' || peek() == '\t' || peek() == '\r')
            ++mPos;
    }
    bool literal(const char* word) {
        for (; *word; ++word)
            if (!eat(*word)) return false;
        return true;
    }
    bool digits() {
        size_t start = mPos;
        while (peek() >= '0' && peek() <= '9')
            ++mPos;
        return mPos > start;
    }
    bool number() {
        eat('-');
        if (!eat('0') && !digits()) return false;
        if (eat('.') && !digits()) return false;
        if (eat('e') || eat('E')) {
            if (!eat('+')) eat('-');
            if (!digits()) return false;
        }
        return true;
    }
    bool string() {
        if (!eat('"')) return false;
        while (mPos < mS.size()) {
            unsigned char c = static_cast<unsigned char>(mS[mPos++]);
            if (c == '"') return true;
            if (c < 0x20) return false;
            if (c != '\\') continue;
            char e = peek();
            ++mPos;
            if (e == 'u') {
                for (int k = 0; k < 4; ++k, ++mPos)
                    if (!std::isxdigit(static_cast<unsigned char>(peek()))) return false;
            } else if (std::string_view("\"\\/bfnrt").find(e) == std::string_view::npos) {
                return false;
            }
        }
        return false;
    }
    template <class F> bool list(char close, F element) {
        ws();
        if (eat(close)) return true;
        do {
            ws();
            if (!element()) return false;
            ws();
        } while (eat(','));
        return eat(close);
    }
    bool value() {
        char c = peek();
        if (c == '{')
            return eat('{') && list('}', [&] {
                       if (!string()) return false;
                       ws();
                       if (!eat(':')) return false;
                       ws();
                       return value();
                   });
        if (c == '[') return eat('[') && list(']', [&] { return value(); });
        if (c == '"') return string();
        if (c == 't') return literal("true");
        if (c == 'f') return literal("false");
        if (c == 'n') return literal("null");
        return number();
    }
};

bool isValidJson(const std::string& s) {
    return JsonChecker(s).valid();
}

TEST(InspectJsonChecker, RejectsWhatStrictParsersReject) {
    EXPECT_TRUE(isValidJson(R"({"a": [1, -2.5e3, true, null, "x\u00e9\n"], "b": {}})"));
    EXPECT_FALSE(isValidJson(R"({"a": 1,})"));
    EXPECT_FALSE(isValidJson("[nan]"));
    EXPECT_FALSE(isValidJson("[\"tab\there\"]"));
    EXPECT_FALSE(isValidJson(R"(["\x"])"));
    EXPECT_FALSE(isValidJson("{} {}"));
}

// [SECTION] fixture: one box-room file per test in its own directory (ctest runs tests in
// parallel processes)

class Inspect : public ::testing::Test {
protected:
    fs::path dir;
    fs::path sample;
    SceneBuilder builder;

    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir = fs::temp_directory_path() /
              ("pnb_inspect_" + std::string(info->name()) + "_" + std::to_string(getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
        sample = dir / "box_room.pnb";
        assets::buildBoxRoom(builder);
    }
    void TearDown() override { fs::remove_all(dir); }

    // Writes builder.scene plus any extra raw chunks, the way pnb-make-sample does.
    void writeSample(const fs::path& path, Tag extraTag = {}, bool extra = false,
                     WriteOptions options = {}) {
        auto w = Writer::create(path.string(), options);
        ASSERT_TRUE(w.ok()) << w.error().describe();
        ASSERT_TRUE(isOk(writeScene(*w, builder.scene)));
        if (extra) {
            std::vector<std::byte> payload(40, std::byte{0x5A});
            ASSERT_TRUE(isOk(w->addChunk(extraTag, 3, payload)));
        }
        Status s = w->commit();
        ASSERT_TRUE(isOk(s)) << s.describe();
    }

    // Payload position of the `nth` chunk with `tag` in the written sample.
    uint64_t payloadOffset(Tag tag, size_t nth = 0) {
        auto c = Container::open(sample.string());
        EXPECT_TRUE(c.ok());
        if (!c) return 0;
        auto found = c->find(tag);
        EXPECT_LT(nth, found.size());
        return nth < found.size() ? found[nth]->payloadOffset : 0;
    }
};

// [SECTION] report content

TEST_F(Inspect, TextReportShowsDecodedScene) {
    writeSample(sample);
    Captured r = inspect(sample.string());
    ASSERT_EQ(r.code, kInspectOk) << r.err;
    EXPECT_EQ(r.err, "");

    EXPECT_NE(
        r.out.find("format: version 1.0, " + std::to_string(fs::file_size(sample)) + " bytes"),
        std::string::npos);
    EXPECT_NE(r.out.find("name: box-room"), std::string::npos);
    EXPECT_NE(r.out.find("shadows.cascades=4"), std::string::npos);
    EXPECT_NE(r.out.find("HAS_BASE_COLOR_TEXTURE"), std::string::npos);
    EXPECT_EQ(r.out.find("unknown (skipped)"), std::string::npos);

    auto glass = tableRow(r.out, "materials", "tinted-glass");
    ASSERT_GE(glass.size(), 8u) << r.out;
    EXPECT_EQ(glass[2], "forward");
    EXPECT_EQ(glass[3], "1"); // layer priority
    EXPECT_EQ(glass[4], "blend");
    EXPECT_EQ(glass[6], "double");
    EXPECT_EQ(glass[7], "receive"); // casts no shadows
    auto floor = tableRow(r.out, "materials", "checker-floor");
    ASSERT_FALSE(floor.empty());
    EXPECT_EQ(floor[2], "deferred");
    EXPECT_EQ(floor.back(), "base_color:checker");

    const Mesh& room = builder.scene.meshes[0];
    auto row = tableRow(r.out, "meshes", "room");
    ASSERT_GE(row.size(), 8u) << r.out;
    EXPECT_EQ(row[3], std::to_string(room.vertexCount));
    EXPECT_EQ(row[4], std::to_string(room.indices.size() / 2 / 3)); // u16 triangles
    EXPECT_EQ(row[5], "u16");
    EXPECT_EQ(row[6], "position:f32x3");
    EXPECT_EQ(row[7], "normal:f32x3");
    EXPECT_EQ(row[8], "texcoord0:f32x2");

    auto tex = tableRow(r.out, "textures", "checker");
    ASSERT_GE(tex.size(), 10u);
    EXPECT_EQ(tex[3], "rgba8");
    EXPECT_EQ(tex[4], "64x64");
    EXPECT_EQ(tex[6], "7");
    EXPECT_EQ(tex[8], "srgb");
    EXPECT_EQ(tex[9], "rgba");

    auto path = tableRow(r.out, "camera paths", "orbit");
    ASSERT_GE(path.size(), 4u);
    EXPECT_EQ(path[2], "8");
    EXPECT_EQ(path[3], "10.5");
    EXPECT_NE(r.out.find("nodes: 7 (roots 1, with mesh 3, with light 2, with camera 1)"),
              std::string::npos);
}

TEST_F(Inspect, ChunkTableListsEveryChunkAndTheToc) {
    writeSample(sample);
    auto c = Container::open(sample.string());
    ASSERT_TRUE(c.ok());
    Captured r = inspect(sample.string());
    ASSERT_EQ(r.code, kInspectOk) << r.err;
    for (const ChunkInfo& info : c->chunks()) {
        std::string needle = std::to_string(info.header.sequence) + "  " + info.header.tag.str();
        EXPECT_NE(r.out.find(needle), std::string::npos) << needle;
    }
    EXPECT_NE(r.out.find("TOCX"), std::string::npos);
    EXPECT_NE(r.out.find("table of contents\n"), std::string::npos);
    EXPECT_NE(r.out.find("  TMIP       7"), std::string::npos) << "per-tag totals";
}

TEST_F(Inspect, JsonReportIsValidWithStableFields) {
    writeSample(sample);
    Captured r = inspect(sample.string(), /*json=*/true);
    ASSERT_EQ(r.code, kInspectOk) << r.err;
    EXPECT_TRUE(isValidJson(r.out)) << r.out;
    const size_t room = r.out.find(R"("name": "room")", r.out.find(R"("meshes": [)"));
    ASSERT_NE(room, std::string::npos);
    const std::string vertices =
        R"("vertices": )" + std::to_string(builder.scene.meshes[0].vertexCount) + ",";
    EXPECT_EQ(r.out.find(R"("vertices": )", room), r.out.find(vertices, room)) << vertices;
    for (const char* needle :
         {R"("name": "tinted-glass")", R"("shading_path": "forward")", R"("alpha_mode": "blend")",
          R"("index_type": "u16")", R"("kind": "toc")", R"("render_settings": [)",
          R"({"key": "shadows.cascades", "value": "4"})", R"("color_space": "srgb")",
          R"("duration_seconds": 10.5)", R"("unknown_chunks": 0)"})
        EXPECT_NE(r.out.find(needle), std::string::npos) << needle;
    EXPECT_EQ(r.out.find("\"error\""), std::string::npos);
}

TEST_F(Inspect, UnknownChunksAreListedAsSkipped) {
    writeSample(sample, Tag{{'X', 'T', 'R', 'A'}}, /*extra=*/true);
    Captured r = inspect(sample.string());
    ASSERT_EQ(r.code, kInspectOk) << r.err;
    EXPECT_NE(r.out.find("XTRA"), std::string::npos);
    EXPECT_NE(r.out.find("unknown (skipped)"), std::string::npos);
    EXPECT_NE(r.out.find("unknown chunks (skipped): 1"), std::string::npos);
    Captured j = inspect(sample.string(), /*json=*/true);
    EXPECT_TRUE(isValidJson(j.out));
    EXPECT_NE(j.out.find(R"("tag": "XTRA", "kind": "unknown", "version": 3)"), std::string::npos);
}

TEST_F(Inspect, HostileStringsAreEscaped) {
    // Quote, backslash, newline, a terminal escape sequence, a C1 control (U+009B, CSI), an
    // invalid UTF-8 byte, then valid UTF-8 that must pass through untouched.
    builder.scene.materials[0].name = builder.intern("evil\"\\\n\x1b[2J\xc2\x9b\xff"
                                                     "caf\xc3\xa9");
    writeSample(sample);

    Captured t = inspect(sample.string());
    ASSERT_EQ(t.code, kInspectOk) << t.err;
    EXPECT_EQ(t.out.find('\x1b'), std::string::npos);
    EXPECT_EQ(t.out.find("\xc2\x9b"), std::string::npos);
    EXPECT_NE(t.out.find("evil\"\\\\x0a\\x1b[2J\\xc2\\x9b\\xffcaf\xc3\xa9"), std::string::npos)
        << t.out;

    Captured j = inspect(sample.string(), /*json=*/true);
    ASSERT_EQ(j.code, kInspectOk) << j.err;
    EXPECT_TRUE(isValidJson(j.out));
    EXPECT_NE(j.out.find(R"("name": "evil\"\\\n\u001b[2J\u009b\ufffdcaf)"
                         "\xc3\xa9\""),
              std::string::npos)
        << j.out;
}

TEST_F(Inspect, OutputIsDeterministic) {
    writeSample(sample);
    EXPECT_EQ(inspect(sample.string()).out, inspect(sample.string()).out);
    EXPECT_EQ(inspect(sample.string(), true).out, inspect(sample.string(), true).out);
}

TEST_F(Inspect, ScanFindsTheSameChunksAsTheToc) {
    writeSample(sample);
    InspectOptions o = inspectDefaults();
    o.path = sample.string();
    Captured toc = inspect(o);
    o.useToc = false;
    Captured scan = inspect(o);
    ASSERT_EQ(scan.code, kInspectOk) << scan.err;
    EXPECT_NE(scan.out.find("read: chunks located by scanning chunk headers"), std::string::npos);
    // Everything after the "read:" line is identical.
    EXPECT_EQ(toc.out.substr(toc.out.find("\nchunks:")),
              scan.out.substr(scan.out.find("\nchunks:")));
}

// [SECTION] verification and damaged files

TEST_F(Inspect, VerifyPassesOnAGoodFile) {
    writeSample(sample);
    auto c = Container::open(sample.string());
    ASSERT_TRUE(c.ok());
    Captured r = inspect(sample.string(), false, /*verify=*/true);
    EXPECT_EQ(r.code, kInspectOk) << r.err;
    EXPECT_EQ(r.out, "verify: ok (" + std::to_string(c->chunks().size()) + " chunks, " +
                         std::to_string(fs::file_size(sample)) + " bytes)\n");
    Captured j = inspect(sample.string(), true, true);
    EXPECT_EQ(j.code, kInspectOk);
    EXPECT_TRUE(isValidJson(j.out));
    EXPECT_NE(j.out.find(R"("ok": true)"), std::string::npos);
}

TEST_F(Inspect, FlippedPayloadByteFailsWithChecksumMismatch) {
    writeSample(sample);
    auto bytes = readFile(sample);
    const uint64_t at = payloadOffset(tags::kMesh) + 10;
    bytes[at] = char(bytes[at] ^ 0x40);
    fs::path bad = dir / "flipped.pnb";
    writeFile(bad, bytes);

    Captured v = inspect(bad.string(), false, /*verify=*/true);
    EXPECT_EQ(v.code, kInspectInputError);
    EXPECT_EQ(v.out, "");
    EXPECT_EQ(v.err.rfind("Error: checksum-mismatch at byte ", 0), 0u) << v.err;
    EXPECT_NE(v.err.find("'MESH'"), std::string::npos) << v.err;

    // The report still shows the frame (it needs no payload) before naming the error.
    Captured r = inspect(bad.string());
    EXPECT_EQ(r.code, kInspectInputError);
    EXPECT_NE(r.out.find("MESH"), std::string::npos);
    EXPECT_EQ(r.out.find("\nscene:"), std::string::npos);
    EXPECT_NE(r.err.find("checksum-mismatch"), std::string::npos);

    Captured j = inspect(bad.string(), /*json=*/true);
    EXPECT_EQ(j.code, kInspectInputError);
    EXPECT_TRUE(isValidJson(j.out)) << j.out;
    EXPECT_NE(j.out.find(R"("scene": null)"), std::string::npos);
    EXPECT_NE(j.out.find(R"("code": "checksum-mismatch")"), std::string::npos);
}

TEST_F(Inspect, NoChecksumsSkipsHashingButVerifyStillHashes) {
    writeSample(sample);
    auto bytes = readFile(sample);
    // The last texel of the largest mip: the payload still decodes, only its hash is wrong.
    auto c = Container::open(sample.string());
    ASSERT_TRUE(c.ok());
    const ChunkInfo* last = c->find(tags::kTextureMip).back();
    const uint64_t at = last->payloadOffset + last->header.storedSize - 1;
    bytes[at] = char(bytes[at] ^ 0x01);
    fs::path bad = dir / "texel.pnb";
    writeFile(bad, bytes);

    InspectOptions o = inspectDefaults();
    o.path = bad.string();
    EXPECT_EQ(inspect(o).code, kInspectInputError);
    o.verifyChecksums = false;
    Captured r = inspect(o);
    EXPECT_EQ(r.code, kInspectOk) << r.err;
    EXPECT_NE(r.out.find("payload checksums not verified"), std::string::npos);
    o.verify = true;
    Captured v = inspect(o);
    EXPECT_EQ(v.code, kInspectInputError);
    EXPECT_NE(v.err.find("checksum-mismatch"), std::string::npos);
}

// A file written without checksums cannot show a flipped byte that still decodes: verify must say
// what it could not check, and strict mode must fail on it.
TEST_F(Inspect, VerifySaysWhatItCouldNotCheckAndStrictFailsOnIt) {
    writeSample(sample, {}, false, WriteOptions{.checksums = false});
    auto bytes = readFile(sample);
    auto c = Container::open(sample.string());
    ASSERT_TRUE(c.ok());
    const size_t total = c->chunks().size();
    // The last texel of the largest mip: the payload still decodes, only its bytes are wrong.
    const ChunkInfo* last = c->find(tags::kTextureMip).back();
    const uint64_t at = last->payloadOffset + last->header.storedSize - 1;
    bytes[at] = char(bytes[at] ^ 0x01);
    fs::path bad = dir / "unchecked.pnb";
    writeFile(bad, bytes);

    InspectOptions o = inspectDefaults();
    o.path = bad.string();
    o.verify = true;
    Captured v = inspect(o);
    EXPECT_EQ(v.code, kInspectOk) << v.err;
    // Every chunk but the TOC (which always has one) lacks a checksum.
    EXPECT_NE(v.out.find("verify: " + std::to_string(total) + " of " + std::to_string(total) +
                         " chunks carry no checksum"),
              std::string::npos)
        << v.out;
    o.json = true;
    Captured j = inspect(o);
    EXPECT_TRUE(isValidJson(j.out)) << j.out;
    EXPECT_NE(j.out.find(R"("chunks_without_checksum": )" + std::to_string(total)),
              std::string::npos)
        << j.out;

    o.json = false;
    o.strict = true;
    Captured s = inspect(o);
    EXPECT_EQ(s.code, kInspectInputError);
    EXPECT_EQ(s.err.rfind("Error: missing at byte ", 0), 0u) << s.err;
    EXPECT_NE(s.err.find("carries no checksum"), std::string::npos) << s.err;

    // The report mode says it too, instead of "checksums verified" alone.
    Captured r = inspect(bad.string());
    EXPECT_NE(r.out.find("chunks carry no checksum: their payload bytes cannot be checked"),
              std::string::npos)
        << r.out;

    // A file with checksums passes strict mode.
    writeSample(sample);
    o.path = sample.string();
    EXPECT_EQ(inspect(o).code, kInspectOk);
}

TEST_F(Inspect, TruncatedFilesAreInputErrorsNotCrashes) {
    writeSample(sample);
    const auto bytes = readFile(sample);
    // "Error: <code> at byte <offset>: <message>\n", one line. (Checked by hand: GCC 12's
    // std::regex trips -Wmaybe-uninitialized under ASan at -O2.)
    auto isErrorLine = [](const std::string& e) {
        const std::string prefix = "Error: ";
        if (e.rfind(prefix, 0) != 0 || e.empty() || e.back() != '\n') return false;
        if (e.find('\n') != e.size() - 1) return false;
        size_t at = e.find(" at byte ", prefix.size());
        if (at == std::string::npos || at == prefix.size()) return false;
        for (size_t i = prefix.size(); i < at; ++i)
            if (!(std::islower(static_cast<unsigned char>(e[i])) || e[i] == '-')) return false;
        size_t digits = at + 9, colon = e.find(": ", digits);
        if (colon == std::string::npos || colon == digits) return false;
        for (size_t i = digits; i < colon; ++i)
            if (!std::isdigit(static_cast<unsigned char>(e[i]))) return false;
        return colon + 3 < e.size();
    };
    std::vector<size_t> lengths = {0,
                                   1,
                                   8,
                                   63,
                                   64,
                                   65,
                                   128,
                                   bytes.size() / 2,
                                   bytes.size() - 33,
                                   bytes.size() - 32,
                                   bytes.size() - 1};
    for (size_t n = 0; n < bytes.size(); n += 389)
        lengths.push_back(n);
    fs::path cut = dir / "cut.pnb";
    for (size_t n : lengths) {
        writeFile(cut, std::vector<char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(n)));
        for (bool useToc : {true, false}) {
            for (bool json : {false, true}) {
                InspectOptions o = inspectDefaults();
                o.path = cut.string();
                o.useToc = useToc;
                o.json = json;
                Captured r = inspect(o);
                SCOPED_TRACE("length " + std::to_string(n) + (useToc ? " toc" : " scan") +
                             (json ? " json" : " text"));
                EXPECT_EQ(r.code, kInspectInputError);
                // What and where: "Error: <code> at byte <offset>: <message>", one line.
                EXPECT_TRUE(isErrorLine(r.err)) << r.err;
                if (json)
                    EXPECT_TRUE(isValidJson(r.out)) << r.out;
                else
                    EXPECT_EQ(r.out, "");
            }
        }
    }
    // Cuts inside a header or the footer. Which code a cut inside a payload gets is the
    // library's contract, tested in corruption_test.cpp; here only "named, no crash" matters.
    for (size_t n : {size_t(63), size_t(100), bytes.size() - 1}) {
        writeFile(cut, std::vector<char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(n)));
        EXPECT_EQ(inspect(cut.string()).err.rfind("Error: truncated at byte ", 0), 0u) << n;
    }
}

// With checksums off, damaged payloads reach the decoders and, when they still decode, the
// printers: odd values (NaN floats, huge counts, wild indices that validateScene must catch) have
// to give a valid report or a named error. Texel chunks are skipped (any value is valid there).
TEST_F(Inspect, FlippedPayloadBytesNeverBreakTheReport) {
    writeSample(sample);
    const auto bytes = readFile(sample);
    auto c = Container::open(sample.string());
    ASSERT_TRUE(c.ok());
    fs::path bad = dir / "flipped.pnb";
    size_t failures = 0, decoded = 0, rejected = 0;
    for (const ChunkInfo& info : c->chunks()) {
        if (info.header.tag == tags::kTextureMip) continue;
        const uint64_t size = info.header.storedSize;
        for (uint64_t k = 0; k < size && failures < 5; ++k) {
            // Every field of the small chunks; a big one's fixed fields at both ends, and a
            // sample of its bulk blobs in between.
            if (k >= 96 && k + 160 < size && k % 97 != 0) continue;
            auto damaged = bytes;
            damaged[info.payloadOffset + k] = char(damaged[info.payloadOffset + k] ^ 0xA5);
            writeFile(bad, damaged);
            // Neighbouring bytes alternate between the two printers, which halves the runs.
            const bool json = k % 2 == 1;
            InspectOptions o = inspectDefaults();
            o.path = bad.string();
            o.verifyChecksums = false;
            o.json = json;
            Captured r = inspect(o);
            bool ok = r.code == kInspectOk
                          ? r.err.empty()
                          : r.code == kInspectInputError && r.err.rfind("Error: ", 0) == 0;
            if (json) ok = ok && isValidJson(r.out);
            if (!ok && ++failures <= 5)
                ADD_FAILURE() << "chunk " << info.header.sequence << " '" << info.header.tag.str()
                              << "' byte " << k << (json ? " json" : "") << ": exit " << r.code
                              << "\n"
                              << r.err << r.out.substr(0, 2000);
            (r.code == kInspectOk ? decoded : rejected) += 1;
        }
    }
    // Both outcomes must actually occur, or the sweep tested nothing.
    EXPECT_GT(decoded, 0u);
    EXPECT_GT(rejected, 0u);
}

TEST_F(Inspect, OtherBadInputs) {
    fs::path text = dir / "notes.txt";
    writeFile(text, {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd', '\n'});
    Captured r = inspect(text.string());
    EXPECT_EQ(r.code, kInspectInputError);
    EXPECT_NE(r.err.find("Error: bad-magic"), std::string::npos) << r.err;

    Captured missing = inspect((dir / "missing.pnb").string(), false, true);
    EXPECT_EQ(missing.code, kInspectInputError);
    EXPECT_NE(missing.err.find("Error: io-error"), std::string::npos) << missing.err;

    Captured none = inspect(std::string());
    EXPECT_EQ(none.code, kInspectUsageError);
}

TEST_F(Inspect, NewerVersionsExitWithUnsupported) {
    writeSample(sample);
    std::vector<char> bytes;
    {
        std::FILE* f = std::fopen(sample.string().c_str(), "rb");
        ASSERT_NE(f, nullptr);
        int ch;
        while ((ch = std::fgetc(f)) != EOF) bytes.push_back(char(ch));
        std::fclose(f);
    }
    auto header = encodeFileHeader(FileHeader{.versionMajor = 2});
    std::memcpy(bytes.data(), header.data(), header.size());
    fs::path newer = dir / "newer.pnb";
    writeFile(newer, bytes);
    Captured r = inspect(newer.string());
    EXPECT_EQ(r.code, kInspectUnsupported);
    EXPECT_NE(r.err.find("unsupported-version"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("update Penumbra"), std::string::npos) << r.err;

}

} // namespace
