#include "osd_reference.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyRefiner.h>

#include "support/osd_adapter.h"

namespace loopsub::testing {

namespace {

using namespace OpenSubdiv;

// The interface PrimvarRefiner wants from a primvar: Clear and AddWithWeight. Doubles, so that the reference's
// own rounding is far below the tolerances of the tests.
template <int N>
struct Value {
    double x[N];
    void Clear() {
        for (double& v : x) v = 0;
    }
    void AddWithWeight(const Value& src, double weight) {
        for (int k = 0; k < N; ++k) x[k] += weight * src.x[k];
    }
};
using Point = Value<3>;
using UV = Value<2>;

const char* rule_name(Sdc::Crease::Rule rule) {
    switch (rule) {
        case Sdc::Crease::RULE_SMOOTH: return "smooth";
        case Sdc::Crease::RULE_DART: return "dart";
        case Sdc::Crease::RULE_CREASE: return "crease";
        case Sdc::Crease::RULE_CORNER: return "corner";
        default: return "unknown";
    }
}

}  // namespace

struct OsdReference::Impl {
    std::unique_ptr<Far::TopologyRefiner> refiner;
    int levels = 0;
    std::vector<std::vector<Point>> points;        // per level, OpenSubdiv's order
    std::vector<std::vector<double>> flat;         // the same, 3 doubles per vertex
    std::vector<UV> last_uvs, limit_uvs;           // last level's face-varying values, refined and at the limit
    std::vector<Point> limit, tangent1, tangent2;  // Limit() of the last level
    bool has_uvs = false;
};

OsdReference::OsdReference(const MeshView& mesh, const float* positions, const ReferenceOptions& options,
                           const ReferenceUVs& uvs)
    : impl_(std::make_unique<Impl>()) {
    // The UVs, if any, as the mesh's one face-varying layer (whatever layers the view names).
    impl_->has_uvs = uvs.triangle_uvs != nullptr;
    const FaceVaryingLayer layer{uvs.triangle_uvs, uvs.num_uvs};
    MeshView base = mesh;
    base.face_varying = impl_->has_uvs ? &layer : nullptr;
    base.num_face_varying = impl_->has_uvs ? 1 : 0;
    impl_->refiner =
        osd_topology_refiner(base, sdc_options(options.boundary, options.crease_method, options.face_varying));

    Far::TopologyRefiner::UniformOptions uniform(options.levels);
    uniform.fullTopologyInLastLevel = true;  // the last level's faces and edges are compared too
    impl_->refiner->RefineUniform(uniform);
    impl_->levels = options.levels;

    const Far::TopologyRefiner& refiner = *impl_->refiner;
    Far::PrimvarRefinerReal<double> primvar(refiner);
    impl_->points.resize(options.levels + 1);
    impl_->points[0].resize(mesh.num_vertices);
    for (int v = 0; v < mesh.num_vertices; ++v)
        for (int k = 0; k < 3; ++k) impl_->points[0][v].x[k] = positions[3 * v + k];
    std::vector<UV> uv_src, uv_dst;
    if (impl_->has_uvs) {
        uv_src.resize(uvs.num_uvs);
        for (int i = 0; i < uvs.num_uvs; ++i)
            for (int k = 0; k < 2; ++k) uv_src[i].x[k] = uvs.uvs[2 * i + k];
    }
    for (int level = 1; level <= options.levels; ++level) {
        impl_->points[level].resize(refiner.GetLevel(level).GetNumVertices());
        const Point* src = impl_->points[level - 1].data();
        Point* dst = impl_->points[level].data();  // PrimvarRefiner takes the destination by reference
        primvar.Interpolate(level, src, dst);
        if (impl_->has_uvs) {
            uv_dst.assign(refiner.GetLevel(level).GetNumFVarValues(0), UV{});
            const UV* uv_in = uv_src.data();
            UV* uv_out = uv_dst.data();
            primvar.InterpolateFaceVarying(level, uv_in, uv_out, 0);
            std::swap(uv_src, uv_dst);
        }
    }
    impl_->last_uvs = std::move(uv_src);
    if (impl_->has_uvs) {
        impl_->limit_uvs.assign(impl_->last_uvs.size(), UV{});
        primvar.LimitFaceVarying(impl_->last_uvs, impl_->limit_uvs, 0);
    }
    const int last_count = refiner.GetLevel(options.levels).GetNumVertices();
    impl_->limit.assign(last_count, Point{});
    impl_->tangent1.assign(last_count, Point{});
    impl_->tangent2.assign(last_count, Point{});
    primvar.Limit(impl_->points[options.levels], impl_->limit, impl_->tangent1, impl_->tangent2);
    impl_->flat.resize(options.levels + 1);
    for (int level = 0; level <= options.levels; ++level) {
        for (const Point& p : impl_->points[level]) impl_->flat[level].insert(impl_->flat[level].end(), p.x, p.x + 3);
    }
}

OsdReference::~OsdReference() = default;

int OsdReference::levels() const { return impl_->levels; }
int OsdReference::num_vertices(int level) const { return impl_->refiner->GetLevel(level).GetNumVertices(); }
int OsdReference::num_edges(int level) const { return impl_->refiner->GetLevel(level).GetNumEdges(); }
int OsdReference::num_faces(int level) const { return impl_->refiner->GetLevel(level).GetNumFaces(); }
const std::vector<double>& OsdReference::osd_positions(int level) const { return impl_->flat.at(level); }

MappedReference OsdReference::map(const Plan& plan) const {
    MappedReference out;
    const Far::TopologyRefiner& refiner = *impl_->refiner;
    const int levels = std::min(plan.levels(), impl_->levels);
    auto fail = [&](const std::string& why) {
        out.errors.push_back(why);
        return out;
    };

    const int n0 = refiner.GetLevel(0).GetNumVertices();
    if (plan.level_num_vertices(0) != n0)
        return fail("level 0: plan has " + std::to_string(plan.level_num_vertices(0)) + " vertices, OpenSubdiv " +
                    std::to_string(n0));
    out.our_to_osd.resize(levels + 1);
    out.our_to_osd[0].resize(n0);
    for (int v = 0; v < n0; ++v) out.our_to_osd[0][v] = v;

    for (int level = 0; level < levels; ++level) {
        const Far::TopologyLevel& osd = refiner.GetLevel(level);
        const std::vector<std::int32_t>& parent_map = out.our_to_osd[level];
        const int nv = plan.level_num_vertices(level);
        const std::vector<std::int32_t>& edges = plan.level_edges(level);
        const int ne = int(edges.size() / 2);
        const std::string where = "level " + std::to_string(level) + ": ";
        if (ne != osd.GetNumEdges())
            return fail(where + "plan has " + std::to_string(ne) + " edges, OpenSubdiv " +
                        std::to_string(osd.GetNumEdges()));
        if (plan.level_num_vertices(level + 1) != nv + ne)
            return fail(where + "level_num_vertices(" + std::to_string(level + 1) +
                        ") = " + std::to_string(plan.level_num_vertices(level + 1)) +
                        ", expected vertices + edges = " + std::to_string(nv + ne));
        std::vector<std::int32_t>& child_map = out.our_to_osd[level + 1];
        child_map.resize(std::size_t(nv) + ne);
        for (int v = 0; v < nv; ++v) child_map[v] = osd.GetVertexChildVertex(parent_map[v]);
        for (int k = 0; k < ne; ++k) {
            const int a = edges[2 * k], b = edges[2 * k + 1];
            if (a < 0 || a >= nv || b < 0 || b >= nv)
                return fail(where + "edge " + std::to_string(k) + " has an end out of range");
            const Far::Index e = osd.FindEdge(parent_map[a], parent_map[b]);
            if (e == Far::INDEX_INVALID)
                return fail(where + "plan edge " + std::to_string(k) + " (" + std::to_string(a) + ", " +
                            std::to_string(b) + ") is not an edge of OpenSubdiv's mesh");
            child_map[nv + k] = osd.GetEdgeChildVertex(e);
        }
        // A bijection onto OpenSubdiv's child vertices, or the plan named an edge twice.
        std::vector<char> hit(refiner.GetLevel(level + 1).GetNumVertices(), 0);
        for (std::int32_t osd_vertex : child_map) {
            if (osd_vertex < 0 || osd_vertex >= int(hit.size()) || hit[osd_vertex])
                return fail(where + "the plan's vertices and edges do not map one to one onto OpenSubdiv's children");
            hit[osd_vertex] = 1;
        }
    }

    out.positions.resize(levels + 1);
    for (int level = 0; level <= levels; ++level) {
        const std::vector<std::int32_t>& m = out.our_to_osd[level];
        out.positions[level].resize(3 * m.size());
        for (std::size_t v = 0; v < m.size(); ++v)
            for (int k = 0; k < 3; ++k) out.positions[level][3 * v + k] = impl_->points[level][m[v]].x[k];
    }

    // Faces of the last level in our numbering, their level-0 ancestors and their face-varying values. Only
    // when the plan's last level is the reference's last (full topology is kept there only).
    if (levels != impl_->levels) return out;
    const Far::TopologyLevel& last = refiner.GetLevel(levels);
    std::vector<std::int32_t> osd_to_our(last.GetNumVertices());
    for (std::size_t v = 0; v < out.our_to_osd[levels].size(); ++v) osd_to_our[out.our_to_osd[levels][v]] = int(v);
    const int nf = last.GetNumFaces();
    out.triangles.resize(3 * std::size_t(nf));
    out.ancestors.resize(nf);
    if (impl_->has_uvs) out.face_uvs.resize(6 * std::size_t(nf)), out.face_uvs_limit.resize(6 * std::size_t(nf));
    for (int e = 0; e < last.GetNumEdges(); ++e) {
        Far::ConstIndexArray ev = last.GetEdgeVertices(e);
        out.edge_tags.push_back({osd_to_our[ev[0]], osd_to_our[ev[1]], last.GetEdgeSharpness(e),
                                 last.IsEdgeBoundary(e) || last.IsEdgeNonManifold(e)});
    }
    out.vertex_tags.resize(out.our_to_osd[levels].size());
    for (std::size_t v = 0; v < out.vertex_tags.size(); ++v) {
        const Far::Index ov = out.our_to_osd[levels][v];
        out.vertex_tags[v] = {last.GetVertexSharpness(ov), last.IsVertexBoundary(ov) || last.IsVertexNonManifold(ov)};
    }
    const std::size_t count = out.our_to_osd[levels].size();
    out.limit_positions.resize(3 * count);
    out.limit_normals.resize(3 * count);
    out.limit_smooth.resize(count);
    for (std::size_t v = 0; v < count; ++v) {
        const Far::Index ov = out.our_to_osd[levels][v];
        const double* a = impl_->tangent1[ov].x;
        const double* b = impl_->tangent2[ov].x;
        const double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) {
            out.limit_positions[3 * v + k] = impl_->limit[ov].x[k];
            out.limit_normals[3 * v + k] = length > 0.0 ? n[k] / length : 0.0;
        }
        const Sdc::Crease::Rule rule = last.GetVertexRule(ov);
        out.limit_smooth[v] = rule == Sdc::Crease::RULE_SMOOTH || rule == Sdc::Crease::RULE_DART;
    }
    // Holes are refined but are no part of the surface: they are left out, as the plan leaves them out.
    int kept = 0;
    for (int g = 0; g < nf; ++g) {
        if (last.IsFaceHole(g)) continue;
        const int f = kept++;
        Far::ConstIndexArray fv = last.GetFaceVertices(g);
        if (fv.size() != 3) return fail("OpenSubdiv produced a face with " + std::to_string(fv.size()) + " sides");
        for (int k = 0; k < 3; ++k) out.triangles[3 * f + k] = osd_to_our[fv[k]];
        int ancestor = g;
        for (int level = levels; level > 0; --level) ancestor = refiner.GetLevel(level).GetFaceParentFace(ancestor);
        out.ancestors[f] = ancestor;
        if (impl_->has_uvs) {
            Far::ConstIndexArray values = last.GetFaceFVarValues(g, 0);
            for (int k = 0; k < 3; ++k)
                for (int c = 0; c < 2; ++c) {
                    out.face_uvs[6 * f + 2 * k + c] = impl_->last_uvs[values[k]].x[c];
                    out.face_uvs_limit[6 * f + 2 * k + c] = impl_->limit_uvs[values[k]].x[c];
                }
        }
    }
    out.triangles.resize(3 * std::size_t(kept));
    out.ancestors.resize(kept);
    if (impl_->has_uvs) out.face_uvs.resize(6 * std::size_t(kept)), out.face_uvs_limit.resize(6 * std::size_t(kept));
    return out;
}

OsdReference::DescendantLimits OsdReference::descendant_limits(const MappedReference& mapped, int level) const {
    const Far::TopologyRefiner& refiner = *impl_->refiner;
    DescendantLimits out;
    const std::vector<std::int32_t>& ours = mapped.our_to_osd.at(level);
    const Far::TopologyLevel& last = refiner.GetLevel(impl_->levels);
    for (std::int32_t v : ours) {
        for (int l = level; l < impl_->levels; ++l) v = refiner.GetLevel(l).GetVertexChildVertex(v);
        const double* a = impl_->tangent1[v].x;
        const double* b = impl_->tangent2[v].x;
        const double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) {
            out.positions.push_back(impl_->limit[v].x[k]);
            out.normals.push_back(length > 0.0 ? n[k] / length : 0.0);
        }
        const Sdc::Crease::Rule rule = last.GetVertexRule(v);
        out.smooth.push_back(rule == Sdc::Crease::RULE_SMOOTH || rule == Sdc::Crease::RULE_DART);
    }
    return out;
}

std::string OsdReference::describe_origin(const Plan& plan, const MappedReference& mapped, int level, int v) const {
    std::ostringstream s;
    if (level <= 0) {
        s << "input vertex " << v;
        return s.str();
    }
    const Far::TopologyLevel& osd = impl_->refiner->GetLevel(level - 1);
    const std::vector<std::int32_t>& parent_map = mapped.our_to_osd[level - 1];
    auto vertex_tags = [&](int our) {
        std::ostringstream t;
        const Far::Index pv = parent_map[our];
        Far::ConstIndexArray edges = osd.GetVertexEdges(pv);
        t << "vertex " << our << " [OSD rule " << rule_name(osd.GetVertexRule(pv)) << ", valence " << edges.size()
          << ", faces " << osd.GetVertexFaces(pv).size() << (osd.IsVertexBoundary(pv) ? ", boundary" : "")
          << (osd.IsVertexNonManifold(pv) ? ", non-manifold" : "") << ", sharpness " << osd.GetVertexSharpness(pv);
        int sharp_edges = 0;
        for (int k = 0; k < edges.size(); ++k) sharp_edges += osd.GetEdgeSharpness(edges[k]) > 0;
        t << ", sharp edges " << sharp_edges << "]";
        return t.str();
    };
    const int nv = plan.level_num_vertices(level - 1);
    s << "level-" << level << " vertex " << v << " is the ";
    if (v < nv) {
        s << "vertex point of level-" << (level - 1) << " " << vertex_tags(v);
    } else {
        const std::vector<std::int32_t>& edges = plan.level_edges(level - 1);
        const int k = v - nv, a = edges[2 * k], b = edges[2 * k + 1];
        const Far::Index e = osd.FindEdge(parent_map[a], parent_map[b]);
        s << "edge point of level-" << (level - 1) << " edge " << a << "-" << b << " [OSD sharpness "
          << osd.GetEdgeSharpness(e) << ", faces " << osd.GetEdgeFaces(e).size()
          << (osd.IsEdgeBoundary(e) ? ", boundary" : "") << (osd.IsEdgeNonManifold(e) ? ", non-manifold" : "")
          << "], ends " << vertex_tags(a) << " and " << vertex_tags(b);
    }
    return s.str();
}

std::array<std::int32_t, 3> canonical_triangle(std::int32_t a, std::int32_t b, std::int32_t c) {
    const std::int32_t t[3] = {a, b, c};
    const int r = canonical_rotation(a, b, c);
    return {t[r], t[(r + 1) % 3], t[(r + 2) % 3]};
}

int canonical_rotation(std::int32_t a, std::int32_t b, std::int32_t c) {
    if (a <= b && a <= c) return 0;
    if (b <= c) return 1;
    return 2;
}

std::string compare_positions(const OsdReference& reference, const Plan& plan, const MappedReference& mapped, int level,
                              const std::vector<float>& ours, double tolerance) {
    const std::vector<double>& expected = mapped.positions.at(level);
    std::ostringstream s;
    if (ours.size() != expected.size()) {
        s << "vertex count differs at level " << level << ": ours " << ours.size() / 3 << ", OpenSubdiv "
          << expected.size() / 3;
        return s.str();
    }
    std::vector<std::pair<double, int>> bad;  // (distance, vertex)
    for (std::size_t v = 0; 3 * v < ours.size(); ++v) {
        double d2 = 0;
        for (int k = 0; k < 3; ++k)
            d2 += (ours[3 * v + k] - expected[3 * v + k]) * (ours[3 * v + k] - expected[3 * v + k]);
        const double d = std::sqrt(d2);
        if (!(d <= tolerance)) bad.emplace_back(std::isnan(d) ? INFINITY : d, int(v));
    }
    if (bad.empty()) return "";
    std::sort(bad.begin(), bad.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    s << bad.size() << " of " << ours.size() / 3 << " vertices differ from OpenSubdiv by more than " << tolerance
      << " at level " << level << "; the worst:\n";
    s.precision(9);
    for (std::size_t i = 0; i < std::min<std::size_t>(bad.size(), 5); ++i) {
        const int v = bad[i].second;
        s << "  vertex " << v << ": expected (" << expected[3 * v] << ", " << expected[3 * v + 1] << ", "
          << expected[3 * v + 2] << ") got (" << ours[3 * v] << ", " << ours[3 * v + 1] << ", " << ours[3 * v + 2]
          << "), distance " << bad[i].first << "\n    " << reference.describe_origin(plan, mapped, level, v) << "\n";
    }
    return s.str();
}

std::string compare_triangles(const Plan& plan, const MappedReference& mapped) {
    std::ostringstream s;
    const int n = plan.num_output_triangles();
    if (std::size_t(n) * 3 != mapped.triangles.size()) {
        s << "face count differs: ours " << n << ", OpenSubdiv " << mapped.triangles.size() / 3;
        return s.str();
    }
    // OpenSubdiv's faces by their oriented vertex triple -> level-0 ancestor (a multimap: input meshes may repeat
    // a triangle).
    std::multimap<std::array<std::int32_t, 3>, std::int32_t> theirs;
    for (int f = 0; f < n; ++f) {
        const std::int32_t* t = &mapped.triangles[3 * f];
        theirs.emplace(canonical_triangle(t[0], t[1], t[2]), mapped.ancestors[f]);
    }
    const std::int32_t* tris = plan.output_triangles();
    const std::int32_t* parents = plan.output_parent_triangles();
    int missing = 0, wrong_parent = 0;
    for (int f = 0; f < n; ++f) {
        auto key = canonical_triangle(tris[3 * f], tris[3 * f + 1], tris[3 * f + 2]);
        auto range = theirs.equal_range(key);
        auto it = range.first;
        while (it != range.second && it->second != parents[f]) ++it;
        if (it != range.second) {
            theirs.erase(it);
            continue;
        }
        if (range.first == range.second) {
            if (missing++ < 5)
                s << "  our triangle " << f << " (" << key[0] << ", " << key[1] << ", " << key[2]
                  << ") is not an OpenSubdiv face with that winding\n";
        } else {
            if (wrong_parent++ < 5)
                s << "  our triangle " << f << " has parent " << parents[f] << ", OpenSubdiv's " << range.first->second
                  << "\n";
            theirs.erase(range.first);
        }
    }
    if (missing == 0 && wrong_parent == 0) return "";
    std::ostringstream head;
    head << missing << " triangles not in OpenSubdiv's output, " << wrong_parent << " with a wrong parent:\n";
    return head.str() + s.str();
}

std::string compare_crease_tags(const Plan& plan, const MappedReference& mapped) {
    std::ostringstream s;
    int bad = 0;
    auto report = [&](const std::string& line) {
        if (bad++ < 8) s << "  " << line << "\n";
    };
    std::map<std::pair<std::int32_t, std::int32_t>, float> ours;
    const std::vector<std::int32_t>& edges = plan.output_crease_edges();
    const std::vector<float>& sharpness = plan.output_crease_sharpness();
    if (edges.size() != 2 * sharpness.size()) return "output_crease_edges and output_crease_sharpness sizes differ";
    for (std::size_t k = 0; k < sharpness.size(); ++k) {
        auto key = std::minmax(edges[2 * k], edges[2 * k + 1]);
        if (!ours.emplace(key, sharpness[k]).second)
            report("edge " + std::to_string(key.first) + "-" + std::to_string(key.second) + " tagged twice");
    }
    for (const MappedReference::EdgeTag& tag : mapped.edge_tags) {
        auto key = std::minmax(tag.a, tag.b);
        auto it = ours.find(key);
        const float got = it == ours.end() ? 0.0f : it->second;
        if (it != ours.end()) ours.erase(it);
        if (tag.implicit) continue;
        if (!(std::abs(got - tag.sharpness) <= 1e-5f)) {
            std::ostringstream line;
            line << "edge " << key.first << "-" << key.second << ": OpenSubdiv sharpness " << tag.sharpness << ", ours "
                 << got;
            report(line.str());
        }
    }
    for (const auto& left : ours)
        report("tagged edge " + std::to_string(left.first.first) + "-" + std::to_string(left.first.second) +
               " is not an edge of the output");

    std::map<std::int32_t, float> corners;
    const std::vector<std::int32_t>& corner_vertices = plan.output_corner_vertices();
    const std::vector<float>& corner_sharpness = plan.output_corner_sharpness();
    if (corner_vertices.size() != corner_sharpness.size()) return "output corner vertex and sharpness sizes differ";
    for (std::size_t k = 0; k < corner_vertices.size(); ++k)
        if (!corners.emplace(corner_vertices[k], corner_sharpness[k]).second)
            report("vertex " + std::to_string(corner_vertices[k]) + " tagged twice");
    for (std::size_t v = 0; v < mapped.vertex_tags.size(); ++v) {
        auto it = corners.find(std::int32_t(v));
        const float got = it == corners.end() ? 0.0f : it->second;
        const MappedReference::VertexTag& tag = mapped.vertex_tags[v];
        if (tag.implicit && tag.sharpness >= 10.0f) continue;  // OpenSubdiv's own boundary corner
        if (!(std::abs(got - tag.sharpness) <= 1e-5f)) {
            std::ostringstream line;
            line << "vertex " << v << ": OpenSubdiv sharpness " << tag.sharpness << ", ours " << got;
            report(line.str());
        }
    }
    if (bad == 0) return "";
    return std::to_string(bad) + " crease / corner tags differ from OpenSubdiv's last level:\n" + s.str();
}

}  // namespace loopsub::testing
