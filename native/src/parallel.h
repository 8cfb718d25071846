// The one place threads are made: a run over the levels of a plan or a frame, each level split into parts, and
// the team that keeps its threads through a plan's build.
#pragma once

#include <algorithm>
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

// Part `part` of `parts` of n items, [first, second): how a level's work is shared among run_levels' parts.
template <typename Count>
std::pair<Count, Count> part_of(Count n, int part, int parts) {
    return {Count(std::int64_t(n) * part / parts), Count(std::int64_t(n) * (part + 1) / parts)};
}

// A thread arriving at a meeting point waits awake a while, yielding (the thread still to arrive may share its core),
// then sleeps: the parts of a level end close together, and waking a thread that went to sleep costs tens of
// microseconds (measured 50-90 us on a virtual machine's idle core, about what a level of a frame takes).
template <typename Done>
void wait_awake_then_sleep(std::mutex& mutex, std::condition_variable& changed, const Done& done,
                           std::chrono::microseconds awake = std::chrono::microseconds(200)) {
    const auto give_up = std::chrono::steady_clock::now() + awake;
    while (!done() && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
    std::unique_lock<std::mutex> lock(mutex);
    changed.wait(lock, done);
}

// Threads kept for one stretch of work with many parallel steps and short serial ones between them (a plan's build):
// while a Team is in scope on a thread, run_levels there runs on the team's threads instead of starting its own. A
// thread starts in 60 us on average here (mean of 800 starts, a plan's four steps paying 0.24 ms of a 2.9 ms build);
// a team starts its threads once, while the caller does serial work, and they wait awake between steps for up to
// 1 ms, since a plan's serial steps are longer than a frame's (its base level: 0.4 ms here). A plan's two-thread
// build: 2.61-2.75 ms with a start per step, 2.48-2.55 with a team. A thread the system refuses to start costs
// parallelism, never the process: the caller then runs its part too.
class Team {
public:
    explicit Team(int threads) : parts_(std::max(1, threads)), previous_(current_) {
        for (int part = 1; part < parts_; ++part) {
            try {
                workers_.emplace_back([this, part] { serve(part); });
            } catch (const std::system_error&) {
                for (; part < parts_; ++part) callers_parts_.push_back(part);
            }
        }
        current_ = this;
    }
    ~Team() {
        current_ = previous_;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
            generation_.fetch_add(1, std::memory_order_release);
        }
        started_.notify_all();
        for (std::thread& worker : workers_) worker.join();
    }
    Team(const Team&) = delete;
    Team& operator=(const Team&) = delete;

    // The team in scope on this thread, or null.
    static Team* current() { return current_; }
    int parts() const { return parts_; }

    // Runs work(part, parts) for every part at once and returns when all have ended (their writes visible). Called
    // again from within the caller's own part, it runs every part there, one after the other: the workers are busy.
    template <typename Work>
    void run(const Work& work) {
        if (running_) {
            for (int part = 0; part < parts_; ++part) work(part, parts_);
            return;
        }
        running_ = true;
        job_ = [](const void* context, int part, int parts) { (*static_cast<const Work*>(context))(part, parts); };
        context_ = &work;
        finished_.store(0, std::memory_order_relaxed);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            generation_.fetch_add(1, std::memory_order_release);
        }
        started_.notify_all();
        for (int part : callers_parts_) work(part, parts_);
        const int workers = int(workers_.size());
        wait_awake_then_sleep(mutex_, ended_, [&] { return finished_.load(std::memory_order_acquire) == workers; });
        running_ = false;
    }

private:
    void serve(int part) {
        int seen = 0;
        while (true) {
            wait_awake_then_sleep(mutex_, started_, [&] { return generation_.load(std::memory_order_acquire) != seen; }, kAwake);
            seen = generation_.load(std::memory_order_acquire);
            if (stopping_) return;
            job_(context_, part, parts_);
            if (finished_.fetch_add(1, std::memory_order_acq_rel) + 1 == int(workers_.size())) {
                std::lock_guard<std::mutex> lock(mutex_);  // the caller may be between its check and its sleep
                ended_.notify_all();
            }
        }
    }

    static constexpr std::chrono::microseconds kAwake{1000};
    const int parts_;
    Team* const previous_;
    std::vector<std::thread> workers_;
    std::vector<int> callers_parts_ = {0};
    std::mutex mutex_;
    std::condition_variable started_, ended_;
    std::atomic<int> generation_{0}, finished_{0};
    bool stopping_ = false;  // written under mutex_ before the generation that ends the workers
    bool running_ = false;   // the caller's thread is inside run()
    void (*job_)(const void*, int, int) = nullptr;
    const void* context_ = nullptr;
    static inline thread_local Team* current_ = nullptr;
};

// Runs work(level, part, parts) for every level in order and every part of a level at once: one thread per part
// for the whole run (the caller being part 0), meeting at a barrier between levels; on the team in scope where its
// size is `threads`. A thread the system refuses to start costs parallelism, never the process: the parts are then
// shared among the threads that run.
template <typename Work>
void run_levels(int threads, int levels, const Work& work) {
    if (threads == 1) {
        for (int l = 0; l < levels; ++l) work(l, 0, 1);
        return;
    }
    if (Team* team = Team::current(); team && team->parts() == threads) {
        for (int l = 0; l < levels; ++l) team->run([&work, l](int part, int parts) { work(l, part, parts); });
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
        wait_awake_then_sleep(mutex, changed, [&] { return generation.load(std::memory_order_acquire) != mine; });
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
