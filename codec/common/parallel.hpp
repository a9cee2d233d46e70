// parallel.hpp - the one way the codec runs work on several threads, over
// one set of threads kept for the life of the process (parallel.cpp).
//
// Two entry points over those threads:
//   parallel_for   independent chunks of a range, taken by whichever thread
//                  is free. Chunk boundaries depend only on the problem
//                  size, never on the thread count, and every reduction the
//                  codec does over chunks is exact integer arithmetic, so
//                  results never depend on how many threads ran nor on which
//                  thread ran which chunk.
//   run_together   a fixed number of jobs that run at the same time, each on
//                  its own thread, for work whose parts wait on one another
//                  (the synthesis wavefront, where a row waits for the row
//                  above it).
// The kept threads hold no data between calls: they sleep until the next
// loop. What they run, and every value it reads, belongs to the call.
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

// Runs job(w) for every w in [0, workers) at the same time, job(0) on the
// calling thread and each other on a thread of its own (kept threads when
// they are free, started for the call otherwise). An exception thrown by
// any job is rethrown once every job has returned (the calling thread's
// first). Jobs that wait on each other must see to it that a failing job
// releases the others.
void run_together(int workers, const std::function<void(int)>& job);

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
    run_together(workers, run);
}

inline int hardware_threads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : int(n);
}

}  // namespace vqtex
