// The loopsub command line: options into a Command, with a UsageError (exit 2) for anything malformed. Apart from
// main.cpp so that a fuzz target can drive it (fuzz/fuzz_cli.cpp).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include "loopsub/loopsub.h"

namespace loopsub::cli {

extern const char* const kUsage;

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct Command {
    std::string input, output;
    Options options;
    std::optional<Boundary> boundary;  // from the flag; else the file's tag decides
    std::optional<CreaseMethod> crease_method;
    std::optional<FaceVaryingInterpolation> face_varying;  // from the flag; else the file's tag, else CornersOnly
    int tessellate = 0;  // > 0: tessellate at this rate per edge instead of refining by levels
    bool stats = false;
    bool help = false;
};

// argv as main receives it (argv[0] is the program). Throws UsageError.
Command parse_command_line(int argc, char** argv);

}  // namespace loopsub::cli
