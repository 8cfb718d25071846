// The surface at a point of a triangle that is no regular patch (level_patches.h): the triangle's neighbourhood, the
// faces around its corners, refined on its own, a level at a time, until the point lies in a regular patch of the
// refined neighbourhood. Those faces are all that shapes the triangle's descendants: at every level, a child's
// neighbourhood is made of its parent's. (Chaikin's decay at the far end of an edge also reads edges outside them,
// which OpenSubdiv's Bfr ignores in the same way.)
//
// Around a non-manifold vertex (of several fans, or on an edge of three faces or more) the faces of other fans shape
// nothing of the triangle: such a vertex is a crease or a corner, whose masks read only its sharp edges. There the
// neighbourhood keeps the triangle's fan and, for each non-manifold edge that decides the vertex's rule, the fans of
// three faces on it (the vertex keeps its rule and class, the edge its face count; checked, and where a rule would
// change, all the faces as elsewhere): a few fans where a hundred pages meet on one edge, whose every triangle's
// neighbourhood held all of them, so that its refinement, and the rows of its weights, grew with their number.
// Tags are read as a plan of the level reads them (RuleSet): a tag on a non-manifold or boundary edge changes nothing
// (infinitely sharp whatever it says), nor one at a vertex made sharp by its fins. An edge tagged infinitely sharp
// counts as a sharp edge, kept where it makes the vertex a corner. The semi-sharp edges at the vertex are kept with
// their fans wherever the vertex's rule on some level, or the blend where it changes, or Chaikin's decay of the
// edges kept, reads them (all but a corner on every level under uniform decay). Tags elsewhere on a fan left out shape
// nothing kept, and those on the fans kept are kept with them. (Under Boundary::None the tessellation refines with
// EdgesOnly's rules, the same but for the faces that leave the surface, which the input's plan decided.)
//
// The neighbourhood is refined by a Plan of its own, on the unit vectors (one channel per vertex), so that the refined
// points come out as weights over the level's points; the result is a stencil, made once per mesh and rates. That plan
// is given the level's own edges (MeshView::triangle_edges): next to an interior vertex of valence 2 two of them share
// their ends, and read as one they were an edge of four faces, sharp. What the refinements hold is counted as
// Plan::estimate_bytes counts a plan, and refused past the limit it is given.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "loopsub/loopsub.h"
#include "tessellate/level_patches.h"

namespace loopsub::detail {

class RuleSet;

// A point of the surface as weights over a level's points: its position and its derivatives along the parameters of
// the face it was found in (their directions give the normal; their lengths are that face's).
struct Stencil {
    std::vector<std::int32_t> points;
    std::vector<double> position, ds, dt;
    void clear() { points.clear(), position.clear(), ds.clear(), dt.clear(); }
    void add(std::int32_t point, double p, double s, double t) {
        points.push_back(point), position.push_back(p), ds.push_back(s), dt.push_back(t);
    }
};

// A point of a face in exact coordinates: (s, t) = (S, T) / D.
struct FacePoint {
    std::int64_t S, T, D;
};

// Part of a level as a mesh of its own (a triangle's neighbourhood, a band of triangles): its triangles and the level's
// tags on it, in local vertex numbers, and the MeshView a plan of it reads (valid while this lives unchanged).
// triangle_edges: a refined level's edges in local numbers (MeshView::triangle_edges), empty for the input's.
struct LocalMesh {
    std::vector<std::int32_t> triangles, triangle_edges, creases, corners, cones;
    std::vector<float> crease_sharpness, corner_sharpness;
    MeshView view(int num_vertices) const;
};

// Moves a point of a face into the face's child that holds it (the split's order: corner children 0 to 2, the middle
// child 3), returning the child's number; the point's coordinates become the child's.
int descend(FacePoint& point);

// What a tessellation holds, counted: its result and plans, and the refinements of its bands' neighbourhoods as they
// are made, against its memory limit.
struct RefinementBytes {
    std::uint64_t limit = 0, held = 0, peak = 0;
};

class LocalRefiner {
public:
    // level: the refined level's patches; plan: the plan that made the level (its output tags are the level's);
    // cones: the input's cone vertices (Hoppe94), which keep their numbers.
    // bytes: what the tessellation holds besides (MemoryLimitError past its limit); must outlive this.
    LocalRefiner(const LevelPatches& level, const Plan& plan, const Options& options, const std::int32_t* cones,
                 int num_cones, RefinementBytes& bytes);
    ~LocalRefiner();
    // The weights of `point` of `face` (not at a corner of it).
    void weights(int face, FacePoint point, Stencil& out);

    // Levels past the level a neighbourhood is refined to at most; past them the point's triangle is taken as flat
    // between its corners' limit points (an error of about 4^-kMaxLocalLevels of the triangle's size).
    static constexpr int kMaxLocalLevels = 4;

private:
    struct Refined;
    struct Neighbourhood;
    struct Fans;
    Neighbourhood& neighbourhood(int face);
    const Fans& fans(std::int32_t v);
    void add_faces_around(std::int32_t v, int face, std::vector<int>& faces);
    bool keeps_rules(std::int32_t v, const std::vector<int>& faces);
    float vertex_sharpness(std::int32_t v, int valence, int edge_faces, int fins) const;
    void refine(Neighbourhood& n, Refined& r, int levels, bool limit_surface);
    // Counts bytes held from now on and, while they are made, `transient` more, refusing what passes the limit.
    template <typename What>
    void hold(std::uint64_t bytes, std::uint64_t transient, What what);

    const LevelPatches& level_;
    Options options_;
    std::unique_ptr<RuleSet> rules_;
    std::unordered_map<std::uint64_t, float> crease_tags_;
    std::unordered_map<std::int32_t, float> corner_tags_;
    std::vector<bool> cone_;
    std::unordered_map<std::int32_t, std::unique_ptr<Fans>> fans_;
    // Neighbourhoods kept for the next points of their triangles, all forgotten past kCachedBytes (a triangle of a
    // level holds a few points at most, and those of one input triangle come together), as counted in bytes_.
    static constexpr std::uint64_t kCachedBytes = std::uint64_t(32) << 20;
    std::unordered_map<int, std::unique_ptr<Neighbourhood>> cache_;
    RefinementBytes& bytes_;
    std::uint64_t cached_bytes_ = 0;
};

}  // namespace loopsub::detail
