// The program binary cache (pnb_player/program_cache.h): entry layout and validation. The
// entries' files are the ProgramCacheStore's (the tool's), so nothing here opens a file.
#include "pnb_player/program_cache.h"

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <xxhash.h>

#include "pnb/user_cache_directory.h"

namespace pnb::player {

namespace {

// Entry layout (native byte order: an entry never leaves the machine that wrote it, and a
// foreign one fails the magic or the driver check):
//   0  magic "PNBPROG\n"        8
//   8  entry version (1)        u32
//  12  binary format (GLenum)   u32
//  16  key low, key high        u64 x2   XXH3-128 of driver strings + stages (the file name)
//  32  lengths of GL_VENDOR, GL_RENDERER, GL_VERSION, GL_SHADING_LANGUAGE_VERSION   u32 x4
//  48  binary length            u64
//  56  binary XXH3-64           u64
//  64  header XXH3-64           u64      over bytes 0..63 and the strings
//  72  the four strings, unterminated, then the binary
// Every byte has a meaning, so a flipped byte anywhere is caught by one of the checks.
constexpr char kMagic[8] = {'P', 'N', 'B', 'P', 'R', 'O', 'G', '\n'};
constexpr uint32_t kEntryVersion = 1;
constexpr size_t kHeaderBytes = 72;
constexpr uint32_t kMaxDriverString = 4096;
// Larger files are not read: no linked program comes near it, and GLsizei must hold the binary.
constexpr uint64_t kMaxEntryBytes = 256ull << 20;

struct State {
    ProgramCacheOptions options;
    std::string directory; // resolved; "" = off
    bool writable = true;  // false after a failed write
    bool directoryNoted = false; // one note per process about the directory (read or write)
    bool noBinaryNoted = false;
    ProgramCacheStats stats;
};

State& state() {
    static State s;
    return s;
}

void note(const char* fmt, ...) {
    if (!state().options.notes) return;
    char buf[2048];
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(buf, sizeof buf, fmt, args);
    va_end(args);
    std::fprintf(stderr, "pnb-play: note: program cache: %s\n", buf);
}

std::string glString(GLenum name) {
    const char* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

struct Driver {
    std::string strings[4];
};

Driver currentDriver() {
    return {{glString(GL_VENDOR), glString(GL_RENDERER), glString(GL_VERSION),
             glString(GL_SHADING_LANGUAGE_VERSION)}};
}

template <class T> void put(std::vector<uint8_t>& out, size_t at, T value) {
    std::memcpy(out.data() + at, &value, sizeof value);
}
template <class T> T get(const std::vector<uint8_t>& in, size_t at) {
    T value;
    std::memcpy(&value, in.data() + at, sizeof value);
    return value;
}

bool driverOffersFormat(GLenum format) {
    GLint count = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &count);
    if (count <= 0) return false;
    std::vector<GLint> formats(static_cast<size_t>(count));
    glGetIntegerv(GL_PROGRAM_BINARY_FORMATS, formats.data());
    return std::find(formats.begin(), formats.end(), GLint(format)) != formats.end();
}

// XXH3-64 of the header's first 64 bytes and the driver strings that follow the header.
uint64_t headerChecksum(const std::vector<uint8_t>& entry, size_t stringBytes) {
    std::vector<uint8_t> covered(entry.begin(), entry.begin() + 64);
    covered.insert(covered.end(), entry.begin() + kHeaderBytes, entry.begin() + static_cast<std::ptrdiff_t>(kHeaderBytes + stringBytes));
    return XXH3_64bits(covered.data(), covered.size());
}

std::string shortDriver(const Driver& d) { return d.strings[0] + " | " + d.strings[1] + " | " + d.strings[2]; }

// Why the entry cannot be used, or "" if it can (then `binary` and `format` are set).
std::string validate(const std::vector<uint8_t>& e, const ProgramCacheLookup& lookup, const Driver& driver,
                     size_t& binaryAt, uint64_t& binaryBytes, GLenum& format) {
    if (e.size() < kHeaderBytes)
        return "truncated (" + std::to_string(e.size()) + " bytes, shorter than its header)";
    if (std::memcmp(e.data(), kMagic, sizeof kMagic) != 0) return "not a program cache entry (bad magic)";
    uint32_t version = get<uint32_t>(e, 8);
    if (version != kEntryVersion)
        return "entry version " + std::to_string(version) + " (this player reads " +
               std::to_string(kEntryVersion) + ")";
    uint64_t stringBytes = 0;
    Driver stored;
    for (int i = 0; i < 4; ++i) {
        uint32_t n = get<uint32_t>(e, 32 + 4 * size_t(i));
        if (n > kMaxDriverString) return "damaged header (driver string of " + std::to_string(n) + " bytes)";
        stringBytes += n;
    }
    if (kHeaderBytes + stringBytes > e.size())
        return "truncated (" + std::to_string(e.size()) + " bytes, its header needs " +
               std::to_string(kHeaderBytes + stringBytes) + ")";
    size_t at = kHeaderBytes;
    for (int i = 0; i < 4; ++i) {
        uint32_t n = get<uint32_t>(e, 32 + 4 * size_t(i));
        stored.strings[i].assign(reinterpret_cast<const char*>(e.data() + at), n);
        at += n;
    }
    for (int i = 0; i < 4; ++i)
        if (stored.strings[i] != driver.strings[i]) return "written by another driver (" + shortDriver(stored) + ")";
    if (headerChecksum(e, size_t(stringBytes)) != get<uint64_t>(e, 64)) return "damaged header (checksum mismatch)";
    if (get<uint64_t>(e, 16) != lookup.keyLow || get<uint64_t>(e, 24) != lookup.keyHigh)
        return "holds another program than its name says";
    binaryAt = at;
    binaryBytes = get<uint64_t>(e, 48);
    if (binaryBytes == 0) return "damaged header (empty binary)";
    if (e.size() - at < binaryBytes)
        return "truncated (" + std::to_string(e.size()) + " of " + std::to_string(at + binaryBytes) + " bytes)";
    if (e.size() - at > binaryBytes)
        return "damaged (" + std::to_string(e.size() - at - binaryBytes) + " bytes after the binary)";
    if (XXH3_64bits(e.data() + at, size_t(binaryBytes)) != get<uint64_t>(e, 56))
        return "damaged (binary checksum mismatch)";
    format = GLenum(get<uint32_t>(e, 12));
    if (!driverOffersFormat(format)) return "binary format " + std::to_string(format) + " not offered by the driver";
    return "";
}

// Problems with the directory itself (not with one entry) are noted once per process.
void directoryNote(const std::string& what) {
    State& s = state();
    if (!s.directoryNoted) note("%s", what.c_str());
    s.directoryNoted = true;
}

void writeFailed(const std::string& what) {
    State& s = state();
    ++s.stats.writeFailures;
    if (s.writable) directoryNote(what + "; not writing entries in this run");
    s.writable = false;
}

} // namespace

std::string defaultProgramCacheDirectory() {
    return userCacheDirectory("PNB_PROGRAM_CACHE_DIR", "programs");
}

void configureProgramCache(const ProgramCacheOptions& options) {
    State& s = state();
    s.options = options;
    s.writable = true;
    s.directoryNoted = false;
    s.directory = options.enabled ? (options.directory.empty() ? defaultProgramCacheDirectory() : options.directory)
                                  : "";
    while (s.directory.size() > 1 && s.directory.back() == '/') s.directory.pop_back();
    if (options.enabled && s.directory.empty())
        note("off: no directory (set PNB_PROGRAM_CACHE_DIR, XDG_CACHE_HOME or HOME)");
    if (!s.directory.empty() && (!options.store.read || !options.store.write)) {
        note("off: no entry store given (ProgramCacheOptions::store)");
        s.directory.clear();
    }
    s.stats.enabled = !s.directory.empty();
    s.stats.directory = s.directory;
}

ProgramCacheStats programCacheStats() { return state().stats; }

void resetProgramCacheStats() {
    State& s = state();
    ProgramCacheStats fresh;
    fresh.enabled = s.stats.enabled;
    fresh.directory = s.stats.directory;
    s.stats = fresh;
}

ProgramCacheLookup programCacheLookup(std::span<const ProgramStageText> stages) {
    State& s = state();
    ProgramCacheLookup lookup;
    if (s.directory.empty()) return lookup;
    GLint formats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
    if (formats <= 0) {
        s.stats.binariesOffered = false;
        if (!s.noBinaryNoted)
            note("unused: the driver offers no program binary format (Mesa offers none while "
                 "MESA_SHADER_CACHE_DISABLE is set)");
        s.noBinaryNoted = true;
        return lookup;
    }
    // Every field with its length first, so "ab"+"c" and "a"+"bc" are different keys.
    std::string keyed;
    auto field = [&](uint64_t tag, std::string_view text) {
        uint64_t header[2] = {tag, uint64_t(text.size())};
        keyed.append(reinterpret_cast<const char*>(header), sizeof header);
        keyed.append(text);
    };
    for (const std::string& str : currentDriver().strings) field(0, str);
    for (const ProgramStageText& st : stages) field(uint64_t(st.stage), st.text);
    XXH128_hash_t key = XXH3_128bits(keyed.data(), keyed.size());
    char name[40];
    std::snprintf(name, sizeof name, "%016llx%016llx.bin", (unsigned long long)key.high64,
                  (unsigned long long)key.low64);
    lookup.active = true;
    lookup.keyLow = key.low64;
    lookup.keyHigh = key.high64;
    lookup.path = s.directory + "/" + name;
    return lookup;
}

GLuint loadCachedProgram(const ProgramCacheLookup& lookup, std::string_view label) {
    if (!lookup.active) return 0;
    State& s = state();
    ProgramCacheEntryRead read = s.options.store.read(lookup.path, kMaxEntryBytes);
    if (read.error != 0) {
        ++s.stats.misses;
        if (read.error != ENOENT) directoryNote("cannot read " + lookup.path + ": " + std::strerror(read.error));
        return 0;
    }
    std::vector<uint8_t> entry = std::move(read.bytes);
    if (read.oversized) entry.assign(kHeaderBytes - 1, 0); // judged "damaged" by its size below
    size_t binaryAt = 0;
    uint64_t binaryBytes = 0;
    GLenum format = 0;
    std::string why = validate(entry, lookup, currentDriver(), binaryAt, binaryBytes, format);
    if (why.empty()) {
        GLuint program = glCreateProgram();
        glProgramBinary(program, format, entry.data() + binaryAt, GLsizei(binaryBytes));
        GLint ok = GL_FALSE;
        glGetProgramiv(program, GL_LINK_STATUS, &ok);
        if (ok) {
            ++s.stats.hits;
            return program;
        }
        glDeleteProgram(program);
        why = "refused by the driver (glProgramBinary did not link)";
    }
    ++s.stats.rejected;
    note("ignored %s for %.*s: %s; compiling from source and rewriting it", lookup.path.c_str(),
         int(label.size()), label.data(), why.c_str());
    return 0;
}

void prepareProgramForCache(const ProgramCacheLookup& lookup, GLuint program) {
    if (lookup.active && state().writable)
        glProgramParameteri(program, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
}

void storeCachedProgram(const ProgramCacheLookup& lookup, GLuint program) {
    State& s = state();
    if (!lookup.active || !s.writable) return;
    GLint length = 0;
    glGetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &length);
    if (length <= 0) return; // nothing to keep (the driver would not give it back)
    Driver driver = currentDriver();
    size_t stringBytes = 0;
    for (const std::string& str : driver.strings) stringBytes += std::min<size_t>(str.size(), kMaxDriverString);
    std::vector<uint8_t> entry(kHeaderBytes + stringBytes + size_t(length));
    GLenum format = 0;
    GLsizei written = 0;
    glGetProgramBinary(program, length, &written, &format, entry.data() + kHeaderBytes + stringBytes);
    if (written <= 0) return;
    entry.resize(kHeaderBytes + stringBytes + size_t(written));
    std::memcpy(entry.data(), kMagic, sizeof kMagic);
    put<uint32_t>(entry, 8, kEntryVersion);
    put<uint32_t>(entry, 12, uint32_t(format));
    put<uint64_t>(entry, 16, lookup.keyLow);
    put<uint64_t>(entry, 24, lookup.keyHigh);
    size_t at = kHeaderBytes;
    for (int i = 0; i < 4; ++i) {
        uint32_t n = uint32_t(std::min<size_t>(driver.strings[i].size(), kMaxDriverString));
        put<uint32_t>(entry, 32 + 4 * size_t(i), n);
        std::memcpy(entry.data() + at, driver.strings[i].data(), n);
        at += n;
    }
    put<uint64_t>(entry, 48, uint64_t(written));
    put<uint64_t>(entry, 56, XXH3_64bits(entry.data() + at, size_t(written)));
    put<uint64_t>(entry, 64, headerChecksum(entry, stringBytes));

    if (std::string failure = s.options.store.write(s.directory, lookup.path, entry); !failure.empty())
        return writeFailed(failure);
    ++s.stats.written;
}

void countCompiledProgram(const ProgramCacheLookup& lookup) {
    if (!lookup.active) ++state().stats.uncached;
}

void addProgramTime(double ms) { state().stats.ms += ms; }

} // namespace pnb::player
