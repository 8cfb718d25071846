// The one place threads are made: a run over the levels of a plan, each level split into parts.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace loopsub::detail {

// Runs work(level, part, parts) for every level in order and every part of a level at once: one thread per part
// for the whole run (the caller being part 0), meeting at a barrier between levels. A thread the system refuses
// to start costs parallelism, never the process: the parts are then shared among the threads that run.
// Part `part` of `parts` of n items, [first, second): how a level's work is shared among run_levels' parts.
template <typename Count>
std::pair<Count, Count> part_of(Count n, int part, int parts) {
    return {Count(std::int64_t(n) * part / parts), Count(std::int64_t(n) * (part + 1) / parts)};
}

template <typename Work>
void run_levels(int threads, int levels, const Work& work) {
    if (threads == 1) {
        for (int l = 0; l < levels; ++l) work(l, 0, 1);
        return;
    }
    std::mutex mutex;
    std::condition_variable changed;
    std::atomic<int> running{threads}, arrived{0}, generation{0};
    auto wait_for_others = [&] {
        const int mine = generation.load(std::memory_order_acquire);
        if (arrived.fetch_add(1, std::memory_order_acq_rel) + 1 == running.load(std::memory_order_acquire)) {
            arrived.store(0, std::memory_order_relaxed);
            {
                std::lock_guard<std::mutex> lock(mutex);
                generation.store(mine + 1, std::memory_order_release);
            }
            changed.notify_all();
            return;
        }
        // The parts of a level end close together, and waking a thread that went to sleep costs tens of microseconds
        // (measured 50-90 us on a virtual machine's idle core, about what a level of a frame takes): wait awake a
        // while first, yielding (the thread still to arrive may share this core), then sleep.
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::microseconds(200);
        while (generation.load(std::memory_order_acquire) == mine && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
        std::unique_lock<std::mutex> lock(mutex);
        changed.wait(lock, [&] { return generation.load(std::memory_order_acquire) != mine; });
    };
    auto run = [&](std::vector<int> parts) {
        for (int l = 0; l < levels; ++l) {
            for (int part : parts) work(l, part, threads);
            wait_for_others();
        }
    };
    std::vector<std::thread> workers;
    workers.reserve(threads - 1);
    std::vector<int> callers_parts = {0};
    for (int part = 1; part < threads; ++part) {
        try {
            workers.emplace_back(run, std::vector<int>{part});
        } catch (const std::system_error&) {
            // The caller has not reached the first barrier yet, so the threads already waiting there cannot be
            // released early: it is safe to lower the count here and hand the remaining parts to the caller.
            std::lock_guard<std::mutex> lock(mutex);
            running.fetch_sub(threads - part, std::memory_order_acq_rel);
            for (; part < threads; ++part) callers_parts.push_back(part);
        }
    }
    run(callers_parts);
    for (std::thread& worker : workers) worker.join();
}

}  // namespace loopsub::detail
