// What the plan's parts share: the error for bad input, number formatting, timing.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include "loopsub/loopsub.h"

namespace loopsub::detail {

[[noreturn]] inline void fail(const std::string& message) { throw InputError(message); }

// A float as printf's %g writes it with float precision: 3.402823e+38, not 39 digits.
inline std::string shortest(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.7g", double(value));
    return text;
}

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace loopsub::detail
