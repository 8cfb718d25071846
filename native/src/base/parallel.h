// The one place threads are made: a run over the levels of a plan or a frame, each level split into parts, and
// the team that keeps its threads through a plan's build.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#if !defined(_WIN32)
#include <unistd.h>
#endif

namespace loopsub::detail {

// Tells a child made by fork() from its parent (Windows has no fork()).
inline long process_id() {
#if defined(_WIN32)
    return 0;
#else
    return long(getpid());
#endif
}

// Part `part` of `parts` of n items, [first, second): how a level's work is shared among run_levels' parts.
template <typename Count>
std::pair<Count, Count> part_of(Count n, int part, int parts) {
    return {Count(std::int64_t(n) * part / parts), Count(std::int64_t(n) * (part + 1) / parts)};
}

// A thread arriving at a meeting point waits awake a while, yielding (the thread still to arrive may share its core),
// then sleeps: the parts of a level end close together, and waking a thread that went to sleep costs about what a
// level of a frame takes (docs/benchmark.md, "Threads").
template <typename Done>
void wait_awake_then_sleep(std::mutex& mutex, std::condition_variable& changed, const Done& done,
                           std::chrono::microseconds awake = std::chrono::microseconds(200)) {
    const auto give_up = std::chrono::steady_clock::now() + awake;
    while (!done() && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
    std::unique_lock<std::mutex> lock(mutex);
    changed.wait(lock, done);
}

// Threads kept for stretches of work with many parallel steps and short serial ones between them: a plan's build, a
// frame's levels. Starting a thread costs a good part of a frame; a team starts its threads once, and between steps
// they wait awake for up to 1 ms before they sleep. A thread the system refuses to start costs
// parallelism, never the process: the caller then runs its part too.
class Team {
public:
    explicit Team(int threads) : parts_(std::max(1, threads)) {
        for (int part = 1; part < parts_; ++part) {
            try {
                workers_.emplace_back([this, part] { serve(part); });
            } catch (const std::system_error&) {
                for (; part < parts_; ++part) callers_parts_.push_back(part);
            }
        }
    }
    ~Team() {
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

    int parts() const { return parts_; }

    // Runs work(part, parts) for every part at once and returns when all have ended (their writes visible). Called
    // again from within the caller's own part, it runs every part there, one after the other: the workers are busy.
    // A part that throws (memory running out) does not cut the others short, whose work may still read the caller's
    // stack: all end, then the first exception is thrown again on the caller's thread.
    // With more `pieces` than threads, the work is cut into that many parts, which the threads take in turn as they
    // finish the last: a thread the system holds up (another process on its core) then delays only its piece.
    template <typename Work>
    void run(const Work& work, int pieces = 0) {
        pieces = std::max(pieces, parts_);
        if (running_) {
            for (int part = 0; part < pieces; ++part) work(part, pieces);
            return;
        }
        running_ = true;
        job_ = [](const void* context, int part, int parts) { (*static_cast<const Work*>(context))(part, parts); };
        context_ = &work;
        pieces_ = pieces;
        next_piece_.store(0, std::memory_order_relaxed);
        finished_.store(0, std::memory_order_relaxed);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            generation_.fetch_add(1, std::memory_order_release);
        }
        started_.notify_all();
        for (int part : callers_parts_) run_part(part);
        const int workers = int(workers_.size());
        wait_awake_then_sleep(mutex_, ended_, [&] { return finished_.load(std::memory_order_acquire) == workers; });
        running_ = false;
        if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
    }

private:
    void run_part(int part) {
        try {
            if (pieces_ == parts_) return job_(context_, part, parts_);
            for (int piece; (piece = next_piece_.fetch_add(1, std::memory_order_relaxed)) < pieces_;)
                job_(context_, piece, pieces_);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!failure_) failure_ = std::current_exception();
        }
    }

    void serve(int part) {
        int seen = 0;
        while (true) {
            wait_awake_then_sleep(
                mutex_, started_, [&] { return generation_.load(std::memory_order_acquire) != seen; }, kAwake);
            seen = generation_.load(std::memory_order_acquire);
            if (stopping_) return;
            run_part(part);
            if (finished_.fetch_add(1, std::memory_order_acq_rel) + 1 == int(workers_.size())) {
                std::lock_guard<std::mutex> lock(mutex_);  // the caller may be between its check and its sleep
                ended_.notify_all();
            }
        }
    }

    static constexpr std::chrono::microseconds kAwake{1000};
    const int parts_;
    std::vector<std::thread> workers_;
    std::vector<int> callers_parts_ = {0};
    std::mutex mutex_;
    std::condition_variable started_, ended_;
    std::atomic<int> generation_{0}, finished_{0}, next_piece_{0};
    int pieces_ = 1;         // of the current run
    bool stopping_ = false;  // written under mutex_ before the generation that ends the workers
    bool running_ = false;   // the caller's thread is inside run()
    void (*job_)(const void*, int, int) = nullptr;
    const void* context_ = nullptr;
    std::exception_ptr failure_;  // the first part's exception in a run, under mutex_
};

// The team run_levels uses on this thread while a TeamScope is alive: the one already in scope if it has as many
// parts, else the team the process keeps if no other thread holds it, else one started for this scope (another thread
// evaluating at the same time, or more threads than the machine has). The kept team makes back-to-back frames and
// plans start no thread (docs/benchmark.md, "threads kept between frames"); its idle worker waits awake 1 ms after
// a frame, then sleeps.
class TeamScope {
public:
    explicit TeamScope(int threads) : previous_(current_) {
        if (threads < 2 || (current_ && current_->parts() == threads)) return;
        team_ = Kept::lease(threads);
        if (!team_) {
            own_ = std::make_unique<Team>(threads);
            team_ = own_.get();
        }
        current_ = team_;
    }
    ~TeamScope() {
        current_ = previous_;
        if (team_ && !own_) Kept::release();
    }
    TeamScope(const TeamScope&) = delete;
    TeamScope& operator=(const TeamScope&) = delete;

    // The team in scope on this thread, or null.
    static Team* current() { return current_; }

private:
    // One team for the process, made on first use and never destroyed: its threads would otherwise be joined while
    // the process exits (a Windows DLL's unload cannot join threads), and a sleeping worker costs nothing. A child
    // made by fork() has none of its parent's threads, so it makes its own team (the parent's is left as it is).
    struct Kept {
        static Team* lease(int threads) {
            // Asked once: glibc reads the count from /sys each time, a noticeable part of a small frame.
            static const unsigned cores = std::max(2u, std::thread::hardware_concurrency());
            if (unsigned(threads) > cores) return nullptr;
            Kept& kept = instance();
            if (kept.leased.exchange(true, std::memory_order_acquire)) return nullptr;
            if (kept.process != process_id()) {
                kept.team = nullptr;  // a forked child: its parent's team has no threads here
                kept.process = process_id();
            }
            if (kept.team && kept.team->parts() != threads) {
                delete kept.team;
                kept.team = nullptr;
            }
            if (!kept.team) {
                try {
                    kept.team = new Team(threads);
                } catch (...) {
                    release();
                    throw;
                }
            }
            return kept.team;
        }
        static void release() { instance().leased.store(false, std::memory_order_release); }
        static Kept& instance() {
            static Kept* kept = new Kept;
            return *kept;
        }
        std::atomic<bool> leased{false};  // a lease held when fork() ran stays held in the child: it starts its own
        Team* team = nullptr;
        long process = process_id();
    };

    Team* team_ = nullptr;
    std::unique_ptr<Team> own_;
    Team* const previous_;
    static inline thread_local Team* current_ = nullptr;
};

// Pieces per thread for a step of a plan whose parts keep no state of their own: four, so that a thread held up by
// the system (or a part with more work) delays the step by a quarter of its share.
constexpr int kPiecesPerThread = 4;

// Runs work(level, part, parts) for every level in order and every part of a level at once, on the team of this
// thread's TeamScope (or a scope of its own): the caller is part 0, and the parts meet between levels. With
// pieces_per_thread > 1 a level is cut into that many parts per thread, taken in turn (Team::run): for work whose
// parts need no state of their own per thread.
template <typename Work>
void run_levels(int threads, int levels, const Work& work, int pieces_per_thread = 1) {
    if (threads < 2) {
        for (int l = 0; l < levels; ++l) work(l, 0, 1);
        return;
    }
    const TeamScope scope(threads);
    for (int l = 0; l < levels; ++l)
        TeamScope::current()->run([&work, l](int part, int parts) { work(l, part, parts); },
                                  pieces_per_thread * threads);
}

}  // namespace loopsub::detail
