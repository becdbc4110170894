// pnb/atomic_file.h — replacing a whole file atomically, for every tool that writes outputs
// (images, reports, glTF sources). Containers use pnb::Writer, which streams with the same
// protocol.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "pnb/error.h"

namespace pnb {

// Writes `bytes` to "<dir>/.<name>.tmp.<pid>.<n>" beside `path`, fsyncs it, renames it over
// `path` and fsyncs the directory: readers see the old file or the new one, never a part, and a
// crash leaves the old file. An existing file's permissions are kept. Errors (IoError) name the
// file and the failing step; the temporary is removed.
Status writeFileAtomic(const std::string& path, std::span<const uint8_t> bytes);

// The pieces pnb::Writer shares. createTemporaryFor makes a fresh "<dir>/.<name>.tmp.<pid>.<n>"
// beside `path` (same file system, so the rename is atomic), exclusively, and holds an flock on it
// for as long as `fd` stays open: the kernel drops that lock when the writer dies, however it
// dies, which is how a later writer tells a stale temporary from a live one. It first removes
// the stale temporaries of `path` (removeStaleTemporaries). Errors: IoError naming `path`.
struct TemporaryFile {
    int fd = -1;
    std::string path;
};
Result<TemporaryFile> createTemporaryFor(const std::string& path);
// Removes "<dir>/.<name>.tmp.<pid>.<n>" files of `path` whose writer is gone (no flock held,
// older than a second so that a writer between create and lock is never touched). Returns how
// many were removed; never fails (what it cannot remove it leaves).
size_t removeStaleTemporaries(const std::string& path);
// The directory to fsync after the rename ("." if none).
std::string directoryOf(const std::string& path);

} // namespace pnb
