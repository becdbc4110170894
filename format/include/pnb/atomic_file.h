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

// The pieces pnb::Writer shares: a fresh "<dir>/.<name>.tmp.<pid>.<n>" beside `path` (same file
// system, so the rename is atomic), and the directory to fsync after the rename ("." if none).
std::string temporaryPathFor(const std::string& path);
std::string directoryOf(const std::string& path);

} // namespace pnb
