// A front end's output arrays in the plans' allocator (base/large_allocator.h).
#include <cstddef>

#include "base/large_allocator.h"
#include "loopsub/loopsub.h"

namespace loopsub {

void* allocate_array_memory(std::size_t bytes) { return detail::LargeAllocator<char>().allocate(bytes); }

void free_array_memory(void* memory, std::size_t bytes) noexcept {
    if (memory) detail::LargeAllocator<char>().deallocate(static_cast<char*>(memory), bytes);
}

}  // namespace loopsub
