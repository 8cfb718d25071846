// Tessellation of the Loop limit surface at a rate per edge: the run-time level of detail of the seed talk. Each input
// triangle is cut into a lattice of its own, as fine along each edge as that edge's rate says, and every point of it is
// placed on the limit surface (the surface that refinement converges to, what Blender's "Use Limit Surface" and
// OpenSubdiv's Bfr evaluate). A point on an edge of the mesh is computed once and shared by the triangles on both
// sides, so the result has no cracks whatever the rates. A rate of 2^L on every edge gives the vertices of L levels of
// refinement, on the limit surface.
//
// Usage is two-phase, as with Plan: a Tessellation holds all the work that depends on the mesh and the rates, and
// evaluate() places the points for one frame's positions.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub {

// Segments per edge of the input mesh (each >= 1): uniform_rate, except for the edges listed (vertex pairs, either
// order) with a rate of their own.
struct TessellationRates {
    int uniform_rate = 1;
    const std::int32_t* edges = nullptr;  // 2 * num_edges vertex indices
    const std::int32_t* rates = nullptr;  // num_edges rates
    int num_edges = 0;
};

// A camera, for rates from the screen: world to clip space as a 4x4 matrix, row-major (clip = M (x, y, z, 1), with
// OpenGL's convention: a point is in view where w > 0 and -w <= x, y <= w), and the viewport's size in pixels.
struct Camera {
    float world_to_clip[16] = {};
    float viewport_width = 0.0f, viewport_height = 0.0f;
};

// A perspective camera at `eye` looking at `target`, `up` above it, with a vertical field of view in degrees and a
// viewport of width x height pixels: OpenGL's look-at and perspective matrices (near and far planes at 1e-3 and 1e6,
// which rates do not read). InputError where the eye, the target and up span no view.
Camera look_at_camera(const float eye[3], const float target[3], const float up[3], float fov_degrees, float width,
                      float height);

// What a camera's rates hold an edge to (screen_space_rates), measured as Cycles measures its dicing: as if the edge
// faced the camera straight ahead at its midpoint's distance from it (an edge seen end on is not spared, an edge
// running past the camera, or beside it out of the picture, is not blown up by the projection), in pixels.
enum class DicingMeasure {
    Length,    // Cycles' dicing rate: the edge's length, `pixels` per segment
    Deviation  // how far a segment strays from the surface along the edge: the edge's bulge (after one smooth split,
               // boundaries as creases, its new point's distance from the chord of its ends' new points: (h^2 / 8)
               // t'Ht on a quadratic surface) over r^2 for r segments, at most `pixels`; then no edge coarser than
               // the other edges of its triangles. Flat stretches take few segments however long they are.
};

// Rates from the screen: each edge of the mesh (its cage's straight edge, from its vertices' positions) cut into as
// few segments as keep it to `pixels` by `measure`, from 1 to max_rate. An edge out of the view (the box around its
// ends on screen misses it; for one reaching behind the camera, its midpoint is out of it) takes `offscreen_scale`
// times fewer; an edge with both ends behind the camera, 1.
struct ScreenRates {
    std::vector<std::int32_t> edges;  // each edge of the mesh once, as a vertex pair
    std::vector<std::int32_t> rates;  // its rate
    TessellationRates view() const;   // for a Tessellation, while this lives
};
ScreenRates screen_space_rates(const MeshView& mesh, const float* positions, const Camera& camera, float pixels,
                               int max_rate, DicingMeasure measure = DicingMeasure::Length,
                               float offscreen_scale = 4.0f);

// The largest rate accepted: 2^12 segments per edge, 16.8 million points per triangle.
inline constexpr int kMaxTessellationRate = 4096;

struct TessellationImpl;
struct InputTopologyParts;

// What a Tessellation read of its input mesh alone, whatever the rates (the input's classification, its triangles that
// are regular patches, its edges; its face-varying layers' the same), for one of the same mesh at other rates: a
// camera's next cut need not do it again. It holds nothing of the result: an old cut may go before the next is made.
// Cheap to copy; read only, so tessellations made on several threads may share it.
class InputTopology {
public:
    InputTopology();
    ~InputTopology();
    InputTopology(const InputTopology&);
    InputTopology& operator=(const InputTopology&);
    bool empty() const;  // nothing kept (an InputTopology made empty)

private:
    friend class Tessellation;
    std::shared_ptr<const InputTopologyParts> parts_;
};

class Tessellation {
public:
    // The mesh as for Plan; of options, the rules, boundary, crease method, crease threshold, face-varying
    // interpolation, kernel, threads and memory limit count (the levels are the ones the rates need). A face's inner
    // rate is the largest of its edges'. Throws InputError for bad input, MemoryLimitError past the memory limit.
    //
    // The triangles without a limit surface (hole tags, and with Boundary::None those a plan takes out of the surface:
    // the faces at the ends of a boundary edge not tagged infinitely sharp) shape the surface around them, as in a
    // plan, but are not cut: they have no triangles and no face points, and their edges and insides no points (an
    // edge of a triangle with a surface has its points). The input's vertices keep their numbers; one of no triangle
    // with a surface (or of none at all) is given its input position by evaluate().
    //
    // reuse: an earlier tessellation's input_topology(), of the same mesh at other rates (a camera's last). It is
    // taken where its triangles, tags and rules are this mesh's, and made anew where they are not; the result is the
    // same either way.
    Tessellation(const MeshView& mesh, const Options& options, const TessellationRates& rates,
                 const InputTopology& reuse = InputTopology());
    ~Tessellation();
    Tessellation(Tessellation&&) noexcept;
    Tessellation& operator=(Tessellation&&) noexcept;
    Tessellation(const Tessellation&) = delete;
    Tessellation& operator=(const Tessellation&) = delete;

    // The points: the input's vertices first (same indices), then the points inside the input's edges, then those
    // inside its triangles.
    int num_points() const;
    int num_triangles() const;
    const std::int32_t* triangles() const;         // 3 per triangle, counter-clockwise
    const std::int32_t* parent_triangles() const;  // the input triangle each triangle lies in
    // Face points: each point of each input triangle, once per triangle (a point on an edge or at a vertex is a face
    // point of every triangle around it). Each has its parameters (u, v) in its triangle (the point is corner 0 plus u
    // times (corner 1 - corner 0) plus v times (corner 2 - corner 0), as OpenSubdiv's Bfr has it) and its normal, which
    // differs between the triangles around a sharp edge. Per corner of each output triangle, its face point.
    int num_face_points() const;
    const std::int32_t* corner_face_points() const;  // 3 per triangle
    const float* face_point_parameters() const;      // (u, v) per face point
    // The triangles' edges, each once (in the order the triangles first reach them, each as its first triangle has
    // it), and per triangle its three edges (edge k joins its corners k and k + 1), as Plan::output_edges gives them:
    // a mesh built from the tessellation needs no edge search. Made on each call (one pass, no sorting).
    struct Edges {
        std::vector<std::int32_t> edge_vertices;   // 2 per edge
        std::vector<std::int32_t> triangle_edges;  // 3 per triangle
    };
    Edges output_edges() const;
    // Face-varying layers (MeshView::face_varying), refined by Options::face_varying as a Plan refines them. A layer is
    // its input level as a mesh of its own (Plan::face_varying_base: one vertex per (vertex, value) pair, so that a
    // seam is a boundary of it) cut by the same rates, the values its class keeps (FaceVaryingValueClass::Stays)
    // tagged as corners and the mesh's tags carried onto it; with FaceVaryingInterpolation::All, linear in each
    // triangle. Writes `channels` floats per face point (num_face_points() rows, as the normals) from `channels` per
    // value of the layer. Throws InputError on a non-finite value. Not reentrant.
    int num_face_varying_layers() const;
    void evaluate_face_varying(int layer, const float* values, int channels, float* out) const;
    // The refinement levels whose control points and limit the points are made from.
    int levels() const;
    // The input's notes, as Plan::notes gives them.
    const std::vector<InputProblem>& notes() const;
    // What this read of its input mesh alone, for a tessellation of the same mesh at other rates.
    InputTopology input_topology() const;
    // Bytes the memory check counted against Options::memory_limit_bytes: the result's arrays, the plans of the input
    // triangles that are no patch (Plan::estimate_bytes), the most their neighbourhoods' local refinements held at
    // once besides (counted as each was made), and each face-varying layer's own cut.
    std::uint64_t estimated_bytes() const;

    // Places the points for the input's positions (3 floats per input vertex): points gets 3 * num_points() floats,
    // normals (optional, may be null) 3 * num_face_points() floats, unit length (zero where the surface has no tangent
    // plane). Throws InputError on a non-finite position. Not reentrant.
    void evaluate(const float* positions, float* points, float* normals) const;

private:
    std::unique_ptr<TessellationImpl> impl_;
};

}  // namespace loopsub
