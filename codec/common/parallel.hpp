// parallel.hpp - fixed work partitions over threads. Work is split into
// chunks whose boundaries depend only on the problem size, never on the
// thread count, and every reduction the codec does over chunks is exact
// integer arithmetic, so results never depend on how many threads ran nor
// on which thread ran which chunk.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <thread>
#include <vector>

namespace vqtex {

namespace detail {

// Runs job(w) for every w in [0, workers): job(0) on the calling thread,
// the others on threads kept from one call to the next (one synthesis runs
// some 150 loops, and starting threads for each cost about a tenth of a
// 512x512 synthesis). Returns false, having run nothing, when the kept
// threads are busy (a call from another thread, or from inside a job); the
// caller then starts threads of its own. An exception thrown by any job is
// rethrown here once every job has returned.
bool run_on_kept_threads(int workers, const std::function<void(int)>& job);

}  // namespace detail

// Calls fn(begin, end) for consecutive ranges of [0, n) of at most `grain`
// items, spread over up to `threads` threads (the caller's thread included).
// Threads take the next chunk when they finish one, so rows that cost more
// than others do not leave a thread idle.
template <typename Fn>
void parallel_for(int threads, std::size_t n, std::size_t grain, Fn&& fn) {
    const std::size_t chunks = (n + grain - 1) / grain;
    const int workers = int(std::min<std::size_t>(std::size_t(std::max(threads, 1)), chunks));
    if (workers <= 1) {
        for (std::size_t c = 0; c < chunks; ++c) fn(c * grain, std::min(n, (c + 1) * grain));
        return;
    }
    std::atomic<std::size_t> next{0};
    const std::function<void(int)> run = [&](int) {
        for (std::size_t c = next.fetch_add(1, std::memory_order_relaxed); c < chunks;
             c = next.fetch_add(1, std::memory_order_relaxed))
            fn(c * grain, std::min(n, (c + 1) * grain));
    };
    if (detail::run_on_kept_threads(workers, run)) return;
    std::vector<std::thread> pool;
    for (int w = 1; w < workers; ++w) pool.emplace_back(run, w);
    run(0);
    for (auto& t : pool) t.join();
}

inline int hardware_threads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : int(n);
}

}  // namespace vqtex
