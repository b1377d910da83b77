// Parallelism is injected: chi2 runs loops through a ParallelFor that the caller
// supplies (validate passes its thread pool: ThreadPool::executor()). This is the
// one parallel-loop type of the project; validate's checks use it too. Results never depend on it: work is
// split into pieces whose boundaries do not depend on the thread count.
#pragma once

#include <cstddef>
#include <functional>

namespace warpcheck::chi2 {

/// Calls body(i) for every i in [0, n), on any threads, and returns when all are done.
using ParallelFor = std::function<void(std::size_t n, const std::function<void(std::size_t)>& body)>;

/// The default executor: body(0), body(1), ... on the calling thread.
inline void serial_for(std::size_t n, const std::function<void(std::size_t)>& body) {
    for (std::size_t i = 0; i < n; ++i) body(i);
}

}  // namespace warpcheck::chi2
