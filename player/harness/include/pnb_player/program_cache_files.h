// pnb_player/program_cache_files.h — the program binary cache's entries as files: the
// ProgramCacheStore (pnb_player/program_cache.h) that pnb-play and the load benchmark give the
// renderer, which reads and writes no file itself.
//
// Reads: the whole file, judged by the cache (a directory or other non-regular file is EISDIR).
// Writes: the directory created first, then a temporary file and a rename (pnb/atomic_file.h's
// temporary, without its fsyncs: a lost or torn entry is detected and rebuilt like a damaged
// one, and a first launch should not wait for the disk).
#pragma once

#include "pnb_player/program_cache.h"

namespace pnb::player {

ProgramCacheStore programCacheFiles();

// configureProgramCache(options) with programCacheFiles() as its store.
void configureProgramCacheOnDisk(ProgramCacheOptions options);

} // namespace pnb::player
