// pnb/error.h — error values for bad data, shared by every part of the container library.
//
// Penumbra uses three error channels (docs/STYLE.md §5): bad data (files, user input) produces a
// returned Error value, never an assert or an exception; API misuse is a precondition check;
// internal invariants are asserts. This header is the first channel.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <variant>

namespace pnb {

// What is wrong with a file. Stable names: they appear in tool output and tests.
enum class FormatError : uint8_t {
    None = 0,
    IoError,                 // the operating system refused a read/write/open/rename
    Truncated,               // the file ends before a structure it declares
    BadMagic,                // not a .pnb file, or damaged by a text-mode transfer
    UnsupportedVersion,      // file major version newer than this reader
    BadEndianness,           // endianness marker is not the little-endian one
    HeaderChecksumMismatch,  // file header, chunk header or footer bytes were altered
    BadHeader,               // a header field has an impossible value (reserved bits, sizes)
    BadChunkSize,            // a chunk size overflows or runs past the end of the file
    BadPadding,              // alignment padding is not zero
    ChecksumMismatch,        // a payload's xxh3 checksum does not match its bytes
    DecompressionFailed,     // zstd rejected the payload, or it inflated to the wrong size
    LimitExceeded,           // a declared size exceeds the reader's configured limit
    BadToc,                  // the table of contents disagrees with the chunks
    TrailingBytes,           // bytes after the footer
    BadPayload,              // a typed chunk payload does not decode
    UnsupportedChunkVersion, // a known chunk kind with a newer chunk version
    BadReference,            // an index refers to something that does not exist (or later)
    Missing,                 // a required chunk is absent
    Locked,                  // another program is saving the file (its lock, file_lock.h)
    ChangedOnDisk,           // another program replaced the file since this one read it
    OutputConflict,          // an output is an input, or two outputs are one file (output_guard.h)
};

// Stable lowercase name of an error code, e.g. "checksum-mismatch".
const char* toString(FormatError e);

// A bad-data error: what, where (absolute byte offset in the file, or in the buffer handed to a
// decoder), and a sentence a user can act on.
struct Error {
    FormatError code = FormatError::None;
    uint64_t offset = 0;
    std::string message;

    // "checksum-mismatch at byte 4096: chunk 3 'MESH' payload checksum ..."
    std::string describe() const;
};

// Either a value or an error (pnb::Error unless stated). A minimal std::expected stand-in
// (C++20 has none). Other modules reuse it with their own error type.
template <class T, class E = Error> class [[nodiscard]] Result {
public:
    Result(T value) : mValue(std::move(value)) {}
    Result(E error) : mValue(std::move(error)) {}

    bool ok() const { return mValue.index() == 0; }
    explicit operator bool() const { return ok(); }

    // Precondition: ok().
    T& value() & { return std::get<0>(mValue); }
    const T& value() const& { return std::get<0>(mValue); }
    T&& value() && { return std::get<0>(std::move(mValue)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

    // Precondition: !ok().
    const E& error() const { return std::get<1>(mValue); }

private:
    std::variant<T, E> mValue;
};

// Result of an operation with no value: Error with code None means success.
using Status = Error;
inline bool isOk(const Status& s) { return s.code == FormatError::None; }

// Builds an Error with a printf-style message.
Error makeError(FormatError code, uint64_t offset, const char* fmt, ...)
    __attribute__((format(printf, 3, 4)));

} // namespace pnb
