// pnb/output_guard.h — an output never replaces an input, two outputs are never one file, and
// inputs are regular files.
//
// Every tool that writes (pnb-convert, its batch mode, pnb-edit -o, pnb-sweep's outputs) names the
// files it reads and the files it will write, each with a role for the message, and asks
// checkOutputs before it writes anything. Two names are one file when they resolve to the same
// place: the same device and inode (hard links, symlinks to the file, "./x" and "x"), or, for a
// file that does not exist yet, the same path once symlinked directories are resolved
// (std::filesystem::weakly_canonical). What a tool reads after the check (a glTF's images) it
// checks again before writing (pnb-convert: the output against every file the conversion read).
#pragma once

#include <span>
#include <string>

#include "pnb/error.h"

namespace pnb {

struct RoleFile {
    std::string path;
    std::string role; // "the input", "the sidecar", "the output of list line 3", ...
};

// OutputConflict naming both files and their roles when an output is one of the inputs or
// another output; ok otherwise. Empty paths are skipped (an option not given).
Status checkOutputs(std::span<const RoleFile> inputs, std::span<const RoleFile> outputs);

// Inputs are regular files (or symlinks to one): a FIFO, a device, a socket or a directory is
// refused up front (IoError naming the role, the path and what it is), because reading a FIFO
// or a device can wait forever or never end. A missing file passes: the reader reports it.
Status checkInputs(std::span<const RoleFile> inputs);

} // namespace pnb
