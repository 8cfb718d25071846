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

// The flags read so far, one argument at a time, and what they leave to check once all are read.
class Parser {
public:
    explicit Parser(int argc, char** argv) : argc_(argc), argv_(argv) {}

    Command parse() {
        for (i_ = 1; i_ < argc_; ++i_) {
            std::string arg = argv_[i_];
            if (arg.size() < 2 || arg.compare(0, 2, "--") != 0) {
                positional_.push_back(arg);
                continue;
            }
            // Both "--flag value" and "--flag=value".
            inline_value_.reset();
            if (std::size_t eq = arg.find('='); eq != std::string::npos) {
                inline_value_ = arg.substr(eq + 1);
                arg.resize(eq);
            }
            flag_ = arg;
            if (!read_camera_flag() && !read_option_flag()) throw UsageError("unknown option '" + flag_ + "'");
        }
        return finish();
    }

private:
    std::string value() {
        if (inline_value_) return *inline_value_;
        if (i_ + 1 >= argc_) throw UsageError(flag_ + " needs a value");
        return argv_[++i_];
    }
    void no_value() const {
        if (inline_value_) throw UsageError(flag_ + " takes no value");
    }

    // --camera and the flags that describe it; false for any other flag.
    bool read_camera_flag() {
        const std::string& arg = flag_;
        if (arg == "--camera") {
            const std::vector<float> v = parse_floats(arg, value(), 6);
            camera_given_ = true;
            std::copy(v.begin(), v.begin() + 3, look_.eye), std::copy(v.begin() + 3, v.end(), look_.target);
            return true;
        }
        if (arg == "--up") {
            const std::vector<float> v = parse_floats(arg, value(), 3);
            std::copy(v.begin(), v.end(), look_.up);
        } else if (arg == "--fov") {
            look_.fov_degrees = parse_floats(arg, value(), 1)[0];
            if (!(look_.fov_degrees >= 1.0f && look_.fov_degrees <= 179.0f))
                throw UsageError("--fov must be between 1 and 179 degrees");
        } else if (arg == "--viewport") {
            const std::string text = value();
            look_.width = int(parse_integer(arg, text.substr(0, text.find(',')), 1, 1 << 16));
            look_.height = int(parse_integer(
                arg, text.find(',') == std::string::npos ? "" : text.substr(text.find(',') + 1), 1, 1 << 16));
        } else if (arg == "--dicing-rate") {
            look_.dicing_rate = parse_floats(arg, value(), 1)[0];
            if (!(look_.dicing_rate > 0.0f)) throw UsageError("--dicing-rate must be > 0");
        } else if (arg == "--dicing-measure") {
            look_.measure = parse_name<DicingMeasure>(arg, value());
        } else if (arg == "--max-rate") {
            look_.max_rate = int(parse_integer(arg, value(), 1, loopsub::kMaxTessellationRate));
        } else {
            return false;
        }
        camera_options_.push_back(arg);  // given without --camera, they would be ignored
        return true;
    }

    // Every other flag; false for none of them.
    bool read_option_flag() {
        const std::string& arg = flag_;
        Options& options = command_.options;
        if (arg == "--help") {
            no_value();
            command_.help = true;
        } else if (arg == "--levels") {
            options.levels = int(parse_integer(arg, value(), 0, loopsub::kMaxLevels));
            levels_given_ = true;
        } else if (arg == "--tessellate") {
            command_.tessellate = int(parse_integer(arg, value(), 1, loopsub::kMaxTessellationRate));
        } else if (arg == "--rules") {
            options.rules = parse_name<Rules>(arg, value());
        } else if (arg == "--crease-threshold") {
            options.crease_threshold = parse_nonnegative_float(arg, value());
        } else if (arg == "--boundary") {
            command_.boundary = parse_name<Boundary>(arg, value());
        } else if (arg == "--limit") {
            no_value();
            options.limit_surface = true;
        } else if (arg == "--uv-interpolation") {
            command_.face_varying = parse_name<FaceVaryingInterpolation>(arg, value());
        } else if (arg == "--crease-method") {
            command_.crease_method = parse_name<CreaseMethod>(arg, value());
        } else if (arg == "--threads") {
            options.threads = int(parse_integer(arg, value(), 1, loopsub::kMaxThreads));
        } else if (arg == "--scalar") {
            no_value();
            options.kernel = Kernel::Scalar;
        } else if (arg == "--memory-limit-mb") {
            options.memory_limit_bytes = std::uint64_t(parse_integer(arg, value(), 1, std::int64_t(1) << 40)) << 20;
        } else if (arg == "--stats") {
            no_value();
            command_.stats = true;
        } else {
            return false;
        }
        return true;
    }

    // What the flags must make together: two files, one way to cut, a camera that sees.
    Command finish() {
        if (command_.help) return command_;
        if (positional_.size() != 2) {
            throw UsageError("expected IN.obj and OUT.obj, got " + std::to_string(positional_.size()) +
                             " file argument(s)");
        }
        if (!camera_given_ && !camera_options_.empty()) throw UsageError(camera_options_.front() + " needs --camera");
        if (int(levels_given_) + int(command_.tessellate > 0) + int(camera_given_) > 1)
            throw UsageError("--levels, --tessellate and --camera exclude each other");
        if (!levels_given_ && command_.tessellate == 0 && !camera_given_)
            throw UsageError("--levels N, --tessellate N or --camera is required");
        if (camera_given_) {
            try {  // the core's check that the flags make a view, here: a wrong command line exits 2 before any reading
                loopsub::look_at_camera(look_.eye, look_.target, look_.up, look_.fov_degrees, float(look_.width),
                                        float(look_.height));
            } catch (const loopsub::InputError&) {
                throw UsageError("--camera: the eye, the target and --up must span a view");
            }
            command_.camera = look_;
        }
        command_.input = positional_[0];
        command_.output = positional_[1];
        return command_;
    }

    const int argc_;
    char** const argv_;
    int i_ = 1;                                // the argument being read
    std::string flag_;                         // its flag, without "=value"
    std::optional<std::string> inline_value_;  // its "=value"
    Command command_;
    std::vector<std::string> positional_;
    bool levels_given_ = false, camera_given_ = false;
    LookAt look_;
    std::vector<std::string> camera_options_;  // the camera's flags given
};

}  // namespace

Command parse_command_line(int argc, char** argv) { return Parser(argc, argv).parse(); }

}  // namespace loopsub::cli
