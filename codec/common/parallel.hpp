// parallel.hpp - fixed work partitions over threads. Work is split into
// chunks whose boundaries depend only on the problem size, never on the
// thread count, and every reduction the codec does over chunks is exact
// integer arithmetic, so results never depend on how many threads ran.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace vqtex {

// Calls fn(begin, end) for consecutive ranges of [0, n) of at most `grain`
// items, spread over up to `threads` threads (the caller's thread included).
template <typename Fn>
void parallel_for(int threads, std::size_t n, std::size_t grain, Fn&& fn) {
    const std::size_t chunks = (n + grain - 1) / grain;
    const int workers = int(std::min<std::size_t>(std::size_t(std::max(threads, 1)), chunks));
    if (workers <= 1) {
        for (std::size_t c = 0; c < chunks; ++c) fn(c * grain, std::min(n, (c + 1) * grain));
        return;
    }
    auto run = [&](int w) {
        for (std::size_t c = std::size_t(w); c < chunks; c += std::size_t(workers))
            fn(c * grain, std::min(n, (c + 1) * grain));
    };
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
