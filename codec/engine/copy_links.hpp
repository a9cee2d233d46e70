// copy_links.hpp - byte maps of the links between adjacent entries of a
// position map (coherent_synthesis.hpp): where a pixel continues its
// neighbour's copy. The correction's skip (coherent_pixel_correction.cpp)
// and the blend at seams (seam_blend.cpp) find with them, a row at a time, the
// pixels whose whole window continues their own copy. A window of radius r
// continues its centre at every tap if and only if each pixel continues its
// left neighbour along the window's rows and its upper neighbour down the
// centre column: the differences of packed positions add up (mod 2^32),
// exactly when the centre lies at least the window's reach inside the
// example. The loops are apart and __restrict so that they vectorise.
#pragma once

#include <cstdint>
#include <cstring>

namespace vqtex {
namespace coherent {

// run[x] = 1 when each of columns x - r + 1 .. x + r of `row` (w wide, a
// torus) continues the one to its left by `step`: the 2r links of a
// (2r + 1)-wide window's row. `links` has w + 2r bytes.
inline void window_runs(const uint32_t* __restrict row, int w, int r, uint32_t step, uint8_t* __restrict links,
                        uint8_t* __restrict run) {
    // links[c + r]: column c + 1 continues column c; padded by the wrap, so
    // that links[i] is the link from column (i - r) mod w, also for w < r.
    for (int x = 0; x + 1 < w; ++x) links[x + r] = uint8_t(row[x + 1] - row[x] == step);
    links[w - 1 + r] = uint8_t(row[0] - row[w - 1] == step);
    for (int i = 0; i < r; ++i) {
        links[i] = links[r + ((i - r) % w + w) % w];
        links[w + r + i] = links[r + i % w];
    }
    std::memset(run, 1, std::size_t(w));
    for (int k = 0; k < 2 * r; ++k)
        for (int x = 0; x < w; ++x) run[x] &= links[x + k];
}

// down[x] = 1 when `next` continues `row` at column x by `step`.
inline void window_down(const uint32_t* __restrict row, const uint32_t* __restrict next, int w, uint32_t step,
                        uint8_t* __restrict down) {
    for (int x = 0; x < w; ++x) down[x] = uint8_t(next[x] - row[x] == step);
}

// whole[x] = 1 when the window of radius r around row[x] continues it at
// every tap: the source's coordinates less `reach` lie below inside_x and
// inside_y (it is at least `reach` inside the example), the 2r + 1 rows'
// runs hold (`runs`, w apart, from the window's first row) and so do the 2r
// links down the centre column (`down`, w apart, from the first row).
inline void whole_windows(const uint32_t* __restrict row, const uint8_t* __restrict runs,
                          const uint8_t* __restrict down, int w, int r, uint32_t reach, uint32_t inside_x,
                          uint32_t inside_y, uint8_t* __restrict whole) {
    for (int x = 0; x < w; ++x)
        whole[x] = uint8_t(((row[x] & 0xFFFF) - reach < inside_x) & ((row[x] >> 16) - reach < inside_y));
    const std::size_t stride = std::size_t(w);
    for (int i = 0; i <= 2 * r; ++i)
        for (int x = 0; x < w; ++x) whole[x] &= runs[std::size_t(i) * stride + std::size_t(x)];
    for (int i = 0; i < 2 * r; ++i)
        for (int x = 0; x < w; ++x) whole[x] &= down[std::size_t(i) * stride + std::size_t(x)];
}

}  // namespace coherent
}  // namespace vqtex
