// coherent_common.hpp - pieces the still and the animated coherent engines
// share (Lefebvre & Hoppe 2005 sections 3-4, 2006 section 4): per-pixel
// seeded hashes, the 5x5 appearance-window distance with windows folded at
// the example's edge, the child coordinate of an upsampled parent, the
// correction pass scheduled in four interleaved subsets, and the choice of
// where to cut the output torus open. One definition each, so that both
// engines give the same bytes for any thread count and kernel set for the
// same reasons.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "common/hash.hpp"
#include "common/image.hpp"
#include "common/parallel.hpp"
#include "dsp/dsp.hpp"
#include "engine/appearance.hpp"

namespace vqtex::coherent {

// Neighbourhood of a correction step: the 5x5 window of appearance
// vectors (each already summarises a 5x5 window of its level).
inline constexpr int kRadius = 2;
inline constexpr int kSide = 2 * kRadius + 1;
static_assert(kAppearanceDims == dsp::kWindowTapValues, "windows are compared by dsp::Kernels::window_ssd");
inline constexpr int kTaps = kSide * kSide;

// A per-pixel hash of the seed, the level and a purpose: the same pixel of
// the same level gets the same numbers whatever else is computed.
inline uint64_t pixel_hash(uint64_t seed, int level, int purpose, int x, int y) {
    return mix64(seed ^ mix64((uint64_t(uint32_t(level)) << 40) ^ (uint64_t(uint32_t(purpose)) << 56) ^
                              (uint64_t(uint32_t(y)) << 20) ^ uint64_t(uint32_t(x))));
}

// Distance between `query` (kTaps vectors) and the window of `features`
// (kAppearanceDims per example pixel of `space`'s size) around (x, y) with
// taps `spacing` apart, stopping once it exceeds `bound`
// (Kernels::window_ssd). Windows across the example's edge read it folded:
// their taps are gathered side by side first, for the same kernel and the
// same sums.
inline uint32_t window_distance(const dsp::Kernels& kernels, const AppearanceSpace& space, const int16_t* features,
                                int spacing, const int16_t* query, int x, int y, uint32_t bound) {
    const int w = space.width, h = space.height;
    auto feature = [&](int fx, int fy) { return features + (std::size_t(fy) * w + fx) * kAppearanceDims; };
    const std::ptrdiff_t tap = std::ptrdiff_t(spacing) * kAppearanceDims;
    if (x - kRadius * spacing >= 0 && x + kRadius * spacing < w && y - kRadius * spacing >= 0 &&
        y + kRadius * spacing < h)
        return kernels.window_ssd(query, feature(x - kRadius * spacing, y - kRadius * spacing), tap, tap * w, kSide,
                                  bound);
    alignas(16) int16_t window[kTaps * kAppearanceDims];
    int xs[kSide], ys[kSide];
    for (int i = 0; i < kSide; ++i) {
        const int sx = x + (i - kRadius) * spacing, sy = y + (i - kRadius) * spacing;
        xs[i] = sx >= 0 && sx < w ? sx : space.fold_x(sx);
        ys[i] = sy >= 0 && sy < h ? sy : space.fold_y(sy);
    }
    for (int r = 0, t = 0; r < kSide; ++r)
        for (int c = 0; c < kSide; ++c, ++t)
            std::memcpy(window + t * kAppearanceDims, feature(xs[c], ys[r]), sizeof(int16_t) * kAppearanceDims);
    return kernels.window_ssd(query, window, kAppearanceDims, std::ptrdiff_t(kSide) * kAppearanceDims, kSide, bound);
}

// A child's coordinate from its parent's. Formats 3 to 6 (`clamp` false):
// a parent whose second child would fall past the example's edge has its
// block of children moved inside whole, so the block stays a coherent copy;
// folding the child back (a mirror) repeated the same rows over several
// levels and drew streaks. But the moved block repeats a few columns of the
// copy beside it, and over the levels those repeats became stutters: strips
// of the example's last columns shown twice or three times side by side
// (caustics' bright blips). Format 7 (`clamp` true): the child past the edge
// is clamped to it, so its copy breaks there and the correction passes
// decide what it shows (docs/SYNTHESIS.md "Session 12").
inline int child_coordinate(int size, bool wraps, int parent, int offset, int spacing, bool clamp) {
    if (wraps) return Image::wrap(parent + offset * spacing, size);
    const int base = clamp || parent + spacing < size ? parent : std::max(0, size - 1 - spacing);
    return std::min(base + offset * spacing, size - 1);
}

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
// finest level of a large output, coherent_synthesis.cpp): the map's row r
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

// The cut's column and row from the change summed across each column
// (`across_x[x]`: between columns x - 1 and x, wrapped) and each row: the
// first of the least, so that ties go the same way for every caller.
inline std::pair<int, int> least_change_origin(const std::vector<int64_t>& across_x,
                                               const std::vector<int64_t>& across_y) {
    const auto first_least = [](const std::vector<int64_t>& across) {
        std::size_t at = 0;
        for (std::size_t i = 1; i < across.size(); ++i)
            if (across[i] < across[at]) at = i;
        return int(at);
    };
    return {first_least(across_x), first_least(across_y)};
}

// Where to cut a w x h torus open: the column and the row across which the
// pixels change least, `step(x0, y0, x1, y1)` being the change between two
// adjacent pixels (summed over everything that shares the cut, such as all
// the frames of an animation). Left at the coarsest level's grid, the edges
// lay where coherent copies tend to meet, and on 6 of 23 corpus textures the
// wrap was a visible line.
//
// The sums are exact integers, so their order is free: the columns' are
// taken in strips of columns, row after row (a column at a time strode
// across the whole map, a cache miss a step), the rows' row by row, both
// on up to `threads` threads (`step` must be safe to call from several at
// once); it was a serial 5% of a 512x512 decode.
template <typename Step>
std::pair<int, int> torus_origin(int w, int h, Step&& step, int threads = 1) {
    std::vector<int64_t> across_x(std::size_t(w), 0), across_y(std::size_t(h), 0);
    constexpr int kStrip = 64;
    parallel_for(threads, std::size_t((w + kStrip - 1) / kStrip), 1, [&](std::size_t s0, std::size_t s1) {
        const int x0 = int(s0) * kStrip, x1 = std::min(w, int(s1) * kStrip);
        for (int y = 0; y < h; ++y)
            for (int x = x0; x < x1; ++x) across_x[std::size_t(x)] += step(x == 0 ? w - 1 : x - 1, y, x, y);
    });
    parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
        for (int y = int(y0); y < int(y1); ++y) {
            int64_t sum = 0;
            const int above = y == 0 ? h - 1 : y - 1;
            for (int x = 0; x < w; ++x) sum += step(x, above, x, y);
            across_y[std::size_t(y)] = sum;
        }
    });
    return least_change_origin(across_x, across_y);
}

}  // namespace vqtex::coherent
