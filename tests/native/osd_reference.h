// OpenSubdiv (Debian's libosd-dev) as the reference for the core: the expected values of the exact tests come
// from here, never from the project's own code.
//
// OsdReference refines a mesh with Far::TopologyRefiner (Sdc::SCHEME_LOOP, uniform refinement) and
// Far::PrimvarRefinerReal<double>. OpenSubdiv numbers its child vertices differently from the seed's order the
// project uses, so map() rearranges the result into a Plan's numbering *through the topology* (not by nearest
// neighbour): our level-0 vertex i is OpenSubdiv's vertex i; our level-(L+1) vertex i < n_L is the child of
// OpenSubdiv's level-L vertex map_L[i]; our vertex n_L + k is the child of OpenSubdiv's edge between the two
// mapped ends of our edge k of level L (Plan::level_edges). The Plan is only asked which edge is which; if its
// edge list does not name exactly OpenSubdiv's edges, map() says so in MappedReference::errors.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::testing {

struct ReferenceOptions {
    Boundary boundary = Boundary::EdgesOnly;
    CreaseMethod crease_method = CreaseMethod::Uniform;
    int levels = 1;
    FaceVaryingInterpolation face_varying = FaceVaryingInterpolation::All;
};

// One face-varying channel of 2 floats per value (UVs): value indices per triangle corner. Interpolated with
// ReferenceOptions::face_varying as Sdc::Options::FVarLinearInterpolation.
struct ReferenceUVs {
    const std::int32_t* triangle_uvs = nullptr;  // 3 per triangle
    const float* uvs = nullptr;                  // 2 per value
    int num_uvs = 0;
};

// OpenSubdiv's result rearranged into a Plan's numbering.
struct MappedReference {
    // our_to_osd[L][i]: OpenSubdiv's index at level L of our vertex i of level L.
    std::vector<std::vector<std::int32_t>> our_to_osd;
    // positions[L]: OpenSubdiv's level-L positions, 3 per vertex, in our order.
    std::vector<std::vector<double>> positions;
    // OpenSubdiv's last-level faces written with our vertex indices (OpenSubdiv's face order and corner order).
    std::vector<std::int32_t> triangles;
    // Level-0 face each of them descends from (OpenSubdiv's parent links).
    std::vector<std::int32_t> ancestors;
    // 2 floats per corner of each of `triangles` (empty without UVs): refined (InterpolateFaceVarying) and at the
    // limit (LimitFaceVarying).
    std::vector<double> face_uvs, face_uvs_limit;
    // Far::PrimvarRefiner::Limit on the last level, our order: positions (3 per vertex), the unit normal
    // tan1 x tan2 (3 per vertex), and whether OpenSubdiv's rule there is smooth or dart (one normal per vertex).
    std::vector<double> limit_positions, limit_normals;
    std::vector<std::uint8_t> limit_smooth;
    // Sharpness of every last-level edge (ends in our numbering) and vertex (our order), as OpenSubdiv's refiner
    // carries them down (decremented per level, Chaikin-averaged, ...). OpenSubdiv makes boundary and
    // non-manifold edges infinitely sharp whatever their tags (and one-face boundary vertices too under
    // EdgesAndCorners), which `implicit` marks: there an output tag does not matter.
    struct EdgeTag {
        std::int32_t a, b;
        float sharpness;
        bool implicit;
    };
    struct VertexTag {
        float sharpness;
        bool implicit;
    };
    std::vector<EdgeTag> edge_tags;
    std::vector<VertexTag> vertex_tags;
    // Why the numbering could not be matched (the Plan's edges or counts differ from OpenSubdiv's); empty when
    // all is well. Everything above is only meaningful when this is empty.
    std::vector<std::string> errors;
};

class OsdReference {
public:
    // positions: 3 floats per vertex of mesh. Throws std::runtime_error if OpenSubdiv refuses the mesh.
    OsdReference(const MeshView& mesh, const float* positions, const ReferenceOptions& options,
                 const ReferenceUVs& uvs = {});
    ~OsdReference();
    OsdReference(const OsdReference&) = delete;
    OsdReference& operator=(const OsdReference&) = delete;

    int levels() const;
    int num_vertices(int level) const;
    int num_edges(int level) const;
    int num_faces(int level) const;
    // OpenSubdiv's positions of a level in its own order, 3 doubles per vertex.
    const std::vector<double>& osd_positions(int level) const;

    // The result in the Plan's numbering, for levels 0 .. min(plan.levels(), levels()).
    MappedReference map(const Plan& plan) const;

    // Far::PrimvarRefiner::Limit on the reference's last level at the descendants (vertex children) of our vertices of
    // `level` (mapped from a plan of that many levels): the limit the refinement tends to, when the reference has
    // refined until the semi-sharp features are spent. 3 per vertex: positions, unit normals tan1 x tan2; and whether
    // the rule there is smooth or dart (one normal per vertex).
    struct DescendantLimits {
        std::vector<double> positions, normals;
        std::vector<std::uint8_t> smooth;
    };
    DescendantLimits descendant_limits(const MappedReference& mapped, int level) const;

    // For failure messages: what our vertex v of `level` (>= 1) is the child of, and OpenSubdiv's tags there
    // (rule, valence, sharpness of the parent vertex or edge and of the edge's ends).
    std::string describe_origin(const Plan& plan, const MappedReference& mapped, int level, int v) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// A triangle rotated so that its smallest index comes first (winding kept): two triangles are the same face with
// the same orientation exactly when their canonical forms are equal.
std::array<std::int32_t, 3> canonical_triangle(std::int32_t a, std::int32_t b, std::int32_t c);
// How many places canonical_triangle rotated (a, b, c) left: canonical[k] == original[(k + rotation) % 3].
int canonical_rotation(std::int32_t a, std::int32_t b, std::int32_t c);

// Compares output positions (3 floats per vertex, our order) with the mapped reference at `level`; every vertex must
// be within tolerance (absolute distance). Returns an empty string when all match, otherwise a report of the count
// and the worst few mismatches with their origin (describe_origin).
std::string compare_positions(const OsdReference& reference, const Plan& plan, const MappedReference& mapped, int level,
                              const std::vector<float>& ours, double tolerance);

// Compares the Plan's output triangles with OpenSubdiv's last level as sets of oriented faces; also the level-0
// parent of each (output_parent_triangles against OpenSubdiv's parent links). Returns "" when equal.
std::string compare_triangles(const Plan& plan, const MappedReference& mapped);

// Compares the Plan's output crease and corner tags with OpenSubdiv's last-level edge and vertex sharpness
// (within 1e-5), skipping implicit ones. Returns "" when equal.
std::string compare_crease_tags(const Plan& plan, const MappedReference& mapped);

}  // namespace loopsub::testing
