// inspect.h — pnb-inspect as a callable function: reports what a .pnb container holds, or checks
// it, without spawning a process (tests call runInspect directly; inspect_main.cpp only parses
// the command line).
//
// Does NOT do: argument parsing (inspect_main.cpp), repairing or rewriting files, printing
// payload contents beyond summaries (no texel or vertex dumps).
//
// Exit codes: kInspectOk (0), kInspectUsageError (1), kInspectInputError (2), kInspectUnsupported
// (3: a newer format or chunk version than this build reads). A malformed file never crashes the
// inspector: every failure is an "Error: <code> at byte <offset>: <message>" line on `err` and
// exit code 2 or 3.
#pragma once

#include <cstdio>
#include <string>

namespace pnb {

inline constexpr int kInspectOk = 0;
inline constexpr int kInspectUsageError = 1;
inline constexpr int kInspectInputError = 2;
inline constexpr int kInspectUnsupported = 3;

struct InspectOptions {
    std::string path;            // the container to read. Default: "" (a usage error).
    bool json = false;           // one JSON object on `out` instead of text. Default: false.
    bool verify = false;         // check mode: verifyAll() + readScene(), print only the
                                 // verdict. Default: false.
    bool strict = false;         // verify mode: also fail (kInspectInputError) when a chunk has
                                 // no payload checksum to verify. Default: false (the verdict
                                 // then says how many chunks could not be checked).
    bool verifyChecksums = true; // ReadOptions::verifyChecksums while decoding. --verify hashes
                                 // every payload regardless. Default: true.
    bool useToc = true;          // ReadOptions::useToc: false locates chunks by scanning chunk
                                 // headers instead of reading the table of contents. Default: true.
};

// The settings a bare `pnb-inspect FILE` uses (the one place defaults are chosen).
InspectOptions inspectDefaults();

// Reads options.path and writes the report to `out`, errors to `err` ("Error: ..." lines).
//
// Report mode (verify = false): the file header and chunk table come from the container index
// alone, so they are printed even when a payload is damaged; the typed summaries need readScene()
// to succeed. On a decode error the text report stops after the chunk table, the JSON report has
// "scene": null and an "error" object, and the result is kInspectInputError.
// Verify mode: "verify: ok (N chunks, M bytes)" (or {"verify": {...}} with json) and kInspectOk,
// or the first error and kInspectInputError. Chunks without a checksum are counted on a second
// line ("chunks_without_checksum" in JSON); with strict they are an error ("missing").
//
// Output is deterministic: the same file and options give the same bytes. Strings from the file
// are escaped (control bytes in text, JSON escapes and U+FFFD for invalid UTF-8 in JSON), so a
// hostile file cannot inject terminal escapes or break the JSON.
// Returns kInspectUsageError if options.path is empty. Thread safety: reentrant.
int runInspect(const InspectOptions& options, std::FILE* out, std::FILE* err);

} // namespace pnb
