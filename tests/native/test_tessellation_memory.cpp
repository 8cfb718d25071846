// What a tessellation holds against what its memory check counted, where local refinement does the work: a "book" of
// triangles on one edge (fins, cards glued along an edge), whose non-manifold edge leaves every triangle irregular.
// Each triangle's neighbourhood once took all the pages, so that 100 pages at rate 3 held 17 GB that the check never
// counted. Measured in a child process (the peak of its resident memory, reset before the tessellation), whose address
// space is capped (cap_address_space).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "loopsub/tessellation.h"

namespace loopsub::testing {
namespace {

constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;

// Under AddressSanitizer the shadow memory needs the address space a cap would take away, and the sanitizer's own
// allocations make the resident peak no measure of the core's: there the children run uncapped, with more time, and
// check the count alone.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

// The child's address space capped at 2 GiB, so that a run that goes astray ends there, not on the machine.
void cap_address_space() {
    if (kSanitized) return;
    const rlimit cap{2048 * kMiB, 2048 * kMiB};
    setrlimit(RLIMIT_AS, &cap);
}

// P triangles on the edge between vertices 0 and 1, each with a third vertex of its own; with tags, on the spine and
// at its vertices, and on the pages' edges.
struct Book {
    std::vector<float> positions;
    std::vector<std::int32_t> triangles, creases, corners;
    std::vector<float> crease_sharpness, corner_sharpness;
    explicit Book(int pages) {
        positions = {0, 0, 0, 0, 0, 1};
        for (int k = 0; k < pages; ++k) {
            const double angle = 2.0 * M_PI * k / pages;
            positions.insert(positions.end(), {float(std::cos(angle)), float(std::sin(angle)), 0.5f});
            triangles.insert(triangles.end(), {0, 1, 2 + k});
        }
    }
    Book& crease(std::int32_t a, std::int32_t b, float sharpness) {
        creases.insert(creases.end(), {a, b}), crease_sharpness.push_back(sharpness);
        return *this;
    }
    Book& corner(std::int32_t v, float sharpness) {
        corners.push_back(v), corner_sharpness.push_back(sharpness);
        return *this;
    }
    MeshView view() const {
        MeshView mesh;
        mesh.num_vertices = int(positions.size() / 3);
        mesh.triangles = triangles.data(), mesh.num_triangles = int(triangles.size() / 3);
        mesh.crease_edges = creases.data(), mesh.crease_sharpness = crease_sharpness.data();
        mesh.num_crease_edges = int(crease_sharpness.size());
        mesh.corner_vertices = corners.data(), mesh.corner_sharpness = corner_sharpness.data();
        mesh.num_corners = int(corner_sharpness.size());
        return mesh;
    }
};

// A field of /proc/self/status in bytes (VmRSS, VmHWM).
std::uint64_t status_bytes(const std::string& field) {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind(field + ":", 0) == 0) return std::strtoull(line.c_str() + field.size() + 1, nullptr, 10) * 1024;
    return 0;
}

// In a child capped in address space and at kMostSeconds of time (SIGALRM ends it): tessellates the book at the
// rate, and exits 0 where its estimate covers the growth of its resident peak and stays under kMostEstimate, else
// prints both and exits 1 (3 where it could not measure).
constexpr std::uint64_t kMostEstimate = 300 * kMiB;
constexpr unsigned kMostSeconds = 20;
[[noreturn]] void measure_in_child(int pages, int rate, Rules rules = Rules::OpenSubdiv, const Book* tagged = nullptr) {
    cap_address_space();
    alarm(kSanitized ? 10 * kMostSeconds : kMostSeconds);
    const Book untagged(pages);
    const Book& book = tagged ? *tagged : untagged;
    Options options;
    options.rules = rules;
    TessellationRates rates;
    rates.uniform_rate = rate;
    std::ofstream("/proc/self/clear_refs") << "5";  // the peak resident size starts again from the current
    const std::uint64_t before = status_bytes("VmRSS");
    if (before == 0 || status_bytes("VmHWM") > before + kMiB) std::_Exit(3);
    try {
        const Tessellation tessellation(book.view(), options, rates);
        std::vector<float> points(3 * std::size_t(tessellation.num_points()));
        tessellation.evaluate(book.positions.data(), points.data(), nullptr);
        const std::uint64_t grown = status_bytes("VmHWM") - before, estimate = tessellation.estimated_bytes();
        std::fprintf(stderr, "%d pages at rate %d (%s): resident peak grew %.1f MiB, estimated %.1f MiB\n", pages, rate,
                     option_name(rules), double(grown) / kMiB, double(estimate) / kMiB);
        std::_Exit((kSanitized || estimate >= grown) && estimate <= kMostEstimate ? 0 : 1);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "%d pages at rate %d: %s\n", pages, rate, error.what());
        std::_Exit(1);
    }
}

TEST(TessellationMemory, ABookOfAHundredPagesIsCountedAndSmallAtEveryRate) {
    if (std::ifstream("/proc/self/clear_refs").fail()) GTEST_SKIP() << "no /proc/self/clear_refs to reset the peak";
    for (int rate : kSanitized ? std::vector<int>{3} : std::vector<int>{3, 5, 6, 7})  // the sanitizer's is slow
        EXPECT_EXIT(measure_in_child(100, rate), ::testing::ExitedWithCode(0), "") << "rate " << rate;
}

// A tag on the spine, or at its vertices, changes none of what their rules read (a non-manifold edge is infinitely
// sharp whatever its tag; a vertex of three fins a corner whatever its own): each triangle still refines its own fans,
// not the hundred pages (a tag of 10 on the spine took 204 MB and 87 s at rate 3, 251 s at rate 7; within the
// child's time, then, or it ends there).
TEST(TessellationMemory, ABookWithATaggedSpineIsCountedAndSmall) {
    if (std::ifstream("/proc/self/clear_refs").fail()) GTEST_SKIP() << "no /proc/self/clear_refs to reset the peak";
    Book book(100);
    book.crease(0, 1, kInfiniteSharpness);
    for (Rules rules : {Rules::OpenSubdiv, Rules::Hoppe94})
        for (int rate : kSanitized ? std::vector<int>{3} : std::vector<int>{3, 7})
            EXPECT_EXIT(measure_in_child(100, rate, rules, &book), ::testing::ExitedWithCode(0), "")
                << option_name(rules) << " rate " << rate;
    // Semi-sharp, on the spine and at its vertex, and on a page's edges (boundary edges, infinitely sharp).
    Book semi(100);
    semi.crease(0, 1, 2.5f).corner(0, 2.5f).corner(1, kInfiniteSharpness).crease(0, 2, 2.5f).crease(1, 3, 1.0f);
    for (Rules rules : {Rules::OpenSubdiv, Rules::Hoppe94})
        EXPECT_EXIT(measure_in_child(100, 3, rules, &semi), ::testing::ExitedWithCode(0), "") << option_name(rules);
}

// Past the limit, the local refinement is refused before it allocates, with the bytes it would need in all (in a capped
// child as above).
[[noreturn]] void refuse_in_child() {
    cap_address_space();
    const Book book(100);
    Options options;
    options.rules = Rules::OpenSubdiv;
    TessellationRates rates;
    rates.uniform_rate = 3;
    try {
        const std::uint64_t counted = Tessellation(book.view(), options, rates).estimated_bytes();
        options.memory_limit_bytes = counted;
        if (Tessellation(book.view(), options, rates).estimated_bytes() != counted) std::_Exit(1);
        options.memory_limit_bytes = counted - 1;
        try {
            Tessellation(book.view(), options, rates);
            std::fprintf(stderr, "made within a limit one byte below its count\n");
        } catch (const MemoryLimitError& error) {
            std::fprintf(stderr, "%s\n", error.what());
            std::_Exit(error.required_bytes == counted ? 0 : 1);
        }
    } catch (const std::exception& error) { std::fprintf(stderr, "%s\n", error.what()); }
    std::_Exit(1);
}

TEST(TessellationMemory, ALimitBelowTheRefinementRefusesIt) {
    EXPECT_EXIT(refuse_in_child(), ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace loopsub::testing
