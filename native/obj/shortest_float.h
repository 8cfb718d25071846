// Floats as the OBJ writer writes them: what std::to_chars writes (the shortest form that reads back exactly), in
// less time than libstdc++ 12's std::to_chars(float) (docs/benchmark.md, "CLI I/O"): the same characters, the same
// shortest digits, the same choice between fixed and scientific notation. It was compared with
// std::to_chars on all 2^32 floats, and tests/native/test_obj_io_fast.cpp compares a sample of them. Inline: it runs
// once per number, inside the writer's line loops.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace loopsub::obj {

namespace shortest_float {

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

inline int lowest_nonzero_byte(std::uint64_t x) { return lowest_set_bit(x) / 8; }

// Digits are made eight at a time in one 64-bit word: the eight digits of a number below 10^8 as byte values, the
// first in the lowest byte (Paul Khuong's method: 10^4, then 10^2, then 10 split off in 32-, 16- and 8-bit lanes
// with multiplications). Adding '0' to each byte and storing the word little-endian writes their text.
inline std::uint64_t eight_digits(std::uint32_t value) {
    const std::uint64_t merged = std::uint64_t(value / 10000) | (std::uint64_t(value % 10000) << 32);
    const std::uint64_t top = ((merged * 10486u) >> 20) & 0x0000007f0000007fu;  // / 100 in each 32-bit lane
    const std::uint64_t hundreds = ((merged - 100 * top) << 16) + top;
    std::uint64_t tens = ((hundreds * 103u) >> 10) & 0x000f000f000f000fu;  // / 10 in each 16-bit lane
    tens += (hundreds - 10 * tens) << 8;
    return tens;
}

inline constexpr std::uint64_t kZeroChars = 0x3030303030303030u;

// Writes the eight bytes of a digit word (lowest byte first) at out.
inline void store_digits(char* out, std::uint64_t word) {
    if constexpr (kLittleEndian) {
        std::memcpy(out, &word, sizeof word);
    } else {
        for (int k = 0; k < 8; ++k) out[k] = char(word >> (8 * k));
    }
}

// Schubfach (Raffaello Giulietti, 2020), for binary32 as in Alexander Bolz's Drachennest: the shortest decimal in
// the float's rounding interval, the nearest to it when several are as short (ties to even), as Ryu, the algorithm
// libstdc++ runs inside to_chars, finds it, but in three multiplications and no loop over digits.
// kPow10Single[k + 31] = ceil(10^k * 2^(63 - floor(log2(10^k)))) for -31 <= k <= 45.
inline constexpr std::uint64_t kPow10Single[77] = {
    0x81CEB32C4B43FCF5, 0xA2425FF75E14FC32, 0xCAD2F7F5359A3B3F, 0xFD87B5F28300CA0E, 0x9E74D1B791E07E49,
    0xC612062576589DDB, 0xF79687AED3EEC552, 0x9ABE14CD44753B53, 0xC16D9A0095928A28, 0xF1C90080BAF72CB2,
    0x971DA05074DA7BEF, 0xBCE5086492111AEB, 0xEC1E4A7DB69561A6, 0x9392EE8E921D5D08, 0xB877AA3236A4B44A,
    0xE69594BEC44DE15C, 0x901D7CF73AB0ACDA, 0xB424DC35095CD810, 0xE12E13424BB40E14, 0x8CBCCC096F5088CC,
    0xAFEBFF0BCB24AAFF, 0xDBE6FECEBDEDD5BF, 0x89705F4136B4A598, 0xABCC77118461CEFD, 0xD6BF94D5E57A42BD,
    0x8637BD05AF6C69B6, 0xA7C5AC471B478424, 0xD1B71758E219652C, 0x83126E978D4FDF3C, 0xA3D70A3D70A3D70B,
    0xCCCCCCCCCCCCCCCD, 0x8000000000000000, 0xA000000000000000, 0xC800000000000000, 0xFA00000000000000,
    0x9C40000000000000, 0xC350000000000000, 0xF424000000000000, 0x9896800000000000, 0xBEBC200000000000,
    0xEE6B280000000000, 0x9502F90000000000, 0xBA43B74000000000, 0xE8D4A51000000000, 0x9184E72A00000000,
    0xB5E620F480000000, 0xE35FA931A0000000, 0x8E1BC9BF04000000, 0xB1A2BC2EC5000000, 0xDE0B6B3A76400000,
    0x8AC7230489E80000, 0xAD78EBC5AC620000, 0xD8D726B7177A8000, 0x878678326EAC9000, 0xA968163F0A57B400,
    0xD3C21BCECCEDA100, 0x84595161401484A0, 0xA56FA5B99019A5C8, 0xCECB8F27F4200F3A, 0x813F3978F8940985,
    0xA18F07D736B90BE6, 0xC9F2C9CD04674EDF, 0xFC6F7C4045812297, 0x9DC5ADA82B70B59E, 0xC5371912364CE306,
    0xF684DF56C3E01BC7, 0x9A130B963A6C115D, 0xC097CE7BC90715B4, 0xF0BDC21ABB48DB21, 0x96769950B50D88F5,
    0xBC143FA4E250EB32, 0xEB194F8E1AE525FE, 0x92EFD1B8D0CF37BF, 0xB7ABC627050305AE, 0xE596B7B0C643C71A,
    0x8F7E32CE7BEA5C70, 0xB35DBF821AE4F38C,
};

struct Decimal {
    std::uint32_t digits;  // no trailing zeros
    int exponent;          // value = digits * 10^exponent
};

// The upper 32 bits of g * cp / 2^32, rounded to odd.
inline std::uint32_t round_to_odd(std::uint64_t g, std::uint32_t cp) {
#ifdef __SIZEOF_INT128__
    const std::uint64_t high = std::uint64_t((static_cast<unsigned __int128>(g) * cp) >> 32);
#else
    const std::uint64_t low = (g & 0xffffffffu) * cp;
    const std::uint64_t high = (g >> 32) * cp + (low >> 32);
#endif
    return std::uint32_t(high >> 32) | (std::uint32_t(high) > 1);
}

// The shortest decimal of c * 2^q, a float that is not a small whole number; its digits may end in zeros.
inline Decimal schubfach(std::uint32_t c, int q, bool lower_boundary_closer) {
    const bool even = c % 2 == 0;
    const std::uint32_t cbl = 4 * c - 2 + lower_boundary_closer, cb = 4 * c, cbr = 4 * c + 2;
    // floor(log10(2^q)), or floor(log10(3/4 * 2^q)) when the lower neighbour is nearer; arithmetic shifts.
    const int k = (q * 1262611 - (lower_boundary_closer ? 524031 : 0)) >> 22;
    const int h = q + ((-k * 1741647) >> 19) + 1;  // q + floor(log2(10^-k)) + 1, between 1 and 4
    const std::uint64_t pow10 = kPow10Single[-k + 31];
    const std::uint32_t vbl = round_to_odd(pow10, cbl << h);
    const std::uint32_t vb = round_to_odd(pow10, cb << h);
    const std::uint32_t vbr = round_to_odd(pow10, cbr << h);
    const std::uint32_t lower = vbl + !even, upper = vbr - !even;

    // One digit less when exactly one multiple of 10^(k+1) next to v lies in the interval (at most one can); else s
    // or s + 1 (times 10^k), whichever lies in it, or the nearer if both do (s on a tie if s is even). Both are
    // computed and one selected: which one it is varies at random from float to float.
    const std::uint32_t s = vb / 4, sp = s / 10;
    const bool up_inside = lower <= 40 * sp, wp_inside = 40 * sp + 40 <= upper;
    const bool u_inside = lower <= 4 * s, w_inside = 4 * s + 4 <= upper;
    const std::uint32_t mid = 4 * s + 2;
    const bool nearer_up = (vb > mid) | ((vb == mid) & ((s & 1) != 0));
    const bool up = (u_inside != w_inside) ? w_inside : nearer_up;
    const bool shorter = (s >= 10) & (up_inside != wp_inside);
    const std::uint32_t mask = 0u - std::uint32_t(shorter);  // a select the compiler cannot turn into a branch
    return {((sp + wp_inside) & mask) | ((s + up) & ~mask), k + shorter};
}

// The positive finite float with these IEEE fields.
inline Decimal shortest_decimal(std::uint32_t ieee_mantissa, std::uint32_t ieee_exponent) {
    Decimal result;
    if (ieee_exponent == 0) {
        result = schubfach(ieee_mantissa, -149, false);
    } else {
        const std::uint32_t c = (1u << 23) | ieee_mantissa;
        const int q = int(ieee_exponent) - 150;
        if (q <= 0 && q > -24 && (c & ((1u << -q) - 1)) == 0) {
            result = {c >> -q, 0};  // a whole number below 2^24 is its own shortest form
        } else {
            result = schubfach(c, q, ieee_mantissa == 0 && ieee_exponent > 1);
        }
    }
    while (result.digits % 10 == 0) {
        result.digits /= 10;
        ++result.exponent;
    }
    return result;
}

// std::to_chars writes 15 characters at most ("-1.00000075e-36"; all 2^32 floats tried).
inline constexpr std::size_t kLongestFloat = 16;

}  // namespace shortest_float

// Writes what std::to_chars(out, end, value) writes: the shortest form that reads back exactly, in fixed notation
// unless scientific is shorter (fixed on a tie), a whole number in fixed notation written exactly. Writes up to
// 27 bytes; returns the end of the number.
inline char* put_float(char* out, float value) {
    using namespace shortest_float;
    std::uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    const std::uint32_t ieee_exponent = (bits >> 23) & 0xff, ieee_mantissa = bits & 0x7fffff;
    if (ieee_exponent == 0xff) return std::to_chars(out, out + kLongestFloat, value).ptr;  // inf, nan
    *out = '-';
    out += bits >> 31;
    if (ieee_exponent == 0 && ieee_mantissa == 0) {
        *out = '0';
        return out + 1;
    }
    const Decimal decimal = shortest_decimal(ieee_mantissa, ieee_exponent);
    // The digits (at most 9) as 12 characters with leading zeros, then zeros, so that 16 bytes can be copied from
    // any of the first 16 positions.
    char padded[32] = {};
    const std::uint32_t first = decimal.digits / 100000000;
    const std::uint64_t rest = eight_digits(decimal.digits % 100000000);
    std::memcpy(padded, "000", 3);
    padded[3] = char('0' + first);
    store_digits(padded + 4, rest + kZeroChars);
    const int length = first ? 9 : 8 - lowest_nonzero_byte(rest | (std::uint64_t(1) << 56));
    const char* const digits = padded + 12 - length;
    const int exponent = decimal.exponent;
    // libstdc++'s bounds for the plain format: fixed notation is not longer than scientific.
    const int lower_bound = length == 1 ? -3 : -(length + 3);
    const int upper_bound = length == 1 ? 4 : 5;
    if (exponent < lower_bound || exponent > upper_bound) {
        // d.ddde+XX, or de+XX; a float's exponent has two digits.
        out[0] = digits[0];
        out[1] = '.';
        std::memcpy(out + 2, digits + 1, 8);
        out += length == 1 ? 1 : length + 1;
        const int scientific_exponent = std::abs(exponent + length - 1);
        out[0] = 'e';
        out[1] = exponent + length - 1 < 0 ? '-' : '+';
        out[2] = char('0' + scientific_exponent / 10);
        out[3] = char('0' + scientific_exponent % 10);
        return out + 4;
    }
    if (exponent >= 0) {
        // A whole number, below 10^14: printed exactly ("as if by printf"), not as the shortest digits and zeros.
        return std::to_chars(out, out + 24, std::uint64_t(std::fabs(value))).ptr;
    }
    const int fraction = -exponent;  // at most length + 3 <= 12
    if (length <= fraction) {
        // 0.000ddd: the zeros after the point are the padding's.
        std::memcpy(out, "0.", 2);
        std::memcpy(out + 2, padded + 12 - fraction, 16);
        return out + 2 + fraction;
    }
    const int whole = length - fraction;
    std::memcpy(out, digits, 16);
    out[whole] = '.';
    std::memcpy(out + whole + 1, padded + 12 - fraction, 16);
    return out + length + 1;
}

}  // namespace loopsub::obj
