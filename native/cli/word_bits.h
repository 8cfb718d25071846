// Bytes of a 64-bit word, for the OBJ reader's and writer's eight-digits-at-a-time number code.
#pragma once

#include <cstdint>

namespace loopsub::obj {

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
inline constexpr bool kLittleEndian = false;
#else
inline constexpr bool kLittleEndian = true;
#endif

// The index of the lowest set bit of x (x is not 0).
inline int lowest_set_bit(std::uint64_t x) {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctzll(x);
#else
    int n = 0;
    for (; !(x & 1); x >>= 1) ++n;
    return n;
#endif
}

}  // namespace loopsub::obj
