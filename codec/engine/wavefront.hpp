// wavefront.hpp - the scan both synthesis engines run over one image (a
// still level, or one frame of an animated level): row y starts at column
// row_start(y, lag, width) and wraps, and the rows run on several threads as
// a wavefront, each waiting only until the row above is far enough ahead
// (synthesis.hpp explains why every read then sees the same value on any
// number of threads).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

#include "common/parallel.hpp"
#include "engine/synthesis.hpp"

namespace vqtex {

// A row's count of finished pixels, alone on its cache line: the thread
// writing it and the thread polling it for the next row would otherwise
// fight over a line shared with other rows' counters.
struct alignas(64) RowProgress {
    std::atomic<int> done{0};
};

// Rows publish their progress every this many pixels (and at the end): the
// row below only needs it to be far enough ahead, and publishing per pixel
// would move the cache line between cores at every pixel.
inline constexpr int kPublishEvery = 8;  // a power of two

// A row trails the row above by this many pixels more than its window needs.
// Without the slack the row above is read a few bytes behind where it is
// being written, and the cache line under both moves between the two cores
// at every pixel; with it the threads touch different lines. Waiting longer
// never changes what is read (those pixels are final either way). Narrow
// rows get less (an eighth of the row): on a 64-pixel row a 64-pixel slack
// would leave no room for a second row at all, and on a 128-pixel one almost
// none (measured: 8% faster at 256x256 output, 1-4% at 512x512).
inline constexpr int kWavefrontSlack = 64;
inline int wavefront_slack(int width) { return std::min(kWavefrontSlack, width / 8); }

inline void wait_for(const std::atomic<int>& value, int needed, const std::atomic<bool>& stop) {
    int spins = 0;
    while (value.load(std::memory_order_acquire) < needed) {
        if (stop.load(std::memory_order_relaxed)) return;
        if (++spins > 64) std::this_thread::yield();
    }
}

// One image's scan: its size, the rotation of its rows and how far the
// causal window reaches, and the shared progress of its rows.
struct WavefrontScan {
    int width, height, lag, reach_x, reach_y, slack;
    bool parallel;  // false: one thread, no waiting
    std::vector<RowProgress>* progress;  // one per row, zero at the start
    std::atomic<bool>* stop;
};

// Row y in scan order: visit(x) for each pixel, after waiting (when
// parallel) until the row above is far enough ahead. False when stopped.
template <typename Visit>
bool scan_row(const WavefrontScan& s, int y, Visit&& visit) {
    const int w = s.width;
    const int start = row_start(y, s.lag, w);
    std::atomic<int>& mine = (*s.progress)[std::size_t(y)].done;
    if (s.parallel && y >= s.height - s.reach_y && s.reach_y > 0) {
        // Rows at the bottom are read as initial values by the first rows
        // (top wrap); they may change only once those rows are finished.
        wait_for((*s.progress)[std::size_t(s.reach_y - 1)].done, w, *s.stop);
    }
    for (int i = 0; i < w; ++i) {
        if (s.parallel && y > 0)
            wait_for((*s.progress)[std::size_t(y - 1)].done, std::min(w, i + s.lag + s.reach_x + 1 + s.slack),
                     *s.stop);
        if (s.stop->load(std::memory_order_relaxed)) return false;
        visit(start + i < w ? start + i : start + i - w);
        if (s.parallel && (((i + 1) & (kPublishEvery - 1)) == 0 || i + 1 == w))
            mine.store(i + 1, std::memory_order_release);
    }
    return true;
}

// Rows 0..height-1 on `workers` threads running together (run_together,
// parallel.hpp), row y on worker y % workers (the calling thread is worker
// 0). Each worker makes its own state once (make_state()) and calls
// row(worker, y, state) for its rows in order. A worker that throws sets
// `stop` first: the rows below wait on its rows, and would otherwise wait
// for ever; run_together then rethrows.
template <typename MakeState, typename Row>
void run_rows(int workers, int height, std::atomic<bool>& stop, MakeState&& make_state, Row&& row) {
    run_together(workers, [&](int index) {
        try {
            auto state = make_state();
            for (int y = index; y < height; y += workers) {
                if (stop.load()) return;
                row(index, y, state);
            }
        } catch (...) {
            stop.store(true);
            throw;
        }
    });
}

}  // namespace vqtex
