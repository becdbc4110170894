// pnb-inspect's report and check modes (see inspect.h): runInspect opens the file, builds the
// chunk table, decodes the scene and hands both to the text or JSON view; --verify checks every
// byte and prints only the verdict.
//
// The views are one file each over shared printing helpers (inspect_internal.h lists them).

#include "inspect.h"

#include <cstdio>
#include <string>

#include "inspect_internal.h"

namespace pnb {

namespace {

using namespace inspect_detail;

// [SECTION] runInspect

void writeAll(std::FILE* f, const std::string& s) {
    std::fwrite(s.data(), 1, s.size(), f);
}

int fail(std::FILE* err, const Error& e) {
    std::fprintf(err, "Error: %s\n", textEscape(e.describe()).c_str());
    bool unsupported = e.code == FormatError::UnsupportedVersion ||
                       e.code == FormatError::UnsupportedChunkVersion;
    return unsupported ? kInspectUnsupported : kInspectInputError;
}

// Opens, checks every byte, decodes everything: the first error wins. A chunk written without a
// checksum (pnb-convert --no-checksums) has nothing its payload can be checked against: strict
// mode fails on it, the default says so beside the verdict.
Result<Container> verifyFile(const InspectOptions& opt, const ReadOptions& ro) {
    auto c = Container::open(opt.path, ro);
    if (!c) return c.error();
    if (Status s = c->verifyAll(); !isOk(s)) return s;
    auto scene = readScene(*c);
    if (!scene) return scene.error();
    if (opt.strict) {
        for (const ChunkInfo& info : c->chunks())
            if (!info.header.hasChecksum())
                return makeError(FormatError::Missing, info.headerOffset,
                                 "strict: chunk %llu ('%s') carries no checksum, its payload "
                                 "cannot be verified",
                                 (unsigned long long)info.header.sequence,
                                 info.header.tag.str().c_str());
    }
    return c;
}

int runVerify(const InspectOptions& opt, const ReadOptions& ro, std::FILE* out, std::FILE* err) {
    auto c = verifyFile(opt, ro);
    if (!opt.json) {
        if (!c) return fail(err, c.error());
        const size_t unchecked = chunksWithoutChecksum(*c);
        std::fprintf(out, "verify: ok (%zu chunks, %zu bytes)\n", c->chunks().size(),
                     c->bytes().size());
        if (unchecked > 0)
            std::fprintf(out,
                         "verify: %zu of %zu chunks carry no checksum: their structure was checked, "
                         "their payload bytes could not be (--strict fails on this)\n",
                         unchecked, c->chunks().size());
        return kInspectOk;
    }
    Json j;
    j.beginObject();
    j.key("file").str(opt.path);
    j.key("verify").beginObject();
    j.key("ok").boolean(c.ok());
    if (c) {
        j.key("chunks").uint(c->chunks().size());
        j.key("chunks_without_checksum").uint(chunksWithoutChecksum(*c));
        j.key("size_bytes").uint(c->bytes().size());
    } else {
        jsonError(j, c.error());
    }
    j.endObject();
    j.endObject();
    writeAll(out, j.out);
    return c ? kInspectOk : fail(err, c.error());
}

} // namespace

InspectOptions inspectDefaults() {
    return InspectOptions{};
}

int runInspect(const InspectOptions& opt, std::FILE* out, std::FILE* err) {
    if (opt.path.empty()) {
        std::fprintf(err, "Error: no input file\n");
        return kInspectUsageError;
    }
    ReadOptions ro;
    ro.verifyChecksums = opt.verifyChecksums;
    ro.useToc = opt.useToc;
    if (opt.verify) return runVerify(opt, ro, out, err);

    auto container = Container::open(opt.path, ro);
    if (!container) {
        if (opt.json) {
            Json j;
            j.beginObject();
            j.key("file").str(opt.path);
            jsonError(j, container.error());
            j.endObject();
            writeAll(out, j.out);
        }
        return fail(err, container.error());
    }
    const ChunkTable table = buildChunkTable(*container);
    // Decoded after the table so that a damaged payload still leaves the frame visible.
    auto scene = readScene(*container);

    std::string text;
    if (opt.json) {
        Json j;
        j.beginObject();
        j.key("file").str(opt.path);
        jsonHeader(j, opt, *container, table);
        if (scene) {
            jsonScene(j, *scene);
        } else {
            j.key("scene").null();
            jsonError(j, scene.error());
        }
        j.endObject();
        text = std::move(j.out);
    } else {
        textHeader(text, opt, *container, table);
        if (scene) textScene(text, *scene);
    }
    writeAll(out, text);
    return scene ? kInspectOk : fail(err, scene.error());
}

} // namespace pnb
