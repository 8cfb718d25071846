// The loopsub command line: options into a Command, with a UsageError (exit 2) for anything malformed. Apart from
// main.cpp so that a fuzz target can drive it (fuzz/fuzz_cli.cpp).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include "loopsub/loopsub.h"
#include "loopsub/tessellation.h"

namespace loopsub::cli {

extern const char* const kUsage;

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A camera for --camera: where it stands and looks, and its picture (a perspective of a vertical field of view).
struct LookAt {
    float eye[3] = {0, 0, 0}, target[3] = {0, 0, -1}, up[3] = {0, 1, 0};
    float fov_degrees = 50.0f;
    int width = 1920, height = 1080;
    float dicing_rate = 1.0f;  // pixels per segment, or of deviation
    int max_rate = 64;
    DicingMeasure measure = DicingMeasure::Length;
};

struct Command {
    std::string input, output;
    Options options;
    std::optional<Boundary> boundary;  // from the flag; else the file's tag decides
    std::optional<CreaseMethod> crease_method;
    std::optional<FaceVaryingInterpolation> face_varying;  // from the flag; else the file's tag, else CornersOnly
    int tessellate = 0;            // > 0: tessellate at this rate per edge instead of refining by levels
    std::optional<LookAt> camera;  // tessellate at rates from this camera's screen instead
    bool stats = false;
    bool help = false;
};

// argv as main receives it (argv[0] is the program). Throws UsageError.
Command parse_command_line(int argc, char** argv);

}  // namespace loopsub::cli
