// Per-frame evaluation kernels: one level of refinement of a range of vertex points and edge points.
// Each instruction set has its own file with the scalar twin as the reference (kernels_scalar.cpp).
#pragma once

#include <cstddef>

#include "loopsub/loopsub.h"
#include "tables/limit_tables.h"
#include "tables/stencils.h"

namespace loopsub::detail {

struct Range {
    int begin = 0;
    int end = 0;
};

// Computes, for every channel, output vertex points [vertices.begin, vertices.end) and output edge points
// num_vertices + [edges.begin, edges.end), special masks included, reading indices through `view` (which covers
// the ranges). Ranges of different calls may run on different threads at once: a call writes only its own outputs.
using RefineFn = void (*)(const LevelStencils& stencils, const StencilView& view, ChannelsView<const float> in,
                          ChannelsView<float> out, Range vertices, Range edges);

void refine_scalar(const LevelStencils&, const StencilView&, ChannelsView<const float>, ChannelsView<float>, Range,
                   Range);
void refine_sse41(const LevelStencils&, const StencilView&, ChannelsView<const float>, ChannelsView<float>, Range,
                  Range);
void refine_avx2(const LevelStencils&, const StencilView&, ChannelsView<const float>, ChannelsView<float>, Range,
                 Range);

// Computes, for every channel, the output edge points of the edges inside parent faces [faces.begin, faces.end) of a
// level whose interior edges are read from its parent's faces (LevelStencils::interior), three per face.
using InteriorFn = void (*)(const LevelStencils& stencils, ChannelsView<const float> in, ChannelsView<float> out,
                            Range faces);

void refine_interior_scalar(const LevelStencils&, ChannelsView<const float>, ChannelsView<float>, Range);
void refine_interior_sse41(const LevelStencils&, ChannelsView<const float>, ChannelsView<float>, Range);
void refine_interior_avx2(const LevelStencils&, ChannelsView<const float>, ChannelsView<float>, Range);

// Computes, for every channel, the output vertex points of the midpoints of parent edges [edges.begin, edges.end) and
// the output edge points of those edges' halves, special masks included, on a level with fans
// (LevelStencils::fan_midpoints). There a midpoint's ring is its edge's ends and then its halves' wings (a, b, c0, c1,
// d0, d1), so a midpoint of two faces and its two halves read the same seven points: three outputs from one fan of
// loads, the same bits as from the tables.
using FanFn = void (*)(const LevelStencils& stencils, ChannelsView<const float> in, ChannelsView<float> out,
                       Range parent_edges);

void refine_fans_scalar(const LevelStencils&, ChannelsView<const float>, ChannelsView<float>, Range);
void refine_fans_sse41(const LevelStencils&, ChannelsView<const float>, ChannelsView<float>, Range);
void refine_fans_avx2(const LevelStencils&, ChannelsView<const float>, ChannelsView<float>, Range);

// The limit stage of a frame (Options::limit_surface) over last-level vertices [vertices.begin, vertices.end) of the
// last level's points `in`: their limit points, every channel (the masks of LimitTables::positions, specials
// included), and, where `normals` is not null, from the first three channels their normals as rows of three at
// normals + 3 v (limit_normals.h: a vertex's own, or zero where its normals are its sides'). The rings are read
// through `view` (which covers the range). The SIMD kernels take the normals of smooth disk fans from the loads of
// their limit points (kernels_limit.h).
using LimitFn = void (*)(const LimitTables& tables, const StencilView& view, ChannelsView<const float> in,
                         ChannelsView<float> out, float* normals, Range vertices);

void limit_scalar(const LimitTables&, const StencilView&, ChannelsView<const float>, ChannelsView<float>, float*,
                  Range);
void limit_sse41(const LimitTables&, const StencilView&, ChannelsView<const float>, ChannelsView<float>, float*, Range);
void limit_avx2(const LimitTables&, const StencilView&, ChannelsView<const float>, ChannelsView<float>, float*, Range);

// A share of the last-level vertices made by the splits after the grandparent (LimitTables::from_grandparent), in the
// grandparent's elements: grandparent edges [edges) give their child's midpoints and the midpoints of both their
// halves, grandparent faces [faces) the midpoints of their interior edges.
struct GrandchildShare {
    Range edges, faces;

    // The same share as last-level vertices, a range per kind: the child's midpoints, the halves', the faces'.
    void vertices(const Grandparent& g, Range out[3]) const {
        const Index child_vertices = g.num_vertices + g.num_edges, halves_end = child_vertices + 2 * g.num_edges;
        out[0] = {g.num_vertices + edges.begin, g.num_vertices + edges.end};
        out[1] = {child_vertices + 2 * edges.begin, child_vertices + 2 * edges.end};
        out[2] = {halves_end + 3 * faces.begin, halves_end + 3 * faces.end};
    }
};

// Runs `limit` over last-level vertices [vertices.begin, vertices.end), all made by the splits after the grandparent,
// a chunk at a time, each chunk's rings written just before (write_ordered_grandchild_rings).
void limit_over_grandchild_rings(LimitFn limit, const LimitTables& tables, ChannelsView<const float> in,
                                 ChannelsView<float> out, float* normals, Range vertices);

// The limit stage over such a share: what LimitFn writes for those vertices, from the rings the grandparent's
// numbering gives. The scalar kernel writes the rings a chunk at a time and runs limit_scalar over them (the
// reference); the SIMD kernels load each ring's points once for the vertices that share them (kernels_limit.h).
using GrandchildLimitFn = void (*)(const LimitTables& tables, ChannelsView<const float> in, ChannelsView<float> out,
                                   float* normals, GrandchildShare share);

void limit_grandchild_scalar(const LimitTables&, ChannelsView<const float>, ChannelsView<float>, float*,
                             GrandchildShare);
void limit_grandchild_sse41(const LimitTables&, ChannelsView<const float>, ChannelsView<float>, float*,
                            GrandchildShare);
void limit_grandchild_avx2(const LimitTables&, ChannelsView<const float>, ChannelsView<float>, float*, GrandchildShare);

// One regular patch of a tessellation evaluated at a block of points: the box spline of its 12 points (xyz and a
// fourth float, rules/box_spline.h's order; a phantom is zero with zero weights) at each sample, with weights for kind
// k (position, derivative along s, along t), point i and sample s at weights[(12 k + i) stride + s], stride a multiple
// of 8 with the samples past `count` weighted zero. Writes each sample's position and unit normal (t_s x t_t; zero
// where the derivatives span no plane), three floats each, at positions + 3 s and normals + 3 s.
inline constexpr int kPatchPoints = 12;
using PatchFn = void (*)(const float points[kPatchPoints][4], const float* weights, int count, int stride,
                         float* positions, float* normals);

void patch_scalar(const float[kPatchPoints][4], const float*, int, int, float*, float*);
void patch_sse41(const float[kPatchPoints][4], const float*, int, int, float*, float*);
void patch_avx2(const float[kPatchPoints][4], const float*, int, int, float*, float*);

// One instruction set's kernels.
struct Kernels {
    RefineFn refine;
    InteriorFn interior;
    FanFn fans;
    LimitFn limit;
    GrandchildLimitFn limit_grandchild;
    PatchFn patch;
};

// Runs the kernels over part `part` of `parts` of a level: a stored level in one call (one whose interior edges come
// from its parent's faces by kind: old vertices, midpoints with their halves, interior edges), a derived one
// (LevelStencils::derived_from) a chunk at a time, each chunk's tables filled from the parent just before. The parts
// together write every output once.
void refine_part(const Kernels& kernels, const LevelStencils& stencils, ChannelsView<const float> in,
                 ChannelsView<float> out, int part, int parts);

// Runs the limit kernels over part `part` of `parts` of the last level: through the stored rings, or, where the limit
// tables come from the grandparent (LimitTables::from_grandparent), its own vertices so and the others by kind
// (GrandchildLimitFn), each kind shared on its own. The parts together write every output once.
void limit_part(const Kernels& kernels, const LimitTables& tables, ChannelsView<const float> in,
                ChannelsView<float> out, float* normals, int part, int parts);

// The kernels for a kernel choice; Auto resolves to the widest one the CPU runs (see resolve_kernel).
Kernel resolve_kernel(Kernel requested);
Kernels kernel_functions(Kernel resolved);

}  // namespace loopsub::detail
