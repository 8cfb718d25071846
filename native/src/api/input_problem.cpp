// What an InputProblem is called and says: the one place its words are chosen (the checks that find problems are in
// base/input_checks.h).
#include <iterator>
#include <string>

#include "base/common.h"
#include "loopsub/loopsub.h"

namespace loopsub {

namespace {

using Kind = InputProblem::Kind;
using Element = InputProblem::Element;

// Each list in its enum's order.
constexpr const char* kKindNames[] = {"vertex_out_of_range", "triangle_out_of_range", "value_out_of_range",
                                      "degenerate_triangle", "not_an_edge",           "bad_sharpness",
                                      "non_finite_value",    "value_too_large",       "runs_the_same_way",
                                      "rate_out_of_range",   "edge_out_of_range",     "edge_ends_differ"};
constexpr const char* kElementNames[] = {"vertex", "triangle",           "crease_edge", "corner_vertex", "cone",
                                         "hole",   "face_varying_value", "rated_edge",  "camera"};
static_assert(std::size(kKindNames) == std::size_t(Kind::EdgeEndsDiffer) + 1 &&
                  std::size(kElementNames) == std::size_t(Element::Camera) + 1,
              "a name for every kind and element");

// An element in a message: "crease edge 3", "face-varying value 7 of layer 1", "the camera's world_to_clip entry 7
// (row 1, column 3)".
std::string element_words(const InputProblem& p) {
    static constexpr const char* kWords[] = {"vertex",
                                             "triangle",
                                             "crease edge",
                                             "corner",
                                             "cone",
                                             "hole",
                                             "face-varying value",
                                             "rated edge",
                                             "the camera's world_to_clip entry"};
    std::string text = kWords[int(p.element)] + (" " + std::to_string(p.index));
    if (p.element == Element::FaceVaryingValue && p.layer >= 0) text += " of layer " + std::to_string(p.layer);
    if (p.element == Element::Camera)
        text += " (row " + std::to_string(p.index / 4) + ", column " + std::to_string(p.index % 4) + ")";
    return text;
}

// "in channel 2", where the element has channels (a camera's matrix entry has none).
std::string channel_words(const InputProblem& p) {
    return p.element == Element::Camera ? std::string() : " in channel " + std::to_string(p.channel);
}

std::string range(int count) { return "0.." + std::to_string(count - 1); }

std::string value_place(const InputProblem& p) {
    if (p.element != Element::Triangle) return element_words(p);
    return "triangle " + std::to_string(p.index) + ", corner " + std::to_string(p.corner) +
           (p.layer >= 0 ? " (face-varying layer " + std::to_string(p.layer) + ")" : std::string());
}

}  // namespace

const char* problem_name(InputProblem::Kind kind) { return kKindNames[int(kind)]; }
const char* problem_name(InputProblem::Element element) { return kElementNames[int(element)]; }

std::string InputProblem::message() const {
    using detail::shortest;
    const std::string at = element_words(*this);
    switch (kind) {
        case Kind::VertexOutOfRange:
            return at + " refers to vertex " + std::to_string(refers_to) + ", outside " + range(other) +
                   " (the mesh has " + std::to_string(other) + " vertices)";
        case Kind::TriangleOutOfRange:
            return at + " refers to triangle " + std::to_string(refers_to) + ", outside " + range(other);
        case Kind::ValueOutOfRange:
            return "face-varying layer " + std::to_string(layer) + ": corner " + std::to_string(corner) +
                   " of triangle " + std::to_string(index) + " refers to value " + std::to_string(refers_to) +
                   ", outside " + range(other);
        case Kind::DegenerateTriangle:
            return at + " is degenerate: it repeats vertex " + std::to_string(refers_to) +
                   " (every corner must be a different vertex)";
        case Kind::NotAnEdge:
            return at + " (" + std::to_string(refers_to) + ", " + std::to_string(other) +
                   ") is not an edge of the mesh";
        case Kind::BadSharpness:
            return at + " has sharpness " + std::to_string(value) + "; it must be a finite number >= 0";
        case Kind::NonFiniteValue:
            return value_place(*this) + " has a non-finite value (" + shortest(value) + ")" + channel_words(*this);
        case Kind::ValueTooLarge:
            return value_place(*this) + " has a value too large to refine (" + shortest(value) + ") in channel " +
                   std::to_string(channel) + ": sums of up to " + std::to_string(other) +
                   " values must stay finite, so values are limited to +-" + shortest(limit);
        case Kind::RunsTheSameWay:
            return "triangles " + std::to_string(other) + " and " + std::to_string(index) +
                   " run along an edge the same way (edge " + std::to_string(corner) + " of triangle " +
                   std::to_string(index) + "), as a face wound against its neighbours does: it is infinitely sharp";
        case Kind::RateOutOfRange:
            return at + " (" + std::to_string(refers_to) + ", " + std::to_string(other) + ") has rate " +
                   shortest(value) + "; a rate must be between 1 and " + shortest(limit);
        case Kind::EdgeOutOfRange:
            return value_place(*this) + " numbers its edge " + std::to_string(refers_to) + ", outside " + range(other) +
                   " (triangle_edges)";
        case Kind::EdgeEndsDiffer:
            return value_place(*this) + " numbers its edge " + std::to_string(refers_to) +
                   ", which joins other vertices in triangle " + std::to_string(other) +
                   " (triangle_edges: one number, one pair of vertices)";
    }
    return at;
}

InputError::InputError(const InputProblem& problem, const std::string& context)
    : std::invalid_argument(context + problem.message()), problem_(problem), has_problem_(true) {}

}  // namespace loopsub
