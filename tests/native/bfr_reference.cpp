#include "bfr_reference.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyRefiner.h>

#include "mesh_gen.h"
#include "support/osd_adapter.h"

namespace loopsub::testing {

using namespace OpenSubdiv;

namespace {

// holes: whether the mesh may have hole tags (where only the faces with a surface are asked for).
std::unique_ptr<Far::TopologyRefiner> base_refiner(const TestMesh& mesh, FaceVaryingInterpolation interpolation,
                                                   bool face_varying, bool holes = false) {
    if (!holes && !mesh.hole_triangles.empty()) throw std::runtime_error("bfr: meshes without holes only");
    return osd_topology_refiner(face_varying ? mesh.view_with_uvs() : mesh.view(),
                                sdc_options(mesh.boundary, mesh.crease_method, interpolation));
}

// Exact at the points asked for: they are corners of Bfr's patches once it isolates smooth irregular vertices to the
// plan's last level, and semi-sharp features until their sharpness is spent.
Bfr::SurfaceFactory::Options exact_at(const Plan& plan) {
    Bfr::SurfaceFactory::Options options;
    options.SetApproxLevelSmooth(std::max(plan.levels(), 2)).SetApproxLevelSharp(10);
    return options;
}

// The (u, v) of the corners of output triangle `child` of a base face (its index among the face's descendants), from
// the base face down: corner child k is (v_k, m_k, m_{k-1}), the middle child (m_0, m_1, m_2).
void corner_parameters(std::size_t child, int levels, double uv[3][2]) {
    const double base[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    std::copy(&base[0][0], &base[0][0] + 6, &uv[0][0]);
    for (int l = levels - 1; l >= 0; --l) {
        const int k = int(child >> 2 * l & 3);
        double m[3][2], next[3][2];
        for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 2; ++c) m[i][c] = 0.5 * (uv[i][c] + uv[(i + 1) % 3][c]);
        for (int c = 0; c < 2; ++c) {
            if (k == 3) {
                next[0][c] = m[0][c], next[1][c] = m[1][c], next[2][c] = m[2][c];
            } else {
                next[0][c] = uv[k][c], next[1][c] = m[k][c], next[2][c] = m[(k + 2) % 3][c];
            }
        }
        std::copy(&next[0][0], &next[0][0] + 6, &uv[0][0]);
    }
}

void require_split(const TestMesh& mesh, const Plan& plan) {
    if (std::int64_t(plan.num_output_triangles()) != (std::int64_t(mesh.num_triangles()) << 2 * plan.levels()))
        throw std::runtime_error("bfr_limit: output triangles must be the split's, without holes");
}

void unit_normal(const double du[3], const double dv[3], double* out) {
    const double n[3] = {du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2], du[0] * dv[1] - du[1] * dv[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int c = 0; c < 3; ++c) out[c] = length > 0.0 ? n[c] / length : 0.0;
}

}  // namespace

BfrLimit bfr_limit(const TestMesh& mesh, const Plan& plan) {
    require_split(mesh, plan);
    const int levels = plan.levels();
    const std::unique_ptr<Far::TopologyRefiner> refiner = base_refiner(mesh, plan.options().face_varying, false);
    const Bfr::RefinerSurfaceFactory<> factory(*refiner, exact_at(plan));

    BfrLimit out;
    out.positions.assign(3 * std::size_t(plan.num_output_vertices()), 0.0);
    out.normals.assign(9 * std::size_t(plan.num_output_triangles()), 0.0);
    std::vector<double> control(mesh.positions.begin(), mesh.positions.end()), patch_points;
    const Bfr::Surface<double>::PointDescriptor point(3);
    Bfr::Surface<double> surface;
    const std::int32_t* triangles = plan.output_triangles();
    const std::size_t per_face = std::size_t(1) << 2 * levels;
    for (int f = 0; f < mesh.num_triangles(); ++f) {
        if (!factory.InitVertexSurface(f, &surface) || !surface.IsValid())
            throw std::runtime_error("Bfr: no surface for a face");
        patch_points.resize(3 * std::size_t(surface.GetNumPatchPoints()));
        surface.PreparePatchPoints(control.data(), point, patch_points.data(), point);
        for (std::size_t child = 0; child < per_face; ++child) {
            const std::size_t t = std::size_t(f) * per_face + child;
            double uv[3][2];
            corner_parameters(child, levels, uv);
            for (int corner = 0; corner < 3; ++corner) {
                double p[3], du[3], dv[3];
                surface.Evaluate(uv[corner], patch_points.data(), point, p, du, dv);
                const std::size_t v = std::size_t(triangles[3 * t + corner]);
                for (int c = 0; c < 3; ++c) out.positions[3 * v + c] = p[c];
                unit_normal(du, dv, &out.normals[9 * t + 3 * std::size_t(corner)]);
            }
        }
    }
    return out;
}

}  // namespace loopsub::testing

namespace loopsub::testing {

std::vector<double> bfr_face_varying_limit(const TestMesh& mesh, const Plan& plan) {
    require_split(mesh, plan);
    const int levels = plan.levels();
    const std::unique_ptr<Far::TopologyRefiner> refiner = base_refiner(mesh, plan.options().face_varying, true);
    Bfr::SurfaceFactory::Options options = exact_at(plan);
    options.SetDefaultFVarID(0);
    const Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
    std::vector<double> out(6 * std::size_t(plan.num_output_triangles()), 0.0);
    std::vector<double> control(mesh.uvs.begin(), mesh.uvs.end()), patch_points;
    const Bfr::Surface<double>::PointDescriptor point(2);
    Bfr::Surface<double> surface;
    const std::size_t per_face = std::size_t(1) << 2 * levels;
    for (int f = 0; f < mesh.num_triangles(); ++f) {
        if (!factory.InitFaceVaryingSurface(f, &surface) || !surface.IsValid())
            throw std::runtime_error("Bfr: no face-varying surface for a face");
        patch_points.resize(2 * std::size_t(surface.GetNumPatchPoints()));
        surface.PreparePatchPoints(control.data(), point, patch_points.data(), point);
        for (std::size_t child = 0; child < per_face; ++child) {
            const std::size_t t = std::size_t(f) * per_face + child;
            double uv[3][2];
            corner_parameters(child, levels, uv);
            for (int corner = 0; corner < 3; ++corner)
                surface.Evaluate(uv[corner], patch_points.data(), point, &out[6 * t + 2 * std::size_t(corner)]);
        }
    }
    return out;
}

}  // namespace loopsub::testing

namespace loopsub::testing {

namespace {

// Walks `points` (grouped by face) over the surfaces a factory isolated as deep as Bfr goes (its approximation near
// irregular vertices shrinks to 2^-10 of a face): init(factory, face, surface) makes a face's surface, whose patch
// points are prepared from `control` (`width` doubles a control point), and evaluate(i, surface, patch_points,
// descriptor) reads point i.
template <typename Init, typename Evaluate>
void over_points(const Far::TopologyRefiner& refiner, bool face_varying, const std::vector<BfrPoint>& points,
                 const std::vector<double>& control, int width, Init init, Evaluate evaluate) {
    Bfr::SurfaceFactory::Options options;
    options.SetApproxLevelSmooth(10).SetApproxLevelSharp(10);
    if (face_varying) options.SetDefaultFVarID(0);
    const Bfr::RefinerSurfaceFactory<> factory(refiner, options);
    const Bfr::Surface<double>::PointDescriptor descriptor(width);
    Bfr::Surface<double> surface;
    std::vector<double> patch_points;
    int face = -1;
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (points[i].face != face) {
            face = points[i].face;
            if (!init(factory, face, surface) || !surface.IsValid())
                throw std::runtime_error("Bfr: no surface for a face");
            patch_points.resize(std::size_t(width) * std::size_t(surface.GetNumPatchPoints()));
            surface.PreparePatchPoints(control.data(), descriptor, patch_points.data(), descriptor);
        }
        evaluate(i, surface, patch_points, descriptor);
    }
}

}  // namespace

std::vector<bool> bfr_faces_with_surface(const TestMesh& mesh) {
    const std::unique_ptr<Far::TopologyRefiner> refiner =
        base_refiner(mesh, FaceVaryingInterpolation::CornersOnly, false, true);
    const Bfr::RefinerSurfaceFactory<> factory(*refiner);
    std::vector<bool> out(std::size_t(mesh.num_triangles()));
    for (int f = 0; f < mesh.num_triangles(); ++f) out[std::size_t(f)] = factory.FaceHasLimitSurface(f);
    return out;
}

BfrLimit bfr_evaluate(const TestMesh& mesh, const std::vector<BfrPoint>& points) {
    const std::unique_ptr<Far::TopologyRefiner> refiner =
        base_refiner(mesh, FaceVaryingInterpolation::CornersOnly, false, true);
    BfrLimit out;
    out.positions.assign(3 * points.size(), 0.0);
    out.normals.assign(3 * points.size(), 0.0);
    over_points(
        *refiner, false, points, std::vector<double>(mesh.positions.begin(), mesh.positions.end()), 3,
        [](const Bfr::RefinerSurfaceFactory<>& factory, int face, Bfr::Surface<double>& surface) {
            return factory.InitVertexSurface(face, &surface);
        },
        [&](std::size_t i, const Bfr::Surface<double>& surface, const std::vector<double>& patch_points,
            const Bfr::Surface<double>::PointDescriptor& descriptor) {
            const double uv[2] = {points[i].u, points[i].v};
            double du[3], dv[3];
            surface.Evaluate(uv, patch_points.data(), descriptor, &out.positions[3 * i], du, dv);
            unit_normal(du, dv, &out.normals[3 * i]);
        });
    return out;
}

std::vector<double> bfr_evaluate_face_varying(const TestMesh& mesh, const std::vector<BfrPoint>& points,
                                              FaceVaryingInterpolation mode) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = base_refiner(mesh, mode, true, true);
    std::vector<double> out(2 * points.size(), 0.0);
    over_points(
        *refiner, true, points, std::vector<double>(mesh.uvs.begin(), mesh.uvs.end()), 2,
        [](const Bfr::RefinerSurfaceFactory<>& factory, int face, Bfr::Surface<double>& surface) {
            return factory.InitFaceVaryingSurface(face, &surface);
        },
        [&](std::size_t i, const Bfr::Surface<double>& surface, const std::vector<double>& patch_points,
            const Bfr::Surface<double>::PointDescriptor& descriptor) {
            const double uv[2] = {points[i].u, points[i].v};
            surface.Evaluate(uv, patch_points.data(), descriptor, &out[2 * i]);
        });
    return out;
}

}  // namespace loopsub::testing

namespace loopsub::testing {

namespace {

template <int N>
struct Values {
    double x[N];
    void Clear() { std::fill(x, x + N, 0.0); }
    void AddWithWeight(const Values& src, double weight) {
        for (int k = 0; k < N; ++k) x[k] += weight * src.x[k];
    }
};

}  // namespace

std::vector<double> far_refined_limit(const TestMesh& mesh, const std::vector<BfrPoint>& points, int levels) {
    using Point = Values<3>;
    std::vector<std::int32_t> corner_values(mesh.triangles.size());
    for (std::size_t c = 0; c < corner_values.size(); ++c) corner_values[c] = std::int32_t(c);
    const FaceVaryingLayer layer{corner_values.data(), int(corner_values.size())};
    MeshView view = mesh.view();
    view.face_varying = &layer, view.num_face_varying = 1;
    const std::unique_ptr<Far::TopologyRefiner> refiner =
        osd_topology_refiner(view, sdc_options(mesh.boundary, mesh.crease_method, FaceVaryingInterpolation::All));
    Far::TopologyRefiner::UniformOptions uniform(levels);
    uniform.fullTopologyInLastLevel = true;
    refiner->RefineUniform(uniform);
    const Far::PrimvarRefinerReal<double> primvar(*refiner);
    std::vector<Point> vertices(std::size_t(mesh.num_vertices())), places(corner_values.size()), next;
    for (std::size_t v = 0; v < vertices.size(); ++v)
        for (std::size_t k = 0; k < 3; ++k) vertices[v].x[k] = mesh.positions[3 * v + k];
    const double corner_uv[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    for (std::size_t c = 0; c < places.size(); ++c)
        places[c] = Point{{double(c / 3), corner_uv[c % 3][0], corner_uv[c % 3][1]}};
    for (int level = 1; level <= levels; ++level) {
        next.assign(std::size_t(refiner->GetLevel(level).GetNumVertices()), Point{});
        Point* out = next.data();
        primvar.Interpolate(level, vertices.data(), out);
        std::swap(vertices, next);
        next.assign(std::size_t(refiner->GetLevel(level).GetNumFVarValues(0)), Point{});
        out = next.data();
        primvar.InterpolateFaceVarying(level, places.data(), out, 0);
        std::swap(places, next);
    }
    std::vector<Point> limit(vertices.size());
    primvar.Limit(vertices, limit);
    // The last level's triangles by base face.
    const Far::TopologyLevel& last = refiner->GetLevel(levels);
    std::vector<std::vector<int>> by_face(std::size_t(mesh.num_triangles()));
    for (int t = 0; t < last.GetNumFaces(); ++t)
        by_face[std::size_t(std::lround(places[std::size_t(last.GetFaceFVarValues(t, 0)[0])].x[0]))].push_back(t);
    std::vector<double> out(3 * points.size(), 0.0);
    for (std::size_t i = 0; i < points.size(); ++i) {
        double best = -1e300, weights[3] = {};
        int found = -1;
        for (int t : by_face[std::size_t(points[i].face)]) {
            const auto values = last.GetFaceFVarValues(t, 0);
            const double* a = places[std::size_t(values[0])].x + 1;
            const double* b = places[std::size_t(values[1])].x + 1;
            const double* c = places[std::size_t(values[2])].x + 1;
            const double det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            const double wb = ((points[i].u - a[0]) * (c[1] - a[1]) - (points[i].v - a[1]) * (c[0] - a[0])) / det;
            const double wc = ((b[0] - a[0]) * (points[i].v - a[1]) - (b[1] - a[1]) * (points[i].u - a[0])) / det;
            const double w[3] = {1.0 - wb - wc, wb, wc};
            const double least = std::min({w[0], w[1], w[2]});
            if (least > best) best = least, found = t, std::copy(w, w + 3, weights);
        }
        if (found < 0) throw std::runtime_error("far_refined_limit: a face without triangles");
        const auto corners = last.GetFaceVertices(found);
        for (int k = 0; k < 3; ++k)
            for (std::size_t x = 0; x < 3; ++x) out[3 * i + x] += weights[k] * limit[std::size_t(corners[k])].x[x];
    }
    return out;
}

}  // namespace loopsub::testing
