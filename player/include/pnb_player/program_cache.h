// pnb_player/program_cache.h — linked GL programs kept on disk between runs
// (glGetProgramBinary / glProgramBinary), so a launch loads binaries instead of compiling and
// linking GLSL.
//
// One file per program: "<dir>/<key>.bin", the key an XXH3-128 of the driver's strings
// (GL_VENDOR, GL_RENDERER, GL_VERSION, GL_SHADING_LANGUAGE_VERSION), every stage's type and full
// source text as compiled (defines included). Each entry starts with a header: magic, entry
// version, binary format, the key, the driver strings, the binary's length and XXH3-64, and an
// XXH3-64 of the header itself. An entry from another driver, a truncated one, a damaged one
// (any flipped byte) or one the driver refuses is ignored with a one-line note on stderr, the
// program is compiled from source and the entry rewritten. Entries are written through a
// temporary file and a rename (readers never see a part); they are not fsync'ed, because a lost
// or torn entry is detected and rebuilt like a damaged one. A directory that cannot be created
// or written (read-only, disk full, file-size limit) turns writing off for the rest of the
// process after one note; loading entries already there goes on. Problems with the directory
// (unreadable, not a directory) are noted once per process, damaged entries once each. Nothing
// here ever fails a run.
//
// The library's default is off: pnb-play turns it on (tests and embedders opt in). Single
// thread, like the GL context it serves.
//
// The renderer keeps the in-memory part (keys, entry layout, checks, glProgramBinary) and touches
// no file: reading and writing entries is the ProgramCacheStore the tool gives it
// (pnb_play_harness: pnb_player/program_cache_files.h), so the renderer library writes nothing.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <epoxy/gl.h>

namespace pnb::player {

// One entry as the store read it.
struct ProgramCacheEntryRead {
    int error = 0;          // 0, or the errno that stopped the read (ENOENT: no entry yet)
    bool oversized = false; // larger than the limit asked for, so not read (judged damaged)
    std::vector<uint8_t> bytes;
};

// Where entries live. Paths are "<directory>/<key>.bin", made by the cache.
struct ProgramCacheStore {
    // The whole file at `path`, unless it holds more than `maxBytes` bytes.
    std::function<ProgramCacheEntryRead(const std::string& path, uint64_t maxBytes)> read;
    // Creates `directory`, then writes `entry` to `path` whole or not at all (readers never see a
    // part). Returns "" or why it failed (the text of the cache's note).
    std::function<std::string(const std::string& directory, const std::string& path,
                              std::span<const uint8_t> entry)>
        write;
};

struct ProgramCacheOptions {
    bool enabled = false;
    std::string directory; // "" = defaultProgramCacheDirectory()
    bool notes = true;     // one-line notes on stderr (pnb-play -q turns them off)
    ProgramCacheStore store; // without read and write the cache stays off (one note)
};

// $PNB_PROGRAM_CACHE_DIR, else $XDG_CACHE_HOME/penumbra/programs, else
// $HOME/.cache/penumbra/programs; "" when none of them is set.
std::string defaultProgramCacheDirectory();

// Applies to every program compiled afterwards in this process.
void configureProgramCache(const ProgramCacheOptions& options);

struct ProgramCacheStats {
    bool enabled = false;      // configured on and a directory known
    bool binariesOffered = true; // the driver offers a binary format (Mesa: none while
                               // MESA_SHADER_CACHE_DISABLE is set)
    std::string directory;
    uint32_t hits = 0;         // programs loaded from an entry
    uint32_t misses = 0;       // no entry yet
    uint32_t rejected = 0;     // an entry was there but ignored (foreign, damaged, refused)
    uint32_t uncached = 0;     // compiled with the cache off or unusable
    uint32_t written = 0;      // entries written
    uint32_t writeFailures = 0;
    double ms = 0;             // wall time spent making programs (loads and compiles)
    uint32_t compiled() const { return misses + rejected + uncached; }
};

// Counters since the process started (or since resetProgramCacheStats).
ProgramCacheStats programCacheStats();
void resetProgramCacheStats();

// --- used by compileProgram (program_compile.cpp) ---

struct ProgramStageText {
    GLenum stage = GL_VERTEX_SHADER;
    std::string_view text; // exactly what glShaderSource receives
};

// The cache's view of one program: whether to use it and, if so, the entry's path.
struct ProgramCacheLookup {
    bool active = false;
    std::string path;
    uint64_t keyLow = 0, keyHigh = 0;
};
ProgramCacheLookup programCacheLookup(std::span<const ProgramStageText> stages);

// A linked program from the entry, or 0 (miss, or an entry ignored with a note). `label` names
// the program in notes.
GLuint loadCachedProgram(const ProgramCacheLookup& lookup, std::string_view label);

// Before glLinkProgram of a program that will be stored.
void prepareProgramForCache(const ProgramCacheLookup& lookup, GLuint program);

// After a successful link: writes the entry (a failure is a note, at most one per process).
void storeCachedProgram(const ProgramCacheLookup& lookup, GLuint program);

// Book-keeping of compileProgram: a program built from source, and the time a program took.
void countCompiledProgram(const ProgramCacheLookup& lookup);
void addProgramTime(double ms);

} // namespace pnb::player
