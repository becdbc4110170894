#include "pnb/error.h"

#include <cstdarg>
#include <cstdio>

#include "pnb/tags.h"

namespace pnb {

const char* toString(FormatError e) {
    switch (e) {
    case FormatError::None: return "ok";
    case FormatError::IoError: return "io-error";
    case FormatError::Truncated: return "truncated";
    case FormatError::BadMagic: return "bad-magic";
    case FormatError::UnsupportedVersion: return "unsupported-version";
    case FormatError::BadEndianness: return "bad-endianness";
    case FormatError::HeaderChecksumMismatch: return "header-checksum-mismatch";
    case FormatError::BadHeader: return "bad-header";
    case FormatError::BadChunkSize: return "bad-chunk-size";
    case FormatError::BadPadding: return "bad-padding";
    case FormatError::ChecksumMismatch: return "checksum-mismatch";
    case FormatError::DecompressionFailed: return "decompression-failed";
    case FormatError::LimitExceeded: return "limit-exceeded";
    case FormatError::BadToc: return "bad-toc";
    case FormatError::TrailingBytes: return "trailing-bytes";
    case FormatError::BadPayload: return "bad-payload";
    case FormatError::UnsupportedChunkVersion: return "unsupported-chunk-version";
    case FormatError::BadReference: return "bad-reference";
    case FormatError::Missing: return "missing";
    case FormatError::Locked: return "locked";
    case FormatError::ChangedOnDisk: return "changed-on-disk";
    case FormatError::OutputConflict: return "output-conflict";
    }
    return "unknown-error";
}

std::string Error::describe() const {
    if (code == FormatError::None) return "ok";
    return std::string(toString(code)) + " at byte " + std::to_string(offset) + ": " + message;
}

Error makeError(FormatError code, uint64_t offset, const char* fmt, ...) {
    char buf[512];
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(buf, sizeof(buf), fmt, args);
    va_end(args);
    return Error{code, offset, buf};
}

std::string Tag::str() const {
    std::string s(4, '?');
    for (int i = 0; i < 4; ++i) {
        unsigned char ch = static_cast<unsigned char>(c[i]);
        if (ch >= 0x20 && ch < 0x7F) s[i] = static_cast<char>(ch);
    }
    return s;
}

} // namespace pnb
