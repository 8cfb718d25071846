// The core's one thread runner (run_levels) and the allocator the plan's arrays come from: what the kernels and the
// plan rely on when they split a level among threads and reuse memory from one plan to the next.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <atomic>
#include <chrono>
#include <functional>
#include <new>
#include <thread>

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

#include "base/large_allocator.h"
#include "loopsub/loopsub.h"
#include "mesh_gen.h"
#include "base/parallel.h"

namespace {

using loopsub::detail::LargeVector;
using loopsub::detail::run_levels;
using loopsub::detail::TeamScope;

// Every part of every level runs exactly once, with the part count asked for, whatever the thread count.
TEST(RunLevels, RunsEveryPartOfEveryLevelOnce) {
    for (int threads : {1, 2, 3, 8}) {
        const int levels = 7;
        std::vector<int> runs(std::size_t(levels * threads), 0);
        std::vector<int> parts_seen(runs.size(), 0);
        run_levels(threads, levels, [&](int level, int part, int parts) {
            ++runs[std::size_t(level * threads + part)];  // each slot has one writer
            parts_seen[std::size_t(level * threads + part)] = parts;
        });
        for (std::size_t k = 0; k < runs.size(); ++k) {
            EXPECT_EQ(runs[k], 1) << threads << " threads, level " << k / threads << ", part " << k % threads;
            EXPECT_EQ(parts_seen[k], threads);
        }
    }
}

// Cut into pieces taken in turn, every piece of every level runs exactly once, with the piece count (pieces per
// thread times threads; one thread runs each level whole), and each level sees every piece's writes of the level
// before.
TEST(RunLevels, RunsEveryPieceOfEveryLevelOnceInLevelOrder) {
    for (int threads : {1, 2, 3}) {
        const int levels = 20, per_thread = 4, pieces = threads > 1 ? per_thread * threads : 1;
        std::vector<int> runs(std::size_t(levels * pieces), 0), seen(runs.size(), 0);
        std::vector<std::int64_t> values(std::size_t(levels * pieces), 0);
        run_levels(
            threads, levels,
            [&](int level, int piece, int count) {
                const std::size_t at = std::size_t(level * count + piece);
                ++runs[at];
                seen[at] = count;
                std::int64_t below = 1;  // the sum of the level before, every piece of it
                if (level > 0)
                    for (int k = 0; k < count; ++k) below += values[std::size_t((level - 1) * count + k)];
                values[at] = below % 1000003;
            },
            per_thread);
        EXPECT_EQ(runs, std::vector<int>(runs.size(), 1)) << threads << " threads";
        EXPECT_EQ(seen, std::vector<int>(seen.size(), pieces)) << threads << " threads";
        std::int64_t expected = 1;
        for (int level = 1; level < levels; ++level) expected = (1 + pieces * expected) % 1000003;
        EXPECT_EQ(values[std::size_t((levels - 1) * pieces)], expected) << threads << " threads";
    }
}

// A piece held up (its thread descheduled) delays only itself: the other thread takes every piece left.
TEST(Team, AThreadHeldUpLeavesTheRemainingPiecesToTheOthers) {
    const TeamScope scope(2);
    std::vector<std::thread::id> ran_on(8);
    run_levels(
        2, 1,
        [&](int, int piece, int) {
            if (piece == 0) std::this_thread::sleep_for(std::chrono::milliseconds(200));
            ran_on[std::size_t(piece)] = std::this_thread::get_id();
        },
        4);
    for (int piece = 1; piece < 8; ++piece) EXPECT_NE(ran_on[std::size_t(piece)], ran_on[0]) << "piece " << piece;
}

// A throwing piece reaches the caller after every other piece has ended; the team serves the next run as before.
TEST(Team, AThrowingPieceReachesTheCallerAfterTheOthersEnd) {
    std::atomic<int> ended{0};
    EXPECT_THROW(run_levels(
                     2, 1,
                     [&](int, int piece, int) {
                         if (piece == 3) throw std::bad_alloc();
                         std::this_thread::sleep_for(std::chrono::milliseconds(2));
                         ++ended;
                     },
                     4),
                 std::bad_alloc);
    EXPECT_EQ(ended.load(), 7);
    std::vector<int> runs(8, 0);
    run_levels(
        2, 1, [&](int, int piece, int) { ++runs[std::size_t(piece)]; }, 4);
    EXPECT_EQ(runs, std::vector<int>(8, 1));
}

// Within a team's scope run_levels runs on the team's threads: every part of every level once, and the same worker
// thread for part 1 of every call (a thread of its own per call would count one call each).
TEST(Team, RunLevelsRunsEveryPartOnTheTeamsThreads) {
    for (int threads : {2, 3}) {
        const TeamScope scope(threads);
        ASSERT_NE(TeamScope::current(), nullptr);
        ASSERT_EQ(TeamScope::current()->parts(), threads);
        static thread_local int calls_on_this_thread = 0;
        const int calls = 10, levels = 3;
        std::vector<int> runs(std::size_t(calls * levels * threads), 0), part1_calls(calls, 0);
        for (int call = 0; call < calls; ++call) {
            run_levels(threads, levels, [&](int level, int part, int parts) {
                EXPECT_EQ(parts, threads);
                ++runs[std::size_t((call * levels + level) * threads + part)];
                if (part == 1 && level == 0) part1_calls[call] = ++calls_on_this_thread;
            });
        }
        for (int run : runs) EXPECT_EQ(run, 1);
        EXPECT_EQ(part1_calls.back() - part1_calls.front(), calls - 1) << threads << " threads";
    }
    EXPECT_EQ(TeamScope::current(), nullptr);
}

// Frames evaluated one after another (run_levels with no scope around it) run on the team the process keeps: part 1
// of every call runs on one thread, which no call started.
TEST(Team, CallsOutsideAScopeShareTheKeptTeam) {
    std::vector<std::thread::id> part1(20);
    for (std::thread::id& id : part1)
        run_levels(2, 2, [&](int level, int part, int) {
            if (part == 1 && level == 0) id = std::this_thread::get_id();
        });
    for (const std::thread::id& id : part1) EXPECT_EQ(id, part1.front());
    EXPECT_NE(part1.front(), std::this_thread::get_id());
    EXPECT_EQ(TeamScope::current(), nullptr);
}

// Two threads evaluating at once: one holds the kept team, the other runs on a team of its own; both get every
// part of every level exactly once.
TEST(Team, ConcurrentCallersEachRunEveryPart) {
    const int levels = 5, calls = 200;
    auto caller = [&](std::vector<int>& runs) {
        for (int call = 0; call < calls; ++call)
            run_levels(2, levels,
                       [&](int level, int part, int) { ++runs[std::size_t((call * levels + level) * 2 + part)]; });
    };
    std::vector<int> first(std::size_t(calls * levels * 2), 0), second(first.size(), 0);
    std::thread other(caller, std::ref(second));
    caller(first);
    other.join();
    EXPECT_EQ(first, std::vector<int>(first.size(), 1));
    EXPECT_EQ(second, std::vector<int>(second.size(), 1));
}

// A part that throws (memory running out on a worker) reaches the caller as the exception, after every other part has
// ended (they may read the caller's stack), and the team serves the next run as before.
TEST(Team, AThrowingPartReachesTheCallerAfterTheOthersEnd) {
    for (int thrower : {0, 1}) {
        std::atomic<int> ended{0};
        EXPECT_THROW(run_levels(2, 3,
                                [&](int level, int part, int) {
                                    if (level == 1 && part == thrower) throw std::bad_alloc();
                                    std::this_thread::sleep_for(std::chrono::milliseconds(part == thrower ? 0 : 5));
                                    ++ended;
                                }),
                     std::bad_alloc);
        EXPECT_EQ(ended.load(), 3) << "thrower " << thrower
                                   << ": level 0's two parts and level 1's other part, not level 2";
        std::vector<int> runs(2, 0);
        run_levels(2, 1, [&](int, int part, int) { ++runs[std::size_t(part)]; });
        EXPECT_EQ(runs, std::vector<int>(2, 1));
    }
}

#if defined(__linux__) && !defined(__SANITIZE_THREAD__)
// A child made by fork() (Python's multiprocessing on Linux) has none of its parent's threads: its runs must not wait
// for the parent's kept workers. The child exits 0 when every part ran; a hang fails the test at ctest's timeout. (Not
// under ThreadSanitizer, which refuses to start threads after a fork of a process that has threads.)
TEST(Team, AForkedChildRunsEveryPart) {
    run_levels(2, 1, [](int, int, int) {});  // the parent's kept team exists
    const pid_t child = fork();
    ASSERT_NE(child, -1);
    if (child == 0) {
        std::vector<int> runs(6, 0);
        run_levels(2, 3, [&](int level, int part, int) { ++runs[std::size_t(level * 2 + part)]; });
        _exit(runs == std::vector<int>(6, 1) ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
}
#endif

// run_levels from within a team's step (the caller's part) still runs every part of the inner run once, and the
// outer step completes: the inner one runs on the caller while the workers finish their own parts.
TEST(Team, RunLevelsInsideAStepRunsEveryPart) {
    const int threads = 2;
    const TeamScope scope(threads);
    std::vector<int> outer(threads, 0), inner(threads, 0);
    run_levels(threads, 1, [&](int, int part, int parts) {
        ++outer[part];
        if (part == 0)
            run_levels(threads, 1, [&](int, int inner_part, int inner_parts) {
                EXPECT_EQ(inner_parts, parts);
                ++inner[std::size_t(inner_part)];
            });
    });
    EXPECT_EQ(outer, std::vector<int>(threads, 1));
    EXPECT_EQ(inner, std::vector<int>(threads, 1));
}

// The barrier between a team's steps orders them as run_levels' own does.
TEST(Team, EachStepSeesThePreviousStepsWrites) {
    const int threads = 2, steps = 200;
    const TeamScope scope(threads);
    std::vector<std::int64_t> values(threads, 1);
    std::int64_t expected = 1;
    for (int step = 0; step < steps; ++step) {
        std::vector<std::int64_t> next(threads);
        run_levels(threads, 1,
                   [&](int, int part, int parts) { next[part] = values[part] + values[(part + 1) % parts]; });
        values.swap(next);
        expected *= 2;
        expected %= 1000003;
        for (std::int64_t& value : values) value %= 1000003;
        ASSERT_EQ(values, std::vector<std::int64_t>(threads, expected)) << "step " << step;
    }
}

// A level reads what every part wrote in the level before (as a refinement level reads its parent): the barrier
// between levels must order them. Each part adds its neighbour part's previous value; the same recurrence written
// out serially gives the expected values.
TEST(RunLevels, EachLevelSeesThePreviousLevelsWrites) {
    for (int threads : {2, 3, 8}) {
        const int levels = 40;
        std::vector<std::int64_t> buffers[2] = {std::vector<std::int64_t>(threads, 1),
                                                std::vector<std::int64_t>(threads, 1)};
        for (int round = 0; round < 50; ++round) {
            buffers[0].assign(threads, 1);
            buffers[1].assign(threads, 1);
            run_levels(threads, levels, [&](int level, int part, int parts) {
                const std::vector<std::int64_t>& before = buffers[(level + 1) % 2];
                buffers[level % 2][part] = before[part] + before[(part + 1) % parts] + level;
            });
            std::vector<std::int64_t> expected(threads, 1), next(threads);
            for (int level = 0; level < levels; ++level) {
                for (int part = 0; part < threads; ++part)
                    next[part] = expected[part] + expected[(part + 1) % threads] + level;
                expected.swap(next);
            }
            ASSERT_EQ(buffers[(levels - 1) % 2], expected) << threads << " threads, round " << round;
        }
    }
}

// Large arrays start a few cache lines into their blocks, a different number each time (so that arrays passed over
// side by side do not share their offset); freeing one must hand its whole block back to the pool, where the next
// array of the same size finds it.
TEST(LargeAllocator, ArraysStartAtDifferentOffsetsInPooledBlocks) {
    using Allocator = loopsub::detail::LargeAllocator<std::int32_t>;
    const std::size_t count = (std::size_t(3) << 20) / sizeof(std::int32_t);  // 3 MiB: two huge pages' block
    const std::uintptr_t block_mask = ~std::uintptr_t(Allocator::kHugePage - 1);
    loopsub::detail::BlockPool::instance().release_all(
        loopsub::detail::free_block);  // no block of this size from earlier tests
    std::uintptr_t block = 0, offset = 0;
    for (int round = 0; round < 200; ++round) {
        LargeVector<std::int32_t> array(count, round);
        EXPECT_EQ(array.back(), round);
        const std::uintptr_t start = reinterpret_cast<std::uintptr_t>(array.data());
        if (round > 0) {
            EXPECT_EQ(start & block_mask, block) << "round " << round << ": the freed block is reused";
            EXPECT_NE(start - block, offset) << "round " << round;
        }
        block = start & block_mask;
        offset = start - block;
        ASSERT_LT(offset, Allocator::kColourRoom) << "round " << round;
        EXPECT_EQ(offset % 64, 0u) << "round " << round << ": whole cache lines";
    }
}

// Middling arrays (16 KiB up to 1 MiB) are runs of 64 KiB units in shared 2 MiB slabs: two such arrays sit in one
// slab without overlapping, and a run freed is taken again at once by an array of another size.
TEST(LargeAllocator, MiddlingArraysShareSlabsAndReuseFreedRuns) {
    if (!loopsub::detail::kSlabs) GTEST_SKIP() << "no slabs under AddressSanitizer";
    const std::uintptr_t slab_mask = ~std::uintptr_t(loopsub::detail::Slabs::kSlab - 1);
    auto start = [](const LargeVector<std::int32_t>& a) { return reinterpret_cast<std::uintptr_t>(a.data()); };
    LargeVector<std::int32_t> a(100 << 8), b(100 << 8);  // 100 KiB each: two units
    a.back() = 1, b.back() = 2;
    EXPECT_EQ(start(a) & slab_mask, start(b) & slab_mask) << "one slab";
    EXPECT_TRUE(start(a) + 100 * 1024 <= start(b) || start(b) + 100 * 1024 <= start(a)) << "apart";
    const std::uintptr_t freed = start(a) & ~std::uintptr_t(loopsub::detail::Slabs::kUnit - 1);
    a = LargeVector<std::int32_t>();
    LargeVector<std::int32_t> c(40 << 8);  // 40 KiB: one unit, the first of a's two
    EXPECT_EQ(start(c) & ~std::uintptr_t(loopsub::detail::Slabs::kUnit - 1), freed);
    EXPECT_EQ(b.back(), 2);
}

#if defined(__linux__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
// Where the system gives transparent huge pages on request, a process's first plan faults its memory in a few huge
// pages at a time: the plan of a 5,120-triangle mesh at level 3 (some 6 MB, most of it in arrays under 1 MiB) took
// about 1,300 faults of 4 KiB before its middling arrays shared slabs of huge pages, each fault a trip into the
// kernel that cost more than the plan's own work. (In a process where earlier tests ran, fewer still.)
TEST(LargeAllocator, AFirstPlanFaultsInHugePages) {
    std::string mode;
    if (FILE* f = std::fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r")) {
        char text[128] = {};
        mode = std::fgets(text, sizeof text, f) ? text : "";
        std::fclose(f);
    }
    if (mode.find("[never]") != std::string::npos || mode.empty()) GTEST_SKIP() << "no transparent huge pages here";
    const loopsub::testing::TestMesh mesh = loopsub::testing::icosphere(4);
    loopsub::Options options;
    options.levels = 3;
    rusage before{}, after{};
    getrusage(RUSAGE_SELF, &before);
    { loopsub::Plan first(mesh.view(), options); }
    getrusage(RUSAGE_SELF, &after);
    EXPECT_LT(after.ru_minflt - before.ru_minflt, 200);
}
#endif

// A plan built again (the modifier after a topology edit, a benchmark loop) finds its memory already mapped: the
// second build of the same plan faults in (almost) no pages. The base level's arrays of a 5,120-triangle mesh are
// just under 64 KiB; from malloc, they went back to the system with each plan and were faulted in again, as were
// the vertex classes (a byte per output vertex): 95-140 pages where ctest runs the test in its own process. Not
// under AddressSanitizer or ThreadSanitizer, whose allocators keep freed memory aside.
#if defined(__linux__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
TEST(LargeAllocator, APlanBuiltAgainFaultsInNoNewPages) {
    const loopsub::testing::TestMesh mesh = loopsub::testing::icosphere(4);
    loopsub::Options options;
    options.levels = 3;
    auto minor_faults = [] {
        rusage usage{};
        getrusage(RUSAGE_SELF, &usage);
        return usage.ru_minflt;
    };
    { loopsub::Plan first(mesh.view(), options); }
    const long before = minor_faults();
    { loopsub::Plan again(mesh.view(), options); }
    // Its arrays span about 1,500 pages; malloc's own small blocks may take a few.
    EXPECT_LT(minor_faults() - before, 32);
}
#endif

// Face-varying layers planned and evaluated in parts: any thread count gives the same indices and values, bit for bit,
// as one thread (the OpenSubdiv comparisons check the values themselves). Levels large enough to be split, with seams,
// islands, semi-sharp creases and corners, three layers, every interpolation mode, with and without the limit; the
// last mesh's base level large enough that the layers' base steps are split too.
TEST(FaceVaryingThreads, AnyThreadCountEqualsOneBitForBit) {
    using namespace loopsub;
    namespace gen = loopsub::testing;
    using gen::TestMesh;
    TestMesh sphere = gen::icosphere(3);
    TestMesh sheet = gen::grid(40, 40);
    TestMesh big = gen::icosphere(5);
    for (TestMesh* mesh : {&sphere, &sheet, &big}) {
        gen::jitter(*mesh, 7, 0.01f);
        gen::add_random_creases(*mesh, 11, 0.04, true);
        gen::add_random_corners(*mesh, 13, 6, true);
        gen::add_uvs_with_seam(*mesh);
    }
    for (const TestMesh* mesh : {&sphere, &sheet, &big}) {
        // Layer 0: a seam; layer 1: none (a value per vertex); layer 2: islands, a triangle's own three values where
        // its first vertex has z > 0, shared per vertex elsewhere.
        const int n = mesh->num_vertices();
        std::vector<std::int32_t> islands(mesh->triangles.size());
        std::vector<float> island_values(2 * std::size_t(n));
        for (int v = 0; v < n; ++v)
            island_values[2 * v] = mesh->positions[3 * v + 2], island_values[2 * v + 1] = float(v % 7);
        for (std::size_t c = 0; c < islands.size(); ++c) {
            const bool own = mesh->positions[3 * mesh->triangles[c - c % 3] + 2] > 0.0f;
            islands[c] = own ? std::int32_t(island_values.size() / 2) : mesh->triangles[c];
            if (own) island_values.insert(island_values.end(), {0.1f * float(c % 5), float(c % 3)});
        }
        std::vector<float> vertex_values(2 * std::size_t(n));
        for (int v = 0; v < n; ++v)
            vertex_values[2 * v] = mesh->positions[3 * v], vertex_values[2 * v + 1] = mesh->positions[3 * v + 1];
        const FaceVaryingLayer layers[3] = {{mesh->triangle_uvs.data(), int(mesh->uvs.size() / 2)},
                                            {mesh->triangles.data(), n},
                                            {islands.data(), int(island_values.size() / 2)}};
        const std::vector<float>* values[3] = {&mesh->uvs, &vertex_values, &island_values};
        MeshView view = mesh->view();
        view.face_varying = layers;
        view.num_face_varying = 3;
        for (int m = 0; m <= int(FaceVaryingInterpolation::All); ++m) {
            for (bool limit : {false, true}) {
                Options options;
                options.rules = Rules::OpenSubdiv;
                options.levels = mesh == &big ? 1 : 3;
                options.face_varying = FaceVaryingInterpolation(m);
                options.limit_surface = limit;
                std::vector<std::vector<std::int32_t>> indices_one;
                std::vector<std::vector<float>> values_one;
                for (int threads : {1, 2, 3, 8}) {
                    SCOPED_TRACE(mesh->name + ", mode " + std::to_string(m) + (limit ? ", limit" : "") + ", threads " +
                                 std::to_string(threads));
                    options.threads = threads;
                    Plan plan(view, options);
                    ASSERT_EQ(plan.num_face_varying_layers(), 3);
                    for (int layer = 0; layer < 3; ++layer) {
                        const std::int32_t* corners = plan.output_face_varying_indices(layer);
                        std::vector<std::int32_t> indices(corners,
                                                          corners + 3 * std::size_t(plan.num_output_triangles()));
                        std::vector<float> out(2 * std::size_t(plan.num_output_face_varying_values(layer)));
                        plan.evaluate_face_varying(layer, interleaved(values[layer]->data(), 2),
                                                   interleaved(out.data(), 2));
                        if (threads == 1) {
                            indices_one.push_back(std::move(indices));
                            values_one.push_back(std::move(out));
                            continue;
                        }
                        EXPECT_EQ(indices, indices_one[std::size_t(layer)]) << "layer " << layer;
                        // Bit for bit: the same float, not merely close (memcmp, so that equal NaNs would count as
                        // equal).
                        ASSERT_EQ(out.size(), values_one[std::size_t(layer)].size()) << "layer " << layer;
                        EXPECT_EQ(
                            std::memcmp(out.data(), values_one[std::size_t(layer)].data(), out.size() * sizeof(float)),
                            0)
                            << "layer " << layer;
                    }
                }
            }
        }
    }
}

}  // namespace
