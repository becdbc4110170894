// pnb_converter/memory_budget.h — how much memory the texture stage may plan to hold, and the
// --max-memory argument that pnb-convert and pnb-edit share.
//
// Why: an image header can declare any size (a 69-byte PNG can claim 16384 x 16384), so the
// decoder checks the memory a texture will need against a budget before it allocates anything.
// The default budget comes from the machine, not a constant, so a small machine refuses what it
// could not hold instead of being OOM-killed, and a big one still converts big textures.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace pnb::converter {

// Memory this process can use: the least of physical RAM (sysconf _SC_PHYS_PAGES x
// _SC_PAGE_SIZE), the address-space limit (RLIMIT_AS, e.g. `prlimit --as` or `ulimit -v`) and the
// cgroup memory limit (v2 memory.max, v1 memory.limit_in_bytes) when there is one.
uint64_t usableMemoryBytes();

// The default --max-memory: half of usableMemoryBytes(). The other half is left to the scene's
// meshes, the container being written and the rest of the machine.
uint64_t defaultMemoryBudget();

// "1048576", "512K", "64M", "1.5G", "2GiB", "1T" → bytes (binary multiples; a trailing "B" or
// "iB" is allowed). nullopt if malformed, zero or out of range.
std::optional<uint64_t> parseByteSize(std::string_view text);

// "5.75 GiB", "64.00 MiB", "512 B": for messages and --help.
std::string formatBytes(uint64_t bytes);

} // namespace pnb::converter
