// coherent_pass.hpp - the schedule of one correction pass of the coherent
// engine (Lefebvre & Hoppe 2005 section 3.4): the pixels of a torus of
// states corrected in four interleaved subsets, each reading only the
// states before it, so that no result depends on the thread count or the
// order of the pixels; with the flags of the pixels whose window changed
// (the only ones a pass must evaluate again) and the bands of rows of a
// taller torus that the still engine's finest level runs in. Written once
// for any state type: still textures and animations alike.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "common/image.hpp"
#include "common/parallel.hpp"
#include "engine/coherent_window.hpp"

namespace vqtex::coherent {

// Which pixels a pass must evaluate again. A pixel's correction depends
// only on the states in its window, so a pixel none of whose window has
// changed since its last evaluation would choose what it holds already:
// skipping it gives the same bytes. Over the passes of one level (same
// features) this skips most of the second pass.
struct Revisit {
    std::vector<uint8_t> due;  // evaluate at its next turn
    explicit Revisit(std::size_t pixels) : due(pixels, 1) {}
};

// A band of rows of a taller torus, passed through on its own (the
// finest level of a large output, coherent_bands.cpp): the map's row r
// is row (first + r) mod torus_height of the torus, which decides the
// subset it belongs to. Windows do not wrap inside a band: those that reach
// past its first or last row read that row instead, so states near its
// edges go wrong, and the caller keeps only rows they cannot reach (the
// margin). A state goes wrong only when its window (2 rows either way)
// holds a wrong one, or its revisit flag is wrong, which takes a wrong
// state within the same 2 rows. The first subset spoils at most 2 rows from
// an edge; each later one changes the rows of the other parity than the one
// before, so the nearest of them past the wrong rows is 1 row further in,
// or 2 once where an odd torus wraps inside the band (two rows of one
// parity side by side): after n subsets, at most n + 2 rows from an edge.
struct Band {
    int first = 0;
    int torus_height = 0;
};

// One correction pass over a w x h torus of states `map` (any element
// type), in four interleaved subsets; each subset reads only the states as
// they were before it, so no pixel's result depends on the thread count or
// on the order pixels are visited. `correct(x, y, xs, ys)` returns pixel
// (x, y)'s new state from `map`; xs and ys are the wrapped columns and rows
// of its 5x5 window. A subset's results go to a buffer of its own size
// first, since its rows read one another's windows, and are put in place
// once it is done. With `revisit`, pixels whose window has not changed
// since their last evaluation keep their state without one. With `band`,
// `map` holds h rows of a taller torus (Band).
template <typename T, typename Correct>
void interleaved_pass(int threads, int w, int h, std::vector<T>& map, Correct&& correct, Revisit* revisit = nullptr,
                      const Band* band = nullptr) {
    static constexpr int kOrder[4][2] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
    // The map's rows by the parity of their row on the torus: every other
    // row, except across the wrap of an odd torus inside a band.
    std::vector<int> parity_rows[2];
    for (int y = 0; y < h; ++y) parity_rows[(band ? (band->first + y) % band->torus_height : y) & 1].push_back(y);
    const auto window_row = [&](int y) { return band ? std::clamp(y, 0, h - 1) : Image::wrap(y, h); };
    std::vector<T> chosen(std::size_t((w + 1) / 2) * std::max(parity_rows[0].size(), parity_rows[1].size()));
    // moved[i] = 1 when chosen[i] differs from the pixel's state: only those
    // are put in place (a quarter of a byte per pixel more).
    std::vector<uint8_t> moved(chosen.size());
    for (const auto& subset : kOrder) {
        // Plain ints: clang 14 cannot capture structured bindings in a lambda.
        const int sx = subset[0];
        const std::vector<int>& subset_rows = parity_rows[subset[1]];
        const int rows = int(subset_rows.size()), cols = (w - sx + 1) / 2;
        if (rows <= 0 || cols <= 0) continue;
        // Chunks of at least ~512 pixels: below that, waking a thread costs
        // more than the rows it would take. The coarse levels' pixels are
        // the dearest (most of their windows propose and cross the
        // example's edge): with 4096, the 128x128 level of a 512x512
        // output and every smaller one ran on one thread, 4.2 ms of it.
        const std::size_t grain = std::max<std::size_t>(4, std::size_t(512 / cols));
        parallel_for(threads, std::size_t(rows), grain, [&](std::size_t r0, std::size_t r1) {
            int xs[kSide], ys[kSide];
            uint8_t* const due = revisit ? revisit->due.data() : nullptr;
            for (std::size_t r = r0; r < r1; ++r) {
                const int y = subset_rows[r];
                T* out = chosen.data() + r * std::size_t(cols);
                uint8_t* changed = moved.data() + r * std::size_t(cols);
                const T* in = map.data() + std::size_t(y) * w;
                for (int i = 0; i < kSide; ++i) ys[i] = window_row(y + i - kRadius);
                for (int x = sx, i = 0; x < w; x += 2, ++i) {
                    const std::size_t at = std::size_t(y) * w + x;
                    if (due) {
                        // Pixels not due (most of them in a level's later
                        // passes, and where the still engine's
                        // skip_coherent found them) go by unchanged; only
                        // due ones have their window's columns made.
                        if (!due[at]) {
                            changed[i] = 0;
                            continue;
                        }
                        due[at] = 0;
                    }
                    // Wrap by comparison except on outputs narrower than
                    // the window.
                    for (int j = 0; j < kSide; ++j) {
                        int c = x + j - kRadius;
                        if (w < kSide) c = Image::wrap(c, w);
                        else if (c < 0) c += w;
                        else if (c >= w) c -= w;
                        xs[j] = c;
                    }
                    out[i] = correct(x, y, xs, ys);
                    changed[i] = uint8_t(!(out[i] == in[x]));
                }
            }
        });
        // Putting the changed choices in place, serially: a pixel's state
        // and the flags of the windows that hold it (with `revisit`, every
        // pixel whose window holds a changed one is due again, marked here,
        // after the subset, so no flag is written twice at once; in a band,
        // only the rows it holds). Few change, so the flags are scanned
        // eight at a time.
        for (int r = 0; r < rows; ++r) {
            const int y = subset_rows[std::size_t(r)];
            T* row = map.data() + std::size_t(y) * std::size_t(w);
            const T* in = chosen.data() + std::size_t(r) * std::size_t(cols);
            const uint8_t* changed = moved.data() + std::size_t(r) * std::size_t(cols);
            for (int i0 = 0; i0 < cols; i0 += 8) {
                const int n = std::min(8, cols - i0);
                uint64_t word = 0;
                std::memcpy(&word, changed + i0, std::size_t(n));
                if (word == 0) continue;
                for (int i = i0; i < i0 + n; ++i) {
                    if (!changed[i]) continue;
                    const int x = sx + 2 * i;
                    row[x] = in[i];
                    if (!revisit) continue;
                    // Rows and columns wrap by division only near the
                    // torus's edges.
                    const bool inner = x >= kRadius && x + kRadius < w;
                    for (int dy = -kRadius; dy <= kRadius; ++dy) {
                        int yy = y + dy;
                        if (yy < 0 || yy >= h) {
                            if (band) continue;
                            yy = Image::wrap(yy, h);
                        }
                        uint8_t* due = revisit->due.data() + std::size_t(yy) * w;
                        if (inner)
                            for (int dx = -kRadius; dx <= kRadius; ++dx) due[x + dx] = 1;
                        else
                            for (int dx = -kRadius; dx <= kRadius; ++dx) due[Image::wrap(x + dx, w)] = 1;
                    }
                }
            }
        }
    }
}

}  // namespace vqtex::coherent
