// Allocator for the plan's big arrays (megabytes per level). Fresh memory costs a page fault per 4 KiB on first
// touch, which measured as more time than the topology work itself; asking the kernel for transparent huge
// pages (2 MiB) on large blocks cuts those faults by 512x where the system allows it (Linux, THP "madvise" mode).
// Elsewhere large blocks are just aligned to 2 MiB.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#elif defined(_WIN32)
#include <malloc.h>
#endif

namespace loopsub::detail {

template <typename T>
struct LargeAllocator {
    using value_type = T;
    static constexpr std::size_t kHugePage = std::size_t(2) << 20;

    LargeAllocator() = default;
    template <typename U>
    LargeAllocator(const LargeAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
        if (bytes < kHugePage) {
            if (void* p = std::malloc(bytes ? bytes : 1)) return static_cast<T*>(p);
            throw std::bad_alloc();
        }
        const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
#if defined(_WIN32)
        void* p = _aligned_malloc(rounded, kHugePage);  // Windows has no aligned_alloc
#else
        void* p = std::aligned_alloc(kHugePage, rounded);
#endif
        if (!p) throw std::bad_alloc();
#if defined(__linux__)
        madvise(p, rounded, MADV_HUGEPAGE);  // advisory: without huge pages it is ordinary memory
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) noexcept {
#if defined(_WIN32)
        if (n * sizeof(T) >= kHugePage) return _aligned_free(p);
#else
        (void)n;
#endif
        std::free(p);
    }

    // resize(n) leaves new elements uninitialised: every array here is filled right after it is sized, so
    // zeroing it first would only cost a pass over memory. Explicit values (assign(n, 0)) still apply.
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        if constexpr (sizeof...(Args) == 0) ::new (static_cast<void*>(p)) U;
        else ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }

    template <typename U>
    bool operator==(const LargeAllocator<U>&) const noexcept { return true; }
    template <typename U>
    bool operator!=(const LargeAllocator<U>&) const noexcept { return false; }
};

template <typename T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

}  // namespace loopsub::detail
