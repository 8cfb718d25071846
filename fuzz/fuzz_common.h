// What every fuzz target checks once the core has accepted an input: it runs every per-frame call, and nothing it
// writes may be other than finite. Refusals (InputError, MemoryLimitError) are fine; anything else ends the run.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdlib>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::fuzz {

// The fuzzer's bytes, read field by field (zero once they run out).
class Bytes {
public:
    Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
    std::uint8_t byte() { return at_ < size_ ? data_[at_++] : 0; }
    float number() {  // raw bits: NaN, infinities and huge values too
        std::uint32_t bits = 0;
        for (int i = 0; i < 4; ++i) bits |= std::uint32_t(byte()) << (8 * i);
        float value;
        std::memcpy(&value, &bits, sizeof value);
        return value;
    }
    std::int32_t index(int count) { return std::int32_t(byte()) % (count + 2) - 1; }  // -1 .. count: some invalid

private:
    const std::uint8_t* data_;
    std::size_t size_, at_ = 0;
};

// Small enough that a fuzzer never waits on a big refinement; the refusal path is exercised instead.
inline constexpr std::uint64_t kMemoryLimit = std::uint64_t(64) << 20;

// The options the core's targets take from their first byte (bits 0 to 5: rules, boundary, crease method, kernel, two
// threads), under the fuzzers' memory limit.
inline Options options_from(std::uint8_t flags) {
    Options options;
    options.rules = flags & 1 ? Rules::OpenSubdiv : Rules::Hoppe94;
    options.boundary = flags & 2 ? Boundary::EdgesAndCorners : Boundary::EdgesOnly;
    options.crease_method = flags & 4 ? CreaseMethod::Chaikin : CreaseMethod::Uniform;
    options.kernel = Kernel((flags >> 3) % 4);
    options.threads = flags & 32 ? 2 : 1;
    options.memory_limit_bytes = kMemoryLimit;
    return options;
}

// A mesh's triangles and tags from the bytes, in this order: the triangles' indices, the crease edges and their
// sharpness, the corners and theirs, the cones (indices are bytes, so some fall outside the mesh).
inline void read_mesh(Bytes& in, MeshData& mesh, int vertices, int triangles, int creases, int corners, int cones) {
    for (int i = 0; i < 3 * triangles; ++i) mesh.triangles.push_back(in.index(vertices));
    for (int i = 0; i < creases; ++i) {
        mesh.crease_edges.insert(mesh.crease_edges.end(), {in.index(vertices), in.index(vertices)});
        mesh.crease_sharpness.push_back(in.number());
    }
    for (int i = 0; i < corners; ++i) {
        mesh.corner_vertices.push_back(in.index(vertices));
        mesh.corner_sharpness.push_back(in.number());
    }
    for (int i = 0; i < cones; ++i) mesh.cone_vertices.push_back(in.index(vertices));
}

inline void require_finite(const std::vector<float>& values) {
    for (float value : values)
        if (!std::isfinite(value)) std::abort();  // finite input must never give a non-finite output
}

// Evaluates the plan with the given positions (3 per vertex) and face-varying values (channels per corner).
// With the limit surface, the normals too; every face-varying layer with `layer_values` (2 channels per value,
// as many values as the layer has).
inline void exercise(Plan& plan, const std::vector<float>& positions, const std::vector<float>& corners,
                     int corner_channels, const std::vector<std::vector<float>>& layer_values = {}) {
    std::vector<float> out(std::size_t(plan.num_output_vertices()) * 3);
    try {
        if (plan.options().limit_surface) {
            std::vector<float> normals(std::size_t(plan.num_output_triangles()) * 9);
            plan.evaluate(interleaved(positions.data(), 3), interleaved(out.data(), 3), normals.data());
            require_finite(normals);
        } else {
            plan.evaluate(interleaved(positions.data(), 3), interleaved(out.data(), 3));
        }
        require_finite(out);
    } catch (const InputError&) {}
    for (int layer = 0; layer < plan.num_face_varying_layers() && layer < int(layer_values.size()); ++layer) {
        std::vector<float> refined(std::size_t(plan.num_output_face_varying_values(layer)) * 2);
        const std::int32_t* indices = plan.output_face_varying_indices(layer);
        for (int c = 0; c < 3 * plan.num_output_triangles(); ++c)
            if (indices[c] < 0 || indices[c] >= plan.num_output_face_varying_values(layer)) std::abort();
        try {
            plan.evaluate_face_varying(layer, interleaved(layer_values[layer].data(), 2),
                                       interleaved(refined.data(), 2));
            require_finite(refined);
        } catch (const InputError&) {}
    }
    if (corner_channels > 0) {
        std::vector<float> refined(std::size_t(plan.num_output_triangles()) * 3 * corner_channels);
        try {
            plan.evaluate_face_varying(corners.data(), refined.data(), corner_channels);
            require_finite(refined);
        } catch (const InputError&) {}
    }
}

}  // namespace loopsub::fuzz
