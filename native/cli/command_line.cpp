#include "command_line.h"

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
    "\n"
    "Subdivides the triangle mesh IN.obj N times by Loop's scheme and writes OUT.obj with the child crease,\n"
    "corner and cone tags. Polygons with more than 3 corners are triangulated by ear clipping (with a notice).\n"
    "With --tessellate, cuts each triangle into N segments per edge instead, every point on the limit surface,\n"
    "with its normals (vn); UVs go linearly within each triangle; no tags are written.\n"
    "\n"
    "options:\n"
    "  --levels N                    subdivision levels, N >= 0 (this or --tessellate is required)\n"
    "  --tessellate N                segments per edge, 1 to 4096: the limit surface at that rate (N = 2^L:\n"
    "                                the vertices of --levels L --limit)\n"
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
    bool levels_given = false;
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
    if (levels_given && command.tessellate > 0) throw UsageError("--levels and --tessellate exclude each other");
    if (!levels_given && command.tessellate == 0) throw UsageError("--levels N or --tessellate N is required");
    command.input = positional[0];
    command.output = positional[1];
    return command;
}

}  // namespace loopsub::cli
