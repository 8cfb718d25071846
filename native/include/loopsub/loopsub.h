// Loop subdivision of triangle meshes with creases.
//
// Two rule sets, chosen at run time:
//   * Rules::Hoppe94    - the GDC'99 seed's rules (after Hoppe et al. 94): smooth, dart, crease (regular and
//                         irregular), corner and cone vertices; edge masks {3,3,1,1}, {5,3,0,0}, {1,1,0,0}.
//   * Rules::OpenSubdiv - OpenSubdiv's Sdc::SCHEME_LOOP: semi-sharp creases, vertex sharpness, Chaikin creasing,
//                         both boundary modes, non-manifold topology made sharp.
//
// Usage is two-phase, as in OpenSubdiv's Far: a Plan holds all topology work (edges, classification, child
// connectivity, stencil weights) and is built once per mesh; Plan::evaluate() then refines vertex data (positions
// and any other per-vertex channels) and is the only work done per frame.
//
// Output order follows the seed (slides 28-29): at every level the old vertices keep their indices, then one new
// vertex per edge of that level, in the order of Plan::level_edges(). Child triangle 4f+k has parent f; the
// three corner children come first, in the parent's corner order, and the middle triangle last.
//
// All input errors throw loopsub::InputError (never crash, never return garbage).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace loopsub {

// What is wrong with an input (or worth telling of it), as data: its kind, the element it is in (`element`, `index`
// and, of a triangle, `corner`) and the numbers its message gives, so that a front end can say where in its own words
// (an OBJ line, a Blender polygon, a UV map's name). diagnose() lists them; an InputError carries the one it met.
// A field a kind does not use is -1 (value and limit: 0).
struct InputProblem {
    enum class Kind : std::uint8_t {
        VertexOutOfRange,    // element `index` (a triangle: at `corner`) refers to vertex `refers_to`; the mesh has
                             // `other` vertices
        TriangleOutOfRange,  // hole `index` refers to triangle `refers_to`; the mesh has `other` triangles
        ValueOutOfRange,     // corner `corner` of triangle `index` in face-varying layer `layer` refers to value
                             // `refers_to`; the layer has `other` values
        DegenerateTriangle,  // triangle `index` repeats vertex `refers_to`, at `corner` and a corner before it
        NotAnEdge,           // crease edge or rated edge `index`, from vertex `refers_to` to `other`, is no edge of the
                             // mesh
        BadSharpness,        // crease edge or corner vertex `index` has sharpness `value`: negative or not finite
        NonFiniteValue,      // vertex, face-varying value (of `layer`) or triangle `index` (at `corner`) has `value`
                             // in channel `channel`; or the camera's world_to_clip entry `index` has `value`
        ValueTooLarge,       // the same with `value` beyond +-`limit`, which keeps sums of up to `other` values finite
        // A note, no error: triangle `index` runs along its edge `corner` (from that corner to the next) the same way
        // as triangle `other` does, as a face wound against its neighbours leaves it; the rules make the edge
        // infinitely sharp (docs/rules.md, Sharpness).
        RunsTheSameWay,
        // A tessellation's rated edge `index`, from vertex `refers_to` to `other`, has rate `value`, outside 1..`limit`
        // (kMaxTessellationRate, loopsub/tessellation.h).
        RateOutOfRange,
        // MeshView::triangle_edges: corner `corner` of triangle `index` numbers its edge (to the next corner)
        // `refers_to`, outside 0..`other` - 1
        EdgeOutOfRange,
        // the same, with `refers_to` a number that joins other vertices in triangle `other`
        EdgeEndsDiffer,
    };
    enum class Element : std::uint8_t {
        Vertex,            // MeshView::num_vertices: a vertex's values
        Triangle,          // MeshView::triangles (a corner of one: `corner`)
        CreaseEdge,        // MeshView::crease_edges and crease_sharpness
        CornerVertex,      // MeshView::corner_vertices and corner_sharpness
        Cone,              // MeshView::cone_vertices
        Hole,              // MeshView::hole_triangles
        FaceVaryingValue,  // a value of face-varying layer `layer`
        RatedEdge,         // TessellationRates::edges and rates (loopsub/tessellation.h): an edge given a rate
        Camera,            // Camera::world_to_clip (loopsub/tessellation.h): `index` is its entry, row-major
    };
    Kind kind = Kind::VertexOutOfRange;
    Element element = Element::Vertex;
    int index = -1;
    int corner = -1;
    int refers_to = -1;
    int other = -1;
    int layer = -1;
    int channel = -1;
    float value = 0.0f;
    float limit = 0.0f;

    bool is_note() const { return kind == Kind::RunsTheSameWay; }
    // The message an InputError gives, in the core's numbering: "triangle 2 is degenerate: it repeats vertex 5".
    std::string message() const;
};

// The names a front end gives kinds and elements, as the Python module does (InputError.kind): "vertex_out_of_range",
// "crease_edge".
const char* problem_name(InputProblem::Kind kind);
const char* problem_name(InputProblem::Element element);

// Invalid input: the message says what and where (index, value). Where the data is at fault (not the call: a null
// pointer, a channel count), problem() says it as data.
class InputError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
    // what(): `context` (such as "evaluate_face_varying: "), then problem.message().
    explicit InputError(const InputProblem& problem, const std::string& context = "");
    const InputProblem* problem() const { return has_problem_ ? &problem_ : nullptr; }

private:
    InputProblem problem_;
    bool has_problem_ = false;
};

// The requested refinement would need more memory than Options::memory_limit_bytes allows.
class MemoryLimitError : public std::runtime_error {
public:
    MemoryLimitError(const std::string& what, std::uint64_t required_bytes)
        : std::runtime_error(what), required_bytes(required_bytes) {}
    std::uint64_t required_bytes;
};

enum class Rules { Hoppe94, OpenSubdiv };

// How a boundary vertex with a single incident face is treated (OpenSubdiv's Sdc::Options::VtxBoundaryInterpolation).
enum class Boundary {
    EdgesOnly,        // VTX_BOUNDARY_EDGE_ONLY: Blender's "Boundary Smooth: All"
    EdgesAndCorners,  // VTX_BOUNDARY_EDGE_AND_CORNER: Blender's "Keep Corners"
    // VTX_BOUNDARY_NONE: the faces around a boundary vertex with a boundary edge not tagged infinitely sharp become
    // holes (refined, not written); the rest as EdgesOnly.
    None
};

enum class CreaseMethod { Uniform, Chaikin };  // OpenSubdiv only: how semi-sharp sharpness decays per level

// Where face-varying values (UVs) stay linear: OpenSubdiv's Sdc::Options::FVarLinearInterpolation, in its order
// (OpenSubdiv's shape files number them 0 .. 5). Blender's Subdivision Surface names in brackets.
enum class FaceVaryingInterpolation {
    None,          // smooth everywhere, seams and boundaries too ("All" smooth)
    CornersOnly,   // corners of a UV island stay, the rest is smooth ("Keep Corners"); OpenSubdiv's default
    CornersPlus1,  // and junctions of three or more islands ("Keep Corners, Junctions")
    CornersPlus2,  // and concave corners ("Keep Corners, Junctions, Concave")
    Boundaries,    // seams and boundaries stay linear ("Keep Boundaries", Blender's default)
    All            // linear everywhere ("None")
};

// Which evaluation kernels run. Auto picks the widest the CPU supports; Scalar is the reference path.
enum class Kernel { Auto, Scalar, SSE41, AVX2 };

// The stencil tables of the refined levels (docs/benchmark.md, "Stored or derived tables"). Stored, an evaluation
// reads them. Derived, the plan holds the levels' connectivity only and an evaluation works the tables out from it,
// chunk by chunk: a plan then builds faster and holds less besides its output, and each evaluation takes longer
// (the measured ratios are in that section). Derived applies only where nothing but vertex values is refined (no limit
// surface, no face-varying layers) over two levels or more; elsewhere the tables are stored. The limit surface's
// rings are the exception: over two levels or more (without holes), Auto and Derived work them out from the level two
// before the last as an evaluation runs, which builds faster and evaluates faster too (docs/architecture.md, "Level
// tables"); Stored stores them.
enum class LevelTables {
    Auto,    // derived past 128 MiB of tables of the level before the last (a level-6 result of 20 M triangles)
    Stored,  // for a plan evaluated again and again (playback)
    Derived  // for a plan evaluated once (a command-line run)
};

inline constexpr float kInfiniteSharpness = 10.0f;  // Sdc::Crease::SHARPNESS_INFINITE
// Options::threads above this is refused: each thread is a real one, and a count meant as "all you have" (or a typo)
// must not try to start millions of them.
inline constexpr int kMaxThreads = 256;
// Options::levels above this is refused. Level 16 of a single triangle is already past 32-bit indices (refused as
// memory), but a mesh without triangles refines to itself at any level, and each level is still a plan record.
inline constexpr int kMaxLevels = 64;

struct Options {
    Rules rules = Rules::Hoppe94;
    int levels = 1;
    // Hoppe94: an edge is a crease when its sharpness is > 0 and >= crease_threshold (0: any positive sharpness).
    float crease_threshold = 0.0f;
    Boundary boundary = Boundary::EdgesOnly;
    CreaseMethod crease_method = CreaseMethod::Uniform;
    FaceVaryingInterpolation face_varying = FaceVaryingInterpolation::CornersOnly;
    Kernel kernel = Kernel::Auto;
    // Put the last level on the limit surface (Blender's "Use Limit Surface"): evaluate() then writes limit values,
    // and can write the limit normals too. OpenSubdiv: Far::PrimvarRefiner::Limit. Hoppe94: the limits of its own
    // masks (docs/python.md, "The limit surface").
    bool limit_surface = false;
    // Up to kMaxThreads, each a real thread (the add-on gives every core; any count gives the same bits). From 2, the
    // process keeps the extra threads between calls (awake for 1 ms after each, then asleep), so that frames back to
    // back start none.
    int threads = 1;
    LevelTables level_tables = LevelTables::Auto;
    // Plan building refuses to allocate past this (MemoryLimitError says how much it would need).
    std::uint64_t memory_limit_bytes = std::uint64_t(4) << 30;
};

// How a face-varying value is refined, as a plan classifies it at the input's level (Plan::face_varying_base).
enum class FaceVaryingValueClass : std::uint8_t {
    Vertex,  // its vertex has no seam: it takes the vertex's own rules
    Seam,    // it runs along its seam as a crease
    Stays,   // it stays where it is (a corner of its UV island, as Options::face_varying keeps it)
    Held     // held while semi-sharp features around it decay, then it runs along its seam
};

// One face-varying layer (a UV map): the value index of each corner of each triangle. Corners of a vertex with the
// same index share their value; where a vertex's corners take different values the layer has a seam there, and each
// side is refined from its own values (OpenSubdiv's face-varying channel).
struct FaceVaryingLayer {
    const std::int32_t* corner_values = nullptr;  // 3 * num_triangles indices in [0, num_values)
    int num_values = 0;
};

// A triangle mesh with crease tags. Plain arrays, not owned; only read while building a Plan.
struct MeshView {
    int num_vertices = 0;
    const std::int32_t* triangles = nullptr;  // 3 * num_triangles vertex indices, counter-clockwise
    int num_triangles = 0;

    const std::int32_t* crease_edges = nullptr;  // 2 * num_crease_edges vertex indices (edge a-b, either order)
    const float* crease_sharpness = nullptr;     // num_crease_edges values >= 0 (kInfiniteSharpness = sharp)
    int num_crease_edges = 0;

    const std::int32_t* corner_vertices = nullptr;  // num_corners vertex indices
    const float* corner_sharpness = nullptr;        // num_corners values >= 0 (Hoppe94: > 0 makes a corner)
    int num_corners = 0;

    const std::int32_t* cone_vertices = nullptr;  // Hoppe94 only: vertices tagged as cones
    int num_cones = 0;

    const FaceVaryingLayer* face_varying = nullptr;  // num_face_varying layers, refined by Options::face_varying
    int num_face_varying = 0;

    // Holes (OpenSubdiv's hole tags): these triangles shape the surface around them but their descendants are not
    // part of the output; the vertices stay.
    const std::int32_t* hole_triangles = nullptr;
    int num_holes = 0;

    // Optional: each triangle's edges, 3 per triangle (edge k from corner k to corner k + 1), as numbers from 0 to
    // 3 * num_triangles - 1, one number always on the same two vertices. Without them an edge is every side with the
    // same two ends, as OpenSubdiv reads a mesh; with them, every side with the same number, so that two edges may
    // share their ends. A refined level has such pairs (next to an interior vertex of valence 2, the edges inside its
    // two faces join the same two neighbours): fed back in with Plan::output_edges' numbers, it goes on to the same
    // surface. A crease tag on two vertices tags every edge between them. Not with face-varying layers, nor for a
    // Tessellation.
    const std::int32_t* triangle_edges = nullptr;
};

// The owning counterpart of MeshView, for C++ callers that build a mesh: view() lends it to a Plan.
struct MeshData {
    std::vector<float> positions;            // 3 per vertex
    std::vector<std::int32_t> triangles;     // 3 per triangle, counter-clockwise
    std::vector<std::int32_t> crease_edges;  // pairs
    std::vector<float> crease_sharpness;
    std::vector<std::int32_t> corner_vertices;
    std::vector<float> corner_sharpness;
    std::vector<std::int32_t> cone_vertices;
    std::vector<std::int32_t> hole_triangles;

    int num_vertices() const { return int(positions.size() / 3); }
    int num_triangles() const { return int(triangles.size() / 3); }
    void add_crease(int a, int b, float sharpness = kInfiniteSharpness);
    void add_corner(int v, float sharpness = kInfiniteSharpness);
    MeshView view() const;  // valid while this mesh lives and is not modified
};

// Vertex classes of docs/rules.md, "Vertex classes" (Hoppe94) and Sdc::Crease::Rule (OpenSubdiv: smooth, dart, crease,
// corner).
enum class VertexType : std::uint8_t {
    Smooth = 0,
    Dart = 1,
    RegularCrease = 2,
    IrregularCrease = 3,
    Corner = 4,
    Cone = 5
};

// A view of per-vertex float data: value of channel c at vertex i is data[c * channel_stride + i * element_stride].
// Interleaved (n x C, row-major): channel_stride = 1, element_stride = C. Planar (C x n): channel_stride = n,
// element_stride = 1.
template <typename Float>
struct ChannelsView {
    Float* data = nullptr;
    int num_channels = 0;
    std::size_t channel_stride = 1;
    std::size_t element_stride = 1;

    // A writable view can be read from.
    template <typename T = Float, typename = std::enable_if_t<!std::is_const_v<T>>>
    operator ChannelsView<const T>() const {
        return {data, num_channels, channel_stride, element_stride};
    }
};

inline ChannelsView<const float> interleaved(const float* data, int num_channels) {
    return {data, num_channels, 1, std::size_t(num_channels)};
}
inline ChannelsView<float> interleaved(float* data, int num_channels) {
    return {data, num_channels, 1, std::size_t(num_channels)};
}

struct PlanImpl;

class Plan {
public:
    // Validates the mesh and tags (InputError), checks the memory estimate (MemoryLimitError), and does all the
    // topology work for options.levels levels.
    Plan(const MeshView& mesh, const Options& options);
    ~Plan();
    Plan(Plan&&) noexcept;
    Plan& operator=(Plan&&) noexcept;
    Plan(const Plan&) = delete;
    Plan& operator=(const Plan&) = delete;

    const Options& options() const;
    int levels() const;

    int num_input_vertices() const;
    int num_output_vertices() const;
    int num_output_triangles() const;

    // Output connectivity: 3 * num_output_triangles() indices, winding kept (holes left out).
    const std::int32_t* output_triangles() const;
    // For each output triangle, the input triangle it came from.
    const std::int32_t* output_parent_triangles() const;

    // Crease tags of the output mesh, so that it can be fed back in: edges with positive sharpness (OpenSubdiv:
    // decremented per level; Hoppe94: the input value carried over) and vertices with positive corner sharpness.
    const std::vector<std::int32_t>& output_crease_edges() const;  // pairs
    const std::vector<float>& output_crease_sharpness() const;
    const std::vector<std::int32_t>& output_corner_vertices() const;
    const std::vector<float>& output_corner_sharpness() const;
    // Every edge of the output the rules treat as sharp (pairs), with its sharpness: tagged creases that pass the
    // rules (Hoppe94: the crease threshold), boundary and non-manifold edges (infinitely sharp). With
    // level_vertex_types(levels()), the one classification to tag the output with.
    const std::vector<std::int32_t>& output_sharp_edges() const;  // pairs
    const std::vector<float>& output_sharp_edge_sharpness() const;
    // The same edges as numbers of output_edges() (for plans of at least one level), in the same order: a caller
    // that builds the mesh from output_edges() marks them without matching vertex pairs.
    const std::vector<std::int32_t>& output_crease_edge_indices() const;
    const std::vector<std::int32_t>& output_sharp_edge_indices() const;

    // Edges of level L (0 <= L < levels()), as vertex pairs: edge k of level L becomes vertex
    // (number of level-L vertices + k) of level L+1.
    const std::vector<std::int32_t>& level_edges(int level) const;
    int level_num_vertices(int level) const;  // 0 <= level <= levels()
    // The output's edges as the last split numbers them (docs/architecture.md, "The split's numbering"), so that a
    // caller building a mesh needs no edge search. With E edges and F faces in level levels() - 1: the halves of
    // edge e are output edges 2e and 2e + 1, the edges inside face f are 2E + 3f + k. Writes
    // 2 * num_output_edges() vertex indices (each edge's ends) and 3 * num_output_triangles() edge indices (edge k
    // of a triangle joins its corners k and k + 1). For plans of at least one level and without holes
    // (std::logic_error otherwise: a hole's inner edges have no triangle to be read from). Given `triangles`, also
    // copies output_triangles() there (3 * num_output_triangles()) in the same pass, which reads them anyway: a mesh's
    // corner vertices and corner edges written together.
    int num_output_edges() const;
    void output_edges(std::int32_t* edge_vertices, std::int32_t* triangle_edges,
                      std::int32_t* triangles = nullptr) const;
    // For each output edge (output_edges()' order), the caller's number of the input edge it lies on, -1 inside an
    // input triangle: side_edges gives 3 numbers per input triangle, that of its edge k (from corner k to k + 1), -1
    // for none (a diagonal the caller's triangulation added); an edge given several takes the greatest. Writes
    // num_output_edges() numbers. For plans of at least one level and without holes (std::logic_error otherwise).
    void output_edge_parents(const std::int32_t* side_edges, std::int32_t* parents) const;
    // Class of each vertex of level L (0 <= L <= levels()) under the chosen rules: what the repositioning at level L
    // used; for the last level, the class its vertices would take at the next level (with the limit surface: what
    // the limit used). The one classification an application needs to tag the output. (With no levels and no limit
    // surface there is none: out_of_range.) Copied out on a level's first request (safe from several threads), and
    // kept with the plan.
    const std::vector<VertexType>& level_vertex_types(int level) const;

    // Refines per-vertex data: in has num_input_vertices() elements, out num_output_vertices(), both with the same
    // channel count. Throws InputError on a non-finite input value. Not reentrant: the plan owns scratch buffers.
    void evaluate(ChannelsView<const float> in, ChannelsView<float> out);
    // With Options::limit_surface: evaluate() and, from its first three channels (positions), the limit surface's
    // unit normal at every corner of every output triangle (num_output_triangles() x 3 x 3 floats, row-major).
    // Across a sharp edge (a crease, a boundary) each side has its own normal: the limit normal of the surface on
    // that side alone; elsewhere the corners of a vertex share one. Where the surface has no tangent plane (a
    // degenerate neighbourhood) the normal is the zero vector. InputError without the limit surface or with
    // fewer than three channels.
    void evaluate(ChannelsView<const float> in, ChannelsView<float> out, float* corner_normals);

    // The limit normals in compact form, for Options::limit_surface plans (std::logic_error otherwise): one normal
    // per output vertex, then one per side of each vertex whose fan infinitely sharp edges (creases, corners,
    // boundaries, non-manifold edges) split into two sides or more; a corner takes its vertex's or its side's. A
    // vertex of one side only (an open fan, as at a boundary) has that side's normal as its own. num_limit_normals()
    // is num_output_vertices() plus the number of sides of split fans. corner_normal_indices() gives, per corner of
    // each output triangle (3 * num_output_triangles()), the index of its normal: v for vertex v's own,
    // num_output_vertices() + s for the s-th side of a split fan. Both are the plan's, the same for every evaluation:
    // the corners of a vertex share an index exactly where no such edge parts them, and num_limit_normals() equals
    // num_output_vertices() exactly where no fan is split. A vertex of a split fan has a zero vector as its own. The
    // indices are made on their first request (safe from several threads) and kept with the plan.
    int num_limit_normals() const;
    const std::int32_t* corner_normal_indices() const;
    // evaluate() and the compact limit normals (num_limit_normals() x 3 floats, row-major): the normals of
    // evaluate(in, out, corner_normals), each written once, not once per corner (corner_normals[c] is
    // normals[corner_normal_indices()[c]]). Errors as that call.
    struct LimitNormals {
        float* normals = nullptr;
    };
    void evaluate(ChannelsView<const float> in, ChannelsView<float> out, LimitNormals normals);

    // Face-varying layers (MeshView::face_varying): the output's value index at each corner of each output triangle
    // (3 per triangle), and the number of output values.
    int num_face_varying_layers() const;
    const std::int32_t* output_face_varying_indices(int layer) const;
    int num_output_face_varying_values(int layer) const;
    // Refines the values of a face-varying layer (in: its num_values elements; out: num_output_face_varying_values)
    // by Options::face_varying, to the limit with Options::limit_surface. Throws InputError on a non-finite value.
    // Not reentrant, as evaluate().
    void evaluate_face_varying(int layer, ChannelsView<const float> in, ChannelsView<float> out);

    // A face-varying layer's input level as a mesh of its own, one vertex per (vertex, value) pair, so that a seam is a
    // boundary of it (docs/rules.md, "Face-varying layers"), with each base value's class: per corner of each input
    // triangle its base value, per base value the caller's value and its FaceVaryingValueClass.
    struct FaceVaryingBase {
        std::vector<std::int32_t> corner_values, values;
        std::vector<FaceVaryingValueClass> classes;
    };
    FaceVaryingBase face_varying_base(int layer) const;

    // Face-varying data without a layer: in holds num_channels floats per corner of each input triangle
    // (num_triangles x 3 x C, row-major), out the same per output triangle. Linear within each face, whatever
    // Options::face_varying says. Throws InputError on a non-finite input value.
    void evaluate_face_varying(const float* in, float* out, int num_channels) const;

    // What the checks of the input found worth telling that is no error (InputProblem::is_note: the edges two
    // triangles run along the same way, each once, as diagnose() lists them), found in one pass over the input's
    // corners as the plan builds its base level.
    const std::vector<InputProblem>& notes() const;

    // The kernel the plan actually uses (Auto resolved against the CPU).
    Kernel kernel() const;

    // Milliseconds spent in the constructor (topology) and in the last evaluate() call.
    double topology_ms() const;
    double last_evaluate_ms() const;

    // Bytes the plan and one evaluation of C channels would hold for a given input: what the memory check uses.
    // num_edges < 0: not known yet, a closed manifold's count (three halves per triangle) stands in.
    static std::uint64_t estimate_bytes(int num_vertices, int num_triangles, int levels, int num_channels,
                                        std::int64_t num_edges = -1);

private:
    std::unique_ptr<PlanImpl> impl_;
};

// Every problem of a mesh and its tags a Plan would refuse (InputProblem, in the order a Plan meets them: the holes,
// the triangles, the creases, corners and cones, the face-varying layers' value indices, then the creases that are no
// edge), each once, then the notes (edges two triangles run along the same way). With vertex_values (positions or
// any per-vertex channels; num_vertices of them), their non-finite values too (a value too large to refine depends on
// the plan: Plan::evaluate reports it). The topology's problems are looked for only where the triangles have none,
// as it is built from them. A view no plan could read (a negative count, a null array) throws InputError, as a Plan
// does. Plan(mesh, options) checks the same with the same code, and throws the first problem.
std::vector<InputProblem> diagnose(const MeshView& mesh, ChannelsView<const float> vertex_values = {});

// The non-finite values among per-corner values (num_channels floats per corner of each triangle, as
// weld_corner_values and Plan::evaluate_face_varying take them): NonFiniteValue problems at a triangle's corner, in
// order, `layer` set to the caller's number for these values (-1: none). The check evaluate_face_varying makes.
std::vector<InputProblem> diagnose_corner_values(const float* values, int num_triangles, int num_channels,
                                                 int layer = -1);

const char* kernel_name(Kernel kernel);
Kernel best_kernel();  // the widest kernel this CPU runs

// The names of an option's values, as the command line (--rules hoppe94), the Python module (rules="hoppe94") and the
// add-on spell them, in the order of the option's enum: names[i] names Option(i).
struct OptionNames {
    const char* const* names;
    int count;

    const char* const* begin() const { return names; }
    const char* const* end() const { return names + count; }
    // The names for a message, each between `quote`s: "a, b or c".
    std::string listed(const char* quote = "") const;
};

// One table for each of Rules (hoppe94 opensubdiv), Boundary (edges edges-and-corners none), CreaseMethod (uniform
// chaikin), FaceVaryingInterpolation (none corners corners-plus1 corners-plus2 boundaries all), LevelTables (auto
// stored derived) and DicingMeasure (length deviation; loopsub/tessellation.h).
template <typename Option>
OptionNames option_names();

// option_name(Boundary::EdgesAndCorners) is "edges-and-corners".
template <typename Option>
const char* option_name(Option value) {
    return option_names<Option>().names[int(value)];
}

// Sets `value` to the value `name` names and returns true; false, leaving `value` as it was, for any other text.
template <typename Option>
bool parse_option(std::string_view name, Option& value) {
    const OptionNames table = option_names<Option>();
    for (int i = 0; i < table.count; ++i) {
        if (name == table.names[i]) {
            value = Option(i);
            return true;
        }
    }
    return false;
}

// Per-corner values welded into shared ones, as a face-varying layer (FaceVaryingLayer) and an OBJ's vt and vn indices
// take them: the corners of a vertex whose values are equal (bit for bit, -0.0 and 0.0 alike) share one value, and
// where they differ each keeps its own (a seam). In the manner of meshoptimizer's vertex remap, in two steps:
//
// weld_corner_values writes each corner's value index into corner_value_indices (3 * num_triangles) and returns the
// number of values. triangles: 3 * num_triangles vertex indices in [0, num_vertices) (InputError otherwise, its
// problem VertexOutOfRange); corner_values: num_channels floats per corner, 3 * num_triangles * num_channels in all
// (a NaN welds with itself, bit for bit: diagnose_corner_values finds them first). Values are numbered vertex
// by vertex, and within a vertex in the order of their first corner: the numbers change only where corners join or
// leave a value, not when values move. Linear in the number of corners.
int weld_corner_values(std::int32_t* corner_value_indices, const std::int32_t* triangles, int num_triangles,
                       int num_vertices, const float* corner_values, int num_channels);
// gather_welded_values writes the values (num_channels floats for each of weld_corner_values' count): each is the
// value of its first corner.
void gather_welded_values(float* values, const std::int32_t* corner_value_indices, int num_triangles,
                          const float* corner_values, int num_channels);

// Memory for a front end's output arrays (the Python module's results), from the allocator of the plans' own arrays:
// from 16 KiB up in huge pages where the system has them, not zeroed, and kept for the next array when freed
// (docs/architecture.md, "pool, slab"). Aligned to 16 bytes at least; free it with its size (null is ignored).
// Throws std::bad_alloc.
void* allocate_array_memory(std::size_t bytes);
void free_array_memory(void* memory, std::size_t bytes) noexcept;

// A size as MemoryLimitError's messages give it: "467.00 MiB (489684798 bytes)", in GiB from 1 GiB.
std::string describe_bytes(std::uint64_t bytes);

// The seed's coefficient constants (docs/rules.md, "One level"), exposed so that tests can check the seed's worked
// example.
double loop_b(int valence);  // (3 + 2 cos(2 pi / n)) / 8
double loop_a(int valence);  // 5/8 - b(n)^2

}  // namespace loopsub
