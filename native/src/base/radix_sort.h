// Sorting by a non-negative 32-bit key a byte at a time (least significant first, stable), for the plan's lists of
// a few thousand to a million entries keyed by vertex or corner, where a sort by comparisons costs several times as
// much (docs/benchmark.md, "Measurements behind the code").
#pragma once

#include <cstddef>
#include <cstdint>

namespace loopsub::detail {

// Sorts `items` (a vector) by key(item), every key at most max_key: as many passes as max_key has bytes.
template <typename Items, typename Key>
void radix_sort(Items& items, std::uint32_t max_key, const Key& key) {
    Items sorted(items.size());
    for (int shift = 0; shift < 32 && max_key >> shift; shift += 8) {
        std::size_t count[257] = {};
        for (const auto& item : items) ++count[(std::uint32_t(key(item)) >> shift & 0xff) + 1];
        for (int b = 0; b < 256; ++b) count[b + 1] += count[b];
        for (const auto& item : items) sorted[count[std::uint32_t(key(item)) >> shift & 0xff]++] = item;
        items.swap(sorted);
    }
}

}  // namespace loopsub::detail
