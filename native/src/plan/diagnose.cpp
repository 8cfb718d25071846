// diagnose(): the checks a Plan makes (plan/validation.h, base/input_checks.h), every problem listed rather than the
// first thrown, and the notes a Plan has no use for.
#include <vector>

#include "plan/validation.h"
#include "topology/topology.h"

namespace loopsub {

std::vector<InputProblem> diagnose(const MeshView& mesh, ChannelsView<const float> vertex_values) {
    detail::validate_view(mesh);
    std::vector<InputProblem> problems;
    auto collect = [&problems](const InputProblem& problem) {
        problems.push_back(problem);
        return true;
    };
    detail::check_mesh(mesh, collect);
    if (vertex_values.num_channels > 0 && vertex_values.data != nullptr)
        detail::check_values(vertex_values, mesh.num_vertices, InputProblem::Element::Vertex, -1, 0.0f, 0, collect);
    // The edges are built from the triangles (and their edges), and a crease is looked up from its ends: only where
    // they are sound.
    auto any = [&problems](InputProblem::Element element) {
        using Kind = InputProblem::Kind;
        for (const InputProblem& p : problems)
            if (p.element == element && (p.kind == Kind::VertexOutOfRange || p.kind == Kind::DegenerateTriangle ||
                                         p.kind == Kind::EdgeOutOfRange || p.kind == Kind::EdgeEndsDiffer))
                return true;
        return false;
    };
    if (any(InputProblem::Element::Triangle)) return problems;
    const detail::Topology base =
        detail::build_base_topology(mesh.triangles, mesh.num_triangles, mesh.num_vertices, 1, mesh.triangle_edges);
    const bool tags_readable = !any(InputProblem::Element::CreaseEdge);
    if (tags_readable) detail::check_crease_edges(base, mesh, collect, [](int, detail::Index) {});
    detail::check_windings(base, collect);
    return problems;
}

std::vector<InputProblem> diagnose_corner_values(const float* values, int num_triangles, int num_channels, int layer) {
    std::vector<InputProblem> problems;
    if (num_triangles <= 0 || num_channels <= 0) return problems;
    if (values == nullptr) throw InputError("diagnose_corner_values: missing (null) values");
    detail::check_corner_values(values, std::size_t(num_triangles), num_channels, layer,
                                [&problems](const InputProblem& p) {
                                    problems.push_back(p);
                                    return true;
                                });
    return problems;
}

}  // namespace loopsub
