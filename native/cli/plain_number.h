// Numbers as the OBJ reader's fast path reads them: what std::from_chars reads, in less time than libstdc++ 12's
// (docs/benchmark.md, "CLI I/O"), for the plain forms that this writer and most exporters write. read_float and
// read_integer try the plain forms first (eight digits at a time, floats by Clinger's exact method), give the same
// value and end as std::from_chars, and hand it everything else. The fast and general paths of the reader must read
// a line alike: tests/native/test_obj_io_fast.cpp compares them.
#pragma once

#include <cfloat>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <limits>
#include <system_error>

#include "word_bits.h"

// The parsers run once or twice per number: inlined into the line readers, they save a call's register saves and
// restores, about a third of their instructions.
#if defined(__GNUC__) || defined(__clang__)
#define LOOPSUB_PLAIN_NUMBER_INLINE inline __attribute__((always_inline))
#else
#define LOOPSUB_PLAIN_NUMBER_INLINE inline
#endif

namespace loopsub::obj {

namespace plain_number {

inline bool is_digit(char c) { return static_cast<unsigned>(c - '0') < 10; }

inline constexpr std::uint64_t kPowersOf10[] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000};
inline constexpr double kExactPowersOf10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                              1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// Reads the run of decimal digits at p into `value` (value * 10^n + the n digits) and adds n to `digits`; returns the
// end of the run, or nullptr once `digits` would pass max_digits (at most 19, so that value cannot overflow). Where 8
// bytes can be read, it takes up to 8 digits at once from a little-endian word.
LOOPSUB_PLAIN_NUMBER_INLINE const char* read_digit_run(const char* p, const char* end, std::uint64_t& value,
                                                       int& digits, int max_digits) {
    if constexpr (kLittleEndian) {
        while (end - p >= 8) {
            std::uint64_t word;
            std::memcpy(&word, p, sizeof word);
            // A byte's top bit is set here when it is not '0'-'9' (carries and borrows reach only later bytes).
            const std::uint64_t flags =
                ((word + 0x4646464646464646u) | (word - 0x3030303030303030u)) & 0x8080808080808080u;
            // The number of digit bytes before the first flagged one, 8 if none (the bit at 63 stands for byte 8).
            const int n = (lowest_set_bit((flags >> 7) | (std::uint64_t(1) << 63)) + 1) / 8;
            if (n == 0) return p;
            digits += n;
            if (digits > max_digits) return nullptr;
            // The n digit values moved to the top bytes, with zeros (leading zeros) below: one 8-digit number.
            std::uint64_t v = (word - 0x3030303030303030u) << (8 * (8 - n));
            v = v * 10 + (v >> 8);
            v = (((v & 0x000000ff000000ffu) * 0x000f424000000064u) +
                 (((v >> 16) & 0x000000ff000000ffu) * 0x0000271000000001u)) >>
                32;
            value = value * kPowersOf10[n] + std::uint32_t(v);
            p += n;
            if (n < 8) return p;
        }
    }
    for (; p < end && is_digit(*p); ++p) {
        if (++digits > max_digits) return nullptr;
        value = 10 * value + std::uint64_t(*p - '0');
    }
    return p;
}

// An optional '-' and 1 to 18 digits (no overflow possible).
LOOPSUB_PLAIN_NUMBER_INLINE const char* parse_plain_integer(const char* p, const char* end, std::int64_t& value) {
    const bool negative = p < end && *p == '-';
    const char* const start = p + negative;
    std::uint64_t n = 0;
    int digits = 0;
    p = read_digit_run(start, end, n, digits, 18);
    if (!p || p == start) return nullptr;
    value = negative ? -std::int64_t(n) : std::int64_t(n);
    return p;
}

// An optional '-', digits, optionally '.' and digits, optionally an exponent (e or E, an optional sign, 1 to 3
// digits), at most 19 digits in all; its value a normal float. The value is Clinger's: a significand below 2^53
// times or over an exact power of ten (at most 10^22) is one correctly rounded double operation. Rounding that
// double to float gives the float nearest the decimal, except when the double fell exactly on the midpoint
// between two floats (the decimal may lie on either side of it): then from_chars decides.
LOOPSUB_PLAIN_NUMBER_INLINE const char* parse_plain_float(const char* p, const char* end, float& value) {
    // Where double arithmetic is carried out in a wider type (x87), the one rounding is not to double.
    if constexpr (FLT_EVAL_METHOD != 0 && FLT_EVAL_METHOD != 1) return nullptr;
    const bool negative = p < end && *p == '-';
    p += negative;
    std::uint64_t significand = 0;
    int digits = 0;
    int exponent = 0;
    const char* const whole = p;
    p = read_digit_run(whole, end, significand, digits, 19);
    if (!p || p == whole) return nullptr;  // too many digits; ".5", "inf", "nan", "+1"...
    if (p < end && *p == '.') {
        const char* const fraction = p + 1;
        p = read_digit_run(fraction, end, significand, digits, 19);
        if (!p || p == fraction) return nullptr;  // too many digits; "1."
        exponent = -int(p - fraction);
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        ++p;
        const bool negative_exponent = p < end && *p == '-';
        if (p < end && (*p == '-' || *p == '+')) ++p;
        const char* const exponent_digits = p;
        int e = 0;
        for (; p < end && is_digit(*p); ++p) {
            if (p - exponent_digits == 3) return nullptr;
            e = 10 * e + (*p - '0');
        }
        if (p == exponent_digits) return nullptr;  // "1e", where from_chars stops before the 'e'
        exponent += negative_exponent ? -e : e;
    }
    if (significand > (std::uint64_t(1) << 53) || exponent < -22 || exponent > 22) return nullptr;
    double x = double(significand);
    x = exponent < 0 ? x / kExactPowersOf10[-exponent] : x * kExactPowersOf10[exponent];
    if (x != 0.0 &&
        !(x >= double(std::numeric_limits<float>::min()) && x <= double(std::numeric_limits<float>::max()))) {
        return nullptr;  // subnormal or out of range
    }
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    if ((bits & 0x1fffffff) == 0x10000000) return nullptr;  // the 29 bits below a float's precision: one half
    value = float(negative ? -x : x);
    return p;
}

}  // namespace plain_number

// std::from_chars, faster on plain forms.
LOOPSUB_PLAIN_NUMBER_INLINE std::from_chars_result read_float(const char* p, const char* end, float& value) {
    if (const char* next = plain_number::parse_plain_float(p, end, value)) return {next, std::errc()};
    return std::from_chars(p, end, value);
}

LOOPSUB_PLAIN_NUMBER_INLINE std::from_chars_result read_integer(const char* p, const char* end, std::int64_t& value) {
    if (const char* next = plain_number::parse_plain_integer(p, end, value)) return {next, std::errc()};
    return std::from_chars(p, end, value);
}

}  // namespace loopsub::obj
