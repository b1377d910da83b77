// A small thread pool whose parallel_for may be nested: the calling thread works
// on its own loop too, so a check running on a pool thread can split its work
// across the pool without deadlock.
//
// Determinism rule for every user: split work into chunks whose boundaries do
// not depend on the thread count, give each chunk its own random stream, and
// combine chunk results in chunk order afterwards. Then any --threads value
// gives the same numbers, bit for bit.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "chi2/parallel.h"

namespace warpcheck {

class ThreadPool {
public:
    /// `threads` counts the caller: 1 runs everything on the calling thread.
    explicit ThreadPool(unsigned threads);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    unsigned threads() const { return static_cast<unsigned>(workers_.size()) + 1; }

    /// Calls body(i) for every i in [0, n), on any threads, and returns when all
    /// calls have finished. The first exception thrown by a body is rethrown here
    /// (the remaining indices are skipped).
    void parallel_for(std::size_t n, const std::function<void(std::size_t)>& body);

    /// The tag of the work this thread is doing: what the thread set with
    /// set_current_tag, or on a pool thread running part of a loop, the tag of
    /// the thread that started the loop. So code on any thread can tell whose
    /// work it runs (the runner tags each job, and a warp that calls exit()
    /// from a pool thread is still named).
    static const void* current_tag();
    static void set_current_tag(const void* tag);

    /// parallel_for as the project's one loop type, for code that takes an
    /// executor (chi2, the exhaustive sweeps). The pool must outlive it.
    chi2::ParallelFor executor() {
        return [this](std::size_t n, const std::function<void(std::size_t)>& body) { parallel_for(n, body); };
    }

private:
    struct Loop;
    void worker_main();
    static bool run_one(Loop& loop);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::shared_ptr<Loop>> loops_;
    bool stopping_ = false;
};

}  // namespace warpcheck
