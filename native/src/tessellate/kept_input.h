// What a tessellation's build reads of the input mesh alone, whatever the rates (KeptInput), kept for the next cut of
// the same mesh (InputTopology's parts).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "loopsub/tessellation.h"
#include "tessellate/level_patches.h"
#include "topology/tessellation_pattern.h"

namespace loopsub {

// What a build reads of the input mesh alone, whatever the rates: the limit plan of no levels (it checks the mesh and
// the options, classifies the input's vertices and, as with any plan, decides which triangles have no limit surface:
// hole tags, and under Boundary::None the faces at an untagged boundary edge's ends), the input triangles that are
// regular patches, the edges. Kept (InputTopology) for one of the same mesh at other rates, which takes it where the
// triangles, tags and rules are the same. Read only once made: tessellations on other threads may share it.
struct KeptInput {
    KeptInput(const MeshView& mesh, const Options& options)
        : mesh_(copy_of(mesh)),
          rules_(options.rules),
          boundary_(options.boundary),
          crease_method_(options.crease_method),
          crease_threshold_(options.crease_threshold) {
        Options input = options;
        input.limit_surface = true, input.levels = 0;
        plan = std::make_unique<Plan>(mesh, input);
        // The plan's output leaves out the triangles without a surface; the patches read every triangle, which all
        // shape the surface.
        patches = std::make_unique<detail::LevelPatches>(*plan, mesh_.triangles.data(), mesh.num_triangles);
        if (plan->num_output_triangles() < mesh.num_triangles) {
            has_surface.assign(std::size_t(mesh.num_triangles), 0);
            const std::int32_t* parents = plan->output_parent_triangles();
            for (int t = 0; t < plan->num_output_triangles(); ++t) has_surface[std::size_t(parents[t])] = 1;
            for (int f = 0; f < mesh.num_triangles; ++f)
                if (!has_surface[std::size_t(f)]) holes.push_back(f);
        }
        face_patch.assign(std::size_t(mesh.num_triangles), -1);
        for (int f = 0; f < mesh.num_triangles; ++f) {  // every face asked now, so that nothing is ordered later
            detail::Patch patch;
            if (!surface(f) || !patches->find_patch(f, patch)) continue;
            face_patch[std::size_t(f)] = std::int32_t(patch_list.size());
            patch_list.push_back(patch);
        }
        edges = detail::sorted_edges(mesh.triangles, mesh.num_triangles);
    }

    // Whether this was made for the same triangles, tags and rules.
    bool made_for(const MeshView& mesh, const Options& options) const {
        auto same = [](const auto& kept, const auto* given, int count) {
            return kept.size() == std::size_t(count) && std::equal(kept.begin(), kept.end(), given);
        };
        return mesh.num_vertices == mesh_.num_vertices &&
               same(mesh_.triangles, mesh.triangles, 3 * mesh.num_triangles) &&
               same(mesh_.crease_edges, mesh.crease_edges, 2 * mesh.num_crease_edges) &&
               same(mesh_.crease_sharpness, mesh.crease_sharpness, mesh.num_crease_edges) &&
               same(mesh_.corner_vertices, mesh.corner_vertices, mesh.num_corners) &&
               same(mesh_.corner_sharpness, mesh.corner_sharpness, mesh.num_corners) &&
               same(mesh_.cone_vertices, mesh.cone_vertices, mesh.num_cones) &&
               same(mesh_.hole_triangles, mesh.hole_triangles, mesh.num_holes) && options.rules == rules_ &&
               options.boundary == boundary_ && options.crease_method == crease_method_ &&
               options.crease_threshold == crease_threshold_;
    }

    int find_edge(std::int32_t a, std::int32_t b) const {
        const auto at = std::lower_bound(edges.keys.begin(), edges.keys.end(), detail::edge_key(a, b));
        return at != edges.keys.end() && *at == detail::edge_key(a, b) ? int(at - edges.keys.begin()) : -1;
    }

    // Whether input triangle f has a limit surface (the plan wrote it).
    bool surface(int f) const { return has_surface.empty() || has_surface[std::size_t(f)]; }
    bool surface_everywhere() const { return has_surface.empty(); }

    std::unique_ptr<Plan> plan;
    std::unique_ptr<detail::LevelPatches> patches;
    std::vector<std::uint8_t> has_surface;  // per input triangle; empty where every one has
    std::vector<std::int32_t> holes;        // the input triangles without a surface, in order
    std::vector<std::int32_t> face_patch;   // per input triangle, its patch in patch_list, or -1
    std::vector<detail::Patch> patch_list;
    detail::SortedEdges edges;

private:
    struct Kept {  // the mesh's triangles and tags
        int num_vertices = 0;
        std::vector<std::int32_t> triangles, crease_edges, corner_vertices, cone_vertices, hole_triangles;
        std::vector<float> crease_sharpness, corner_sharpness;
    };
    static Kept copy_of(const MeshView& mesh) {
        Kept kept;
        kept.num_vertices = mesh.num_vertices;
        auto copy = [](auto& to, const auto* from, int count) {
            if (count > 0) to.assign(from, from + count);
        };
        copy(kept.triangles, mesh.triangles, 3 * mesh.num_triangles);
        copy(kept.crease_edges, mesh.crease_edges, 2 * mesh.num_crease_edges);
        copy(kept.crease_sharpness, mesh.crease_sharpness, mesh.num_crease_edges);
        copy(kept.corner_vertices, mesh.corner_vertices, mesh.num_corners);
        copy(kept.corner_sharpness, mesh.corner_sharpness, mesh.num_corners);
        copy(kept.cone_vertices, mesh.cone_vertices, mesh.num_cones);
        copy(kept.hole_triangles, mesh.hole_triangles, mesh.num_holes);
        return kept;
    }
    Kept mesh_;
    Rules rules_;
    Boundary boundary_;
    CreaseMethod crease_method_;
    float crease_threshold_;
};

struct InputTopologyParts {
    std::shared_ptr<const KeptInput> surface;
    std::vector<InputTopology> layers;  // each face-varying layer's cut's
};

}  // namespace loopsub
