// Checks of what a caller hands the core: the mesh and tags (once, when a plan is built) and the values evaluated
// every frame. Each failure is an InputError that says what and where.
#pragma once

#include <cstddef>

#include "loopsub/loopsub.h"

namespace loopsub::detail {

void validate_options(const Options& options);  // levels, threads, crease threshold
void validate_mesh(const MeshView& mesh);

// Per-vertex values (or a face-varying layer's, element "face-varying value"): finite, and within +-largest (the
// bound that keeps a kernel's sums finite).
void validate_vertex_values(ChannelsView<const float> in, int num_vertices, float largest, int summed_terms,
                            const char* element = "vertex");

// Face-varying values: finite.
void validate_face_varying_values(const float* in, std::size_t num_triangles, int num_channels);

}  // namespace loopsub::detail
