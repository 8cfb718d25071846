#include "command_line.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <vector>

#include "loopsub/tessellation.h"

namespace loopsub::cli {

const char* const kUsage =
    "usage: loopsub IN.obj OUT.obj --levels N [options]\n"
    "       loopsub IN.obj OUT.obj --tessellate N [options]\n"
    "       loopsub IN.obj OUT.obj --camera EX,EY,EZ,TX,TY,TZ [--dicing-rate PX] [options]\n"
    "\n"
    "Subdivides the triangle mesh IN.obj N times by Loop's scheme and writes OUT.obj with the child crease,\n"
    "corner and cone tags. Polygons with more than 3 corners are triangulated by ear clipping (with a notice).\n"
    "With --tessellate, cuts each triangle into N segments per edge instead (with --camera, as many as its\n"
    "picture needs), every point on the limit surface, with its normals (vn); UVs go linearly within each\n"
    "triangle; no tags are written.\n"
    "\n"
    "options:\n"
    "  --levels N                    subdivision levels, N >= 0 (this, --tessellate or --camera is required)\n"
    "  --tessellate N                segments per edge, 1 to 4096: the limit surface at that rate (N = 2^L:\n"
    "                                the vertices of --levels L --limit)\n"
    "  --camera EX,EY,EZ,TX,TY,TZ    instead of a rate: each edge as many segments as its length on screen holds\n"
    "                                --dicing-rate pixels, seen from a camera at E looking at T (Cycles' dicing)\n"
    "  --up X,Y,Z                    the camera's up (default 0,1,0)\n"
    "  --fov DEG                     its vertical field of view, 1 to 179 degrees (default 50)\n"
    "  --viewport W,H                its picture in pixels (default 1920,1080)\n"
    "  --dicing-rate PX              pixels per segment, > 0 (default 1); with --dicing-measure deviation, how far\n"
    "                                in pixels a segment may stray from the surface\n"
    "  --dicing-measure length|deviation\n"
    "                                what --dicing-rate holds an edge to (default length, as Cycles)\n"
    "  --max-rate N                  at most N segments per edge, 1 to 4096 (default 64)\n"
    "  --rules hoppe94|opensubdiv    rule set (default hoppe94)\n"
    "  --crease-threshold S          hoppe94: an edge is a crease when its sharpness is >= S (default 0: any\n"
    "                                positive sharpness)\n"
    "  --boundary edges|edges-and-corners|none\n"
    "                                boundary rule (default: the file's interpolateboundary tag, else edges);\n"
    "                                none: faces at a boundary not tagged sharp become holes\n"
    "  --crease-method uniform|chaikin\n"
    "                                opensubdiv: semi-sharp decay (default: the file's creasemethod tag, else\n"
    "                                uniform)\n"
    "  --limit                       put the result on the limit surface and write its normals (vn), split\n"
    "                                across creases and boundaries\n"
    "  --uv-interpolation MODE       none|corners|corners-plus1|corners-plus2|boundaries|all: where UVs stay\n"
    "                                linear (default: the file's facevaryinginterpolateboundary tag, else\n"
    "                                corners, as OpenSubdiv)\n"
    "  --threads N                   worker threads, 1 to 256 (default 1)\n"
    "  --scalar                      force the scalar reference kernel instead of SIMD\n"
    "  --memory-limit-mb N           refuse a refinement that would need more than N MiB (default 4096)\n"
    "  --stats                       print one line of timings and counts on stdout\n"
    "  --help                        print this help\n";

namespace {

std::int64_t parse_integer(std::string_view flag, std::string_view text, std::int64_t min, std::int64_t max) {
    std::int64_t value = 0;
    auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error == std::errc::result_out_of_range)
        throw UsageError(std::string(flag) + " is out of range: " + std::string(text));
    if (error != std::errc() || end != text.data() + text.size() || text.empty()) {
        throw UsageError(std::string(flag) + " expects an integer, got '" + std::string(text) + "'");
    }
    if (value < min)
        throw UsageError(std::string(flag) + " must be >= " + std::to_string(min) + ", got " + std::string(text));
    if (value > max)
        throw UsageError(std::string(flag) + " must be <= " + std::to_string(max) + ", got " + std::string(text));
    return value;
}

float parse_nonnegative_float(std::string_view flag, std::string_view text) {
    float value = 0.0f;
    auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || text.empty() || !std::isfinite(value)) {
        throw UsageError(std::string(flag) + " expects a number, got '" + std::string(text) + "'");
    }
    if (value < 0.0f) throw UsageError(std::string(flag) + " must be >= 0, got " + std::string(text));
    return value;
}

// count comma-separated finite numbers.
std::vector<float> parse_floats(std::string_view flag, std::string_view text, std::size_t count) {
    std::vector<float> values;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string_view part = text.substr(start, comma - start);
        float value = 0.0f;
        auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
        if (error != std::errc() || end != part.data() + part.size() || part.empty() || !std::isfinite(value))
            throw UsageError(std::string(flag) + " expects " + std::to_string(count) +
                             " numbers separated by commas, got '" + std::string(text) + "'");
        values.push_back(value);
        start = comma + 1;
    }
    if (values.size() != count)
        throw UsageError(std::string(flag) + " expects " + std::to_string(count) +
                         " numbers separated by commas, got '" + std::string(text) + "'");
    return values;
}

// One of the option's names (loopsub::option_names).
template <typename Option>
Option parse_name(std::string_view flag, const std::string& text) {
    Option value{};
    if (!parse_option(text, value))
        throw UsageError(std::string(flag) + " expects " + option_names<Option>().listed() + ", got '" + text + "'");
    return value;
}

}  // namespace

Command parse_command_line(int argc, char** argv) {
    Command command;
    std::vector<std::string> positional;
    bool levels_given = false, camera_given = false;
    LookAt look;
    std::vector<std::string> camera_options;  // given without --camera, they would be ignored
    for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i];
        if (arg.size() < 2 || arg.compare(0, 2, "--") != 0) {
            positional.push_back(arg);
            continue;
        }
        // Both "--flag value" and "--flag=value".
        std::optional<std::string> inline_value;
        if (std::size_t eq = arg.find('='); eq != std::string::npos) {
            inline_value = arg.substr(eq + 1);
            arg.resize(eq);
        }
        auto value = [&]() -> std::string {
            if (inline_value) return *inline_value;
            if (i + 1 >= argc) throw UsageError(arg + " needs a value");
            return argv[++i];
        };
        auto no_value = [&] {
            if (inline_value) throw UsageError(arg + " takes no value");
        };

        if (arg == "--help") {
            no_value();
            command.help = true;
        } else if (arg == "--levels") {
            command.options.levels = int(parse_integer(arg, value(), 0, loopsub::kMaxLevels));
            levels_given = true;
        } else if (arg == "--tessellate") {
            command.tessellate = int(parse_integer(arg, value(), 1, loopsub::kMaxTessellationRate));
        } else if (arg == "--camera") {
            const std::vector<float> v = parse_floats(arg, value(), 6);
            camera_given = true;
            std::copy(v.begin(), v.begin() + 3, look.eye), std::copy(v.begin() + 3, v.end(), look.target);
        } else if (arg == "--up") {
            const std::vector<float> v = parse_floats(arg, value(), 3);
            std::copy(v.begin(), v.end(), look.up), camera_options.push_back(arg);
        } else if (arg == "--fov") {
            look.fov_degrees = parse_floats(arg, value(), 1)[0], camera_options.push_back(arg);
            if (!(look.fov_degrees >= 1.0f && look.fov_degrees <= 179.0f))
                throw UsageError("--fov must be between 1 and 179 degrees");
        } else if (arg == "--viewport") {
            const std::string text = value();
            look.width = int(parse_integer(arg, text.substr(0, text.find(',')), 1, 1 << 16));
            look.height = int(parse_integer(
                arg, text.find(',') == std::string::npos ? "" : text.substr(text.find(',') + 1), 1, 1 << 16));
            camera_options.push_back(arg);
        } else if (arg == "--dicing-rate") {
            look.dicing_rate = parse_floats(arg, value(), 1)[0], camera_options.push_back(arg);
            if (!(look.dicing_rate > 0.0f)) throw UsageError("--dicing-rate must be > 0");
        } else if (arg == "--dicing-measure") {
            const std::string text = value();
            if (text != "length" && text != "deviation")
                throw UsageError("--dicing-measure expects length or deviation, got '" + text + "'");
            look.measure = text == "length" ? DicingMeasure::Length : DicingMeasure::Deviation;
            camera_options.push_back(arg);
        } else if (arg == "--max-rate") {
            look.max_rate = int(parse_integer(arg, value(), 1, loopsub::kMaxTessellationRate));
            camera_options.push_back(arg);
        } else if (arg == "--rules") {
            command.options.rules = parse_name<Rules>(arg, value());
        } else if (arg == "--crease-threshold") {
            command.options.crease_threshold = parse_nonnegative_float(arg, value());
        } else if (arg == "--boundary") {
            command.boundary = parse_name<Boundary>(arg, value());
        } else if (arg == "--limit") {
            no_value();
            command.options.limit_surface = true;
        } else if (arg == "--uv-interpolation") {
            command.face_varying = parse_name<FaceVaryingInterpolation>(arg, value());
        } else if (arg == "--crease-method") {
            command.crease_method = parse_name<CreaseMethod>(arg, value());
        } else if (arg == "--threads") {
            command.options.threads = int(parse_integer(arg, value(), 1, loopsub::kMaxThreads));
        } else if (arg == "--scalar") {
            no_value();
            command.options.kernel = Kernel::Scalar;
        } else if (arg == "--memory-limit-mb") {
            command.options.memory_limit_bytes = std::uint64_t(parse_integer(arg, value(), 1, std::int64_t(1) << 40))
                                                 << 20;
        } else if (arg == "--stats") {
            no_value();
            command.stats = true;
        } else {
            throw UsageError("unknown option '" + arg + "'");
        }
    }
    if (command.help) return command;
    if (positional.size() != 2) {
        throw UsageError("expected IN.obj and OUT.obj, got " + std::to_string(positional.size()) + " file argument(s)");
    }
    if (!camera_given && !camera_options.empty()) throw UsageError(camera_options.front() + " needs --camera");
    if (int(levels_given) + int(command.tessellate > 0) + int(camera_given) > 1)
        throw UsageError("--levels, --tessellate and --camera exclude each other");
    if (!levels_given && command.tessellate == 0 && !camera_given)
        throw UsageError("--levels N, --tessellate N or --camera is required");
    if (camera_given) {
        try {  // the core's check that the flags make a view, here: a wrong command line exits 2 before any reading
            loopsub::look_at_camera(look.eye, look.target, look.up, look.fov_degrees, float(look.width),
                                    float(look.height));
        } catch (const loopsub::InputError&) {
            throw UsageError("--camera: the eye, the target and --up must span a view");
        }
        command.camera = look;
    }
    command.input = positional[0];
    command.output = positional[1];
    return command;
}

}  // namespace loopsub::cli
