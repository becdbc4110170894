// Little-endian load/store helpers. Internal to the format library.
//
// The format is little-endian whatever the host; these compile to plain moves on x86/ARM-LE.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace pnb::detail {

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big,
              "mixed-endian hosts are not supported");

template <class T> inline T byteswapIfBig(T v) {
    if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
        unsigned char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        for (size_t i = 0; i < sizeof(T) / 2; ++i) {
            unsigned char t = b[i];
            b[i] = b[sizeof(T) - 1 - i];
            b[sizeof(T) - 1 - i] = t;
        }
        std::memcpy(&v, b, sizeof(T));
    }
    return v;
}

// Precondition: p points at sizeof(T) readable bytes. T is an integer or float.
template <class T> inline T loadLE(const std::byte* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return byteswapIfBig(v);
}

template <class T> inline void storeLE(std::byte* p, T v) {
    v = byteswapIfBig(v);
    std::memcpy(p, &v, sizeof(T));
}

} // namespace pnb::detail
