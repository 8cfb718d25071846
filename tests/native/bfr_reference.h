// OpenSubdiv's true limit surface (Bfr::Surface, as Blender's "Use Limit Surface" shows it) at the last level's
// vertices of a plan: the reference for the limit where semi-sharp creases have not decayed by the last level, where
// Far::PrimvarRefiner::Limit (osd_reference.h) stops short and takes them for infinitely sharp.
//
// A uniform refinement's level-L vertices are the points of a uniform tessellation at rate 2^L of each base face: an
// output triangle t descends from base face t >> 2L through the split's corner and middle children (2 bits a level,
// docs/architecture.md, "The split's numbering"), which gives its corners' (u, v) in the base face's parameterisation.
#pragma once

#include <cstdint>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::testing {

struct TestMesh;

struct BfrLimit {
    std::vector<double> positions;  // 3 per output vertex
    // 3 per output corner (3 t + k): Du x Dv of the corner's base face at its (u, v), unit; zero where degenerate.
    std::vector<double> normals;
};

// A point of a face of the mesh, in Bfr's parameters: corner 0 + u (corner 1 - corner 0) + v (corner 2 - corner 0).
struct BfrPoint {
    int face;
    double u, v;
};

// The true limit surface at points of the mesh's faces (grouped by face for speed), its tags, holes, boundary and
// crease method as Bfr reads them: positions and unit normals per point (normals: 3 per point, not per corner). Bfr's
// surface near irregular vertices is an approximation, here at its finest (2^-10 of a face). Faces with a limit
// surface only (bfr_faces_with_surface).
BfrLimit bfr_evaluate(const TestMesh& mesh, const std::vector<BfrPoint>& points);

// A third reference, Bfr's patches left out: the limit surface at points of the mesh's faces from Far's uniform
// refinement, `levels` levels down (PrimvarRefiner::Interpolate, then Limit at the last level), between the limit
// points of the corners of the last level's triangle that holds the point (linear there: off by O(4^-levels) of a
// face's size). Each point's place in the refinement comes from a face-varying channel that Far refines linearly,
// each base corner its own value: (face, u, v). 3 positions per point.
std::vector<double> far_refined_limit(const TestMesh& mesh, const std::vector<BfrPoint>& points, int levels);

// Per face of the mesh, whether Bfr gives it a limit surface (Bfr::SurfaceFactory::FaceHasLimitSurface: no hole tag,
// and under Boundary::None no corner on a boundary edge that is not infinitely sharp).
std::vector<bool> bfr_faces_with_surface(const TestMesh& mesh);

// The limit of the mesh's UVs (its face-varying layer, interpolated by `mode`) at points of its faces: 2 per point.
std::vector<double> bfr_evaluate_face_varying(const TestMesh& mesh, const std::vector<BfrPoint>& points,
                                              FaceVaryingInterpolation mode);

// The plan must have been built for `mesh` (its tags, boundary and crease method; no holes) with the OpenSubdiv rules.
BfrLimit bfr_limit(const TestMesh& mesh, const Plan& plan);
// The limit of the mesh's UVs (its face-varying layer, interpolated by the plan's Options::face_varying) at the
// output's corners: 2 per corner (3 t + k).
std::vector<double> bfr_face_varying_limit(const TestMesh& mesh, const Plan& plan);

}  // namespace loopsub::testing
