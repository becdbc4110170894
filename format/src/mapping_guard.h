// mapping_guard.h — survives a mapped file being truncated under us. Reading a page of a
// MAP_PRIVATE file mapping beyond the file's current end raises SIGBUS, and another program can
// truncate a file at any moment (an editor saving in place, `> file`, a half-finished copy).
// The guard's SIGBUS handler replaces the missing pages of a registered mapping with zero pages
// and records the first missing offset, so the access completes and the reader reports a clean
// error naming the file instead of the process dying. The zeros never reach a caller as data:
// Container checks truncatedAt() after reading and turns any read into an IoError.
//
// Does NOT: protect mappings it was not told about (other signals and addresses go to the
// previous handler or the default action); guard more than kSlots mappings at once (the rest
// still work, unguarded); detect a file rewritten in place without shrinking.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pnb::detail {

inline constexpr int kNoGuard = -1;

// Registers [base, base + size) and installs the handler on first use. Returns a slot for
// truncatedAt()/unguardMapping(), or kNoGuard if every slot is taken or sigaction failed.
int guardMapping(const void* base, size_t size);
// Call before munmap. No-op for kNoGuard.
void unguardMapping(int slot);
// Offset (from base) of the first page found missing, or UINT64_MAX while none was.
uint64_t truncatedAt(int slot);

} // namespace pnb::detail
