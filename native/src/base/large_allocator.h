// Allocator for the plan's big arrays (megabytes per level). Fresh memory costs a page fault per 4 KiB on first
// touch, which measured as more time than the topology work itself; asking the kernel for transparent huge
// pages (2 MiB) cuts those faults by 512x where the system allows it (Linux, THP "madvise" mode), and the kernel's
// time with them (docs/benchmark.md, "Fresh processes and first touches"). Huge pages also make a plan's speed
// steady: with 4 KiB pages the physical placement of the arrays the passes read side by side changes from process to
// process, and the plan's time with it. So arrays from 1 MiB up get whole huge pages, and middling ones (16 KiB up)
// runs of 64 KiB units in shared 2 MiB slabs of huge pages (Slabs): a first plan of a few thousand triangles had
// nearly all its faults in such arrays, each its own mapping of 4 KiB pages.
//
// Freed blocks of 1 MiB and up are kept for reuse, up to kPoolBytes (64 MiB) in all (BlockPool), and so are up to 16
// slabs left empty (Slabs): a plan built again (the modifier after an edit that changes the topology, a benchmark loop)
// then finds its arrays already faulted in, instead of paying the kernel again to map and zero them, which is most of
// what a fresh plan's memory costs. The budget bounds what stays mapped once plans are gone, and what a large
// refinement holds on top of its own arrays.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <memory>
#include <mutex>
#include <new>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#elif defined(_WIN32)
#include <malloc.h>
#endif

namespace loopsub::detail {

// Large blocks by size, oldest first; shared by every plan of the process, and never destroyed, so that plans freed
// during static destruction still find it (the blocks it holds at exit stay reachable).
class BlockPool {
public:
    static constexpr std::size_t kPoolBytes = std::size_t(64) << 20;

    static BlockPool& instance() {
        static BlockPool* pool = new BlockPool;
        return *pool;
    }
    // A block of exactly `bytes`, or null.
    void* take(std::size_t bytes) {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto it = blocks_.begin(); it != blocks_.end(); ++it) {
            if (it->first != bytes) continue;
            void* block = it->second;
            held_ -= bytes;
            blocks_.erase(it);
            return block;
        }
        return nullptr;
    }
    // Keeps the block, freeing the oldest ones past the budget; false when the block alone is past it.
    template <typename Free>
    bool keep(void* block, std::size_t bytes, Free free_block) {
        if (bytes > kPoolBytes) return false;
        std::vector<std::pair<std::size_t, void*>> evicted;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            while (held_ + bytes > kPoolBytes) {
                evicted.push_back(blocks_.front());
                held_ -= blocks_.front().first;
                blocks_.pop_front();
            }
            blocks_.emplace_back(bytes, block);
            held_ += bytes;
        }
        for (const auto& [size, old] : evicted) free_block(old, size);
        return true;
    }

    // Gives every kept block back (a plan far bigger than the budget is done building: its dead levels would
    // otherwise sit in the pool beside its output, for little reuse).
    template <typename Free>
    void release_all(Free free_block) {
        std::deque<std::pair<std::size_t, void*>> released;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            released.swap(blocks_);
            held_ = 0;
        }
        for (const auto& [size, block] : released) free_block(block, size);
    }

private:
    std::mutex mutex_;
    std::deque<std::pair<std::size_t, void*>> blocks_;
    std::size_t held_ = 0;
};

constexpr std::size_t kHugePage = std::size_t(2) << 20;

// A block of `bytes` (a whole number of huge pages, or one slab) aligned to `alignment`, from the system: huge pages
// asked for where it has them. Given back by free_block.
inline void* fresh_block(std::size_t bytes, std::size_t alignment) {
#if defined(_WIN32)
    void* block = _aligned_malloc(bytes, alignment);  // Windows has no aligned_alloc
#else
    void* block = std::aligned_alloc(alignment, bytes);
#endif
    if (!block) throw std::bad_alloc();
#if defined(__linux__)
    if (bytes >= kHugePage) madvise(block, bytes, MADV_HUGEPAGE);  // advisory: else it is ordinary memory
#endif
    return block;
}

inline void free_block(void* block, std::size_t) noexcept {
#if defined(_WIN32)
    _aligned_free(block);  // every block came from _aligned_malloc
#else
    std::free(block);
#endif
}

// Middling blocks: runs of 64 KiB units in 2 MiB slabs, first fit. A freed run is free for any size at once; up to
// kKeptEmpty slabs left empty (32 MiB) are kept for the next plan, more are given back. They are kept apart from the
// pool: handed through it as 2 MiB blocks, warm frames in Python turned bimodal (evaluate_face_varying of a level-4
// icosphere 3.3 or 21 ms, runs of each; docs/benchmark.md, "Fresh processes and first touches").
class Slabs {
public:
    static constexpr std::size_t kUnit = std::size_t(64) << 10;
    static constexpr std::size_t kSlab = kHugePage;
    static constexpr unsigned kUnits = unsigned(kSlab / kUnit);  // 32: a slab's units are the bits of a word
    static constexpr std::size_t kKeptEmpty = 16;

    static Slabs& instance() {  // never destroyed, as the pool
        static Slabs* slabs = new Slabs;
        return *slabs;
    }

    // `units` (1 to kUnits) consecutive units, aligned to kUnit.
    void* take(unsigned units) {
        const std::uint32_t run = run_of(units);
        std::lock_guard<std::mutex> lock(mutex_);
        for (Slab& slab : slabs_) {
            for (unsigned first = 0; first + units <= kUnits; ++first) {
                if (slab.used & (run << first)) continue;
                slab.used |= run << first;
                return slab.base + first * kUnit;
            }
        }
        slabs_.reserve(slabs_.size() + 1);  // before a slab is taken, so that nothing is lost if it throws
        char* base = nullptr;
        if (!empty_.empty()) {
            base = empty_.back();
            empty_.pop_back();
        } else {
            base = static_cast<char*>(fresh_block(kSlab, kSlab));
        }
        slabs_.push_back({base, run});
        return base;
    }

    void give(void* block, unsigned units) noexcept {
        const std::uint32_t run = run_of(units);
        char* base = reinterpret_cast<char*>(reinterpret_cast<std::uintptr_t>(block) & ~std::uintptr_t(kSlab - 1));
        char* released = nullptr;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            for (std::size_t k = 0; k < slabs_.size(); ++k) {
                if (slabs_[k].base != base) continue;
                slabs_[k].used &= ~(run << unsigned((static_cast<char*>(block) - base) / kUnit));
                if (slabs_[k].used == 0) {
                    slabs_[k] = slabs_.back();
                    slabs_.pop_back();
                    if (empty_.size() < kKeptEmpty) empty_.push_back(base);  // capacity reserved: no throw
                    else released = base;
                }
                break;
            }
        }
        if (released) free_block(released, kSlab);
    }

private:
    struct Slab {
        char* base;
        std::uint32_t used;  // bit k: unit k is part of a block
    };
    Slabs() { empty_.reserve(kKeptEmpty); }
    // The bits of `units` units from unit 0.
    static std::uint32_t run_of(unsigned units) {
        return units >= kUnits ? ~std::uint32_t(0) : (std::uint32_t(1) << units) - 1;
    }

    std::mutex mutex_;
    std::vector<Slab> slabs_;
    std::vector<char*> empty_;  // slabs of no block, kept for the next plan
};

// Under AddressSanitizer each middling block is an allocation of its own, whose end the sanitizer watches: in a slab,
// an overrun would land in the next block unseen.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSlabs = false;
#else
constexpr bool kSlabs = true;
#endif

template <typename T>
struct LargeAllocator {
    using value_type = T;
    static constexpr std::size_t kHugePage = detail::kHugePage;
    static constexpr std::size_t kPooled = Slabs::kUnit;  // the unit of middling blocks
    // Smaller arrays are malloc's business. Not from 64 KiB: a base level's arrays of a few thousand triangles
    // (just under 64 KiB each) came from the top of malloc's heap, which it gives back to the system when they are
    // freed, and were faulted in again by the next plan.
    static constexpr std::size_t kPooledFrom = std::size_t(16) << 10;
    static constexpr std::size_t kLargeFrom = kHugePage / 2;
    static bool middling(std::size_t bytes) { return bytes >= kPooledFrom && bytes < kLargeFrom; }

    // Large blocks (kLargeFrom up) are whole huge pages; middling ones whole multiples of 64 KiB.
    static std::size_t block_size(std::size_t bytes) {
        const std::size_t unit = bytes >= kLargeFrom ? kHugePage : kPooled;
        return (bytes + unit - 1) / unit * unit;
    }
    static std::size_t block_alignment(std::size_t rounded) { return rounded >= kHugePage ? kHugePage : kPooled; }

    // Arrays do not start at their block's start but a different number of cache lines past it, one of 64 in turn,
    // where the block has that much room to spare (almost always: the last huge page or 64 KiB is rarely full):
    // arrays read and written side by side (a level's edge ends and wings) then do not start at the same offset
    // within 64 KiB, a placement measured to make a pass over them several times slower (docs/benchmark.md).
    static constexpr std::size_t kColourRoom = 4096;
    static std::size_t next_colour() {
        static std::atomic<unsigned> counter{0};
        return std::size_t(counter.fetch_add(1, std::memory_order_relaxed) % 64) * 64;
    }

    LargeAllocator() = default;
    template <typename U>
    LargeAllocator(const LargeAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
        if (bytes < kPooledFrom) {
            if (void* p = std::malloc(bytes ? bytes : 1)) return static_cast<T*>(p);
            throw std::bad_alloc();
        }
        const std::size_t rounded = block_size(bytes);
        char* block = static_cast<char*>(take_block(rounded));
        return reinterpret_cast<T*>(block + (rounded - bytes >= kColourRoom ? next_colour() : 0));
    }
    void deallocate(T* p, std::size_t n) noexcept {
        const std::size_t bytes = n * sizeof(T);
        if (bytes < kPooledFrom) return std::free(p);
        const std::size_t rounded = block_size(bytes);
        // The block starts at the alignment below the array (its colour is less than that).
        give_block(reinterpret_cast<void*>(reinterpret_cast<std::uintptr_t>(p) &
                                           ~std::uintptr_t(block_alignment(rounded) - 1)),
                   rounded);
    }

    // A block of block_size() bytes: a run in a slab, or whole huge pages (from the pool where it has them).
    static void* take_block(std::size_t rounded) {
        if (rounded < kHugePage)
            return kSlabs ? Slabs::instance().take(unsigned(rounded / kPooled)) : fresh_block(rounded, kPooled);
        if (void* block = BlockPool::instance().take(rounded)) return block;
        return fresh_block(rounded, kHugePage);
    }
    static void give_block(void* block, std::size_t rounded) noexcept {
        if (rounded < kHugePage)
            return kSlabs ? Slabs::instance().give(block, unsigned(rounded / kPooled)) : free_block(block, rounded);
        try {
            if (BlockPool::instance().keep(block, rounded, free_block)) return;
        } catch (...) {  // no memory left to remember the block: give it back
        }
        free_block(block, rounded);
    }

    // resize(n) leaves new elements uninitialised: every array here is filled right after it is sized, so
    // zeroing it first would only cost a pass over memory. Explicit values (assign(n, 0)) still apply.
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        if constexpr (sizeof...(Args) == 0) ::new (static_cast<void*>(p)) U;
        else ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }

    template <typename U>
    bool operator==(const LargeAllocator<U>&) const noexcept {
        return true;
    }
    template <typename U>
    bool operator!=(const LargeAllocator<U>&) const noexcept {
        return false;
    }
};

template <typename T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

// The builder's arrays that live a level or two and are written in parts, sized uninitialised as LargeVector's:
// middling ones in the slabs, large ones from malloc, which hands the same blocks back plan after plan, where the pool,
// whose budget the plan's tables fill, would give some of them fresh huge pages to clear. From malloc, the middling
// ones were faulted in anew by many plans (a plan with a UV layer at level 4: about 1,000 faults of 4 KiB every time).
template <typename T>
struct TransientAllocator : std::allocator<T> {
    template <typename U>
    struct rebind {
        using other = TransientAllocator<U>;
    };
    TransientAllocator() = default;
    template <typename U>
    TransientAllocator(const TransientAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        return LargeAllocator<T>::middling(n * sizeof(T)) ? LargeAllocator<T>().allocate(n)
                                                          : std::allocator<T>::allocate(n);
    }
    void deallocate(T* p, std::size_t n) noexcept {
        if (LargeAllocator<T>::middling(n * sizeof(T))) return LargeAllocator<T>().deallocate(p, n);
        std::allocator<T>::deallocate(p, n);
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        if constexpr (sizeof...(Args) == 0) ::new (static_cast<void*>(p)) U;
        else ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

template <typename T>
using TransientVector = std::vector<T, TransientAllocator<T>>;

}  // namespace loopsub::detail
