// seam_cut.cpp - minimum-error boundary cuts between the coherent engine's
// copies (Efros & Freeman 2001; Kwatra et al. 2003). See seam_cut.hpp.
#include "engine/seam_cut.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "common/parallel.hpp"
#include "engine/coherent_positions.hpp"

namespace vqtex {
namespace {

using namespace seam_detail;

// Lines of the map seen across and along a border: for vertical borders
// (between columns) `across` is x and `along` is y; for horizontal ones the
// reverse. `step_*` are the matching unit steps in the example.
struct Lines {
    int across_size, along_size, width;
    bool vertical;
    // Where blocks start along the lines: entry 0 along them is entry
    // `origin` of a torus `period` long.
    int origin, period;
    std::size_t index(int across, int along) const {
        return vertical ? std::size_t(along) * std::size_t(width) + std::size_t(across)
                        : std::size_t(across) * std::size_t(width) + std::size_t(along);
    }
    int dx(int k) const { return vertical ? k : 0; }
    int dy(int k) const { return vertical ? 0 : k; }
};

// Pixels a cut gives another copy: (index in the map, position).
template <class Position>
using Writes = std::vector<std::pair<std::size_t, Position>>;

// One run of a border at `a` (between across-indices a - 1 and a), rows
// [u0, u1) along it: A the copy on the low side, B on the high side.
template <class Positions>
void cut_run(const Source<Positions>& ex, const Lines& lines, const std::vector<typename Positions::Position>& in,
             const std::vector<uint8_t>& links, uint8_t across_bit, Writes<typename Positions::Position>& out, int a,
             int u0, int u1, const CutRules& rules) {
    using Position = typename Positions::Position;
    const int n = u1 - u0, reach = rules.reach, span = 2 * reach + 1;
    const int A = lines.across_size;
    const auto at = [&](int across, int u) { return in[lines.index(Image::wrap(across, A), u)]; };
    // Per row: how many of A's pixels may turn B (low) and of B's turn A
    // (high). A copy narrower than two reaches is shared with the run on
    // its other side, half each, so that runs never write the same pixel.
    std::vector<int> low(static_cast<std::size_t>(n)), high(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const int u = u0 + i;
        const Position pa = at(a - 1, u), pb = at(a, u);
        int la = 1;
        // (link_map's bit across the border: the pixel goes on from the one
        // before it.)
        const auto goes_on = [&](int across_index) {
            return (links[lines.index(Image::wrap(across_index, A), u)] & across_bit) != 0;
        };
        while (la < 2 * reach && goes_on(a - la)) ++la;
        int lb = 1;
        while (lb < 2 * reach && goes_on(a + lb)) ++lb;
        int lo = la >= 2 * reach ? reach : la / 2, hi = lb >= 2 * reach ? reach : lb / 2;
        // B must extend to every pixel it may take, A likewise.
        Position e{};
        for (int k = 1; k <= lo; ++k)
            if (!ex.extend(pb, lines.dx(-k), lines.dy(-k), e)) {
                lo = k - 1;
                break;
            }
        for (int k = 1; k <= hi; ++k)
            if (!ex.extend(pa, lines.dx(k), lines.dy(k), e)) {
                hi = k - 1;
                break;
            }
        low[std::size_t(i)] = lo;
        high[std::size_t(i)] = hi;
    }
    // The run's ends stay where they are, so the cut joins the borders
    // beyond them.
    low.front() = high.front() = low.back() = high.back() = 0;
    // cost[i][j]: the least cost of a path down to row i with B starting
    // at across-index a + j - reach.
    constexpr uint64_t kNone = std::numeric_limits<uint64_t>::max();
    std::vector<uint64_t> cost(std::size_t(n) * span, kNone);
    std::vector<int8_t> from(std::size_t(n) * span, 0);
    for (int i = 0; i < n; ++i) {
        const int u = u0 + i;
        const Position pa = at(a - 1, u), pb = at(a, u);
        for (int j = reach - low[std::size_t(i)]; j <= reach + high[std::size_t(i)]; ++j) {
            const int c = j - reach;  // B from a + c, A up to a + c - 1
            // A's pixel at a + c - 1 and B's at a + c exist (within the
            // row's low and high); the border between them costs what
            // border_cost says.
            Position last_a{}, first_b{};
            ex.extend(pa, lines.dx(c), lines.dy(c), last_a);
            ex.extend(pb, lines.dx(c), lines.dy(c), first_b);
            const uint64_t here = ex.border_cost(last_a, first_b, lines.dx(1), lines.dy(1));
            uint64_t best = i == 0 ? 0 : kNone;
            int8_t move = 0;
            if (i > 0)
                for (int d : {0, -1, 1}) {
                    const int jj = j + d;
                    if (jj < 0 || jj >= span) continue;
                    const uint64_t v = cost[std::size_t(i - 1) * span + std::size_t(jj)];
                    if (v < best) {
                        best = v;
                        move = int8_t(d);
                    }
                }
            if (best == kNone) continue;
            cost[std::size_t(i) * span + std::size_t(j)] = best + here;
            from[std::size_t(i) * span + std::size_t(j)] = move;
        }
    }
    // The last row is pinned at j = reach, reachable from the first.
    int j = reach;
    if (cost[std::size_t(n - 1) * span + std::size_t(j)] == kNone) return;
    for (int i = n - 1; i >= 0; --i) {
        const int c = j - reach;
        const int u = u0 + i;
        const Position pa = at(a - 1, u), pb = at(a, u);
        Position e{};
        for (int k = c; k < 0; ++k)  // A's pixels that turn B
            if (ex.extend(pb, lines.dx(k), lines.dy(k), e))
                out.emplace_back(lines.index(Image::wrap(a + k, A), u), e);
        for (int k = 0; k < c; ++k)  // B's pixels that turn A
            if (ex.extend(pa, lines.dx(k + 1), lines.dy(k + 1), e))
                out.emplace_back(lines.index(Image::wrap(a + k, A), u), e);
        j += from[std::size_t(i) * span + std::size_t(j)];
    }
}

// Where each pixel of a w x h torus of positions goes on from its left
// neighbour (bit 0) and from its upper one (bit 1): a byte per pixel, made
// row by row, so that the runs' scan down columns reads bytes.
template <class Positions>
std::vector<uint8_t> link_map(const Source<Positions>& source, int w, int h,
                              const std::vector<typename Positions::Position>& pos, int threads) {
    using Position = typename Positions::Position;
    std::vector<uint8_t> links(pos.size());
    // Positions (coherent_positions.hpp) go on by +1 to the right and by
    // +2^16 down, exactly, within a frame (a position past the example's
    // last column or row is no position); a tiling example also from its
    // last column to its first and from its last row to its first.
    const Image& ex = source.frames[0];
    const Position last_x = Position(ex.width - 1), last_y = Position(ex.height - 1);
    const Position wrap_y = last_y << 16, down = Position(1) << 16;
    const bool wraps = source.wraps;
    parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
        for (int y = int(y0); y < int(y1); ++y) {
            const Position* __restrict row = pos.data() + std::size_t(y) * std::size_t(w);
            const Position* __restrict up = pos.data() + std::size_t(Image::wrap(y - 1, h)) * std::size_t(w);
            uint8_t* __restrict out = links.data() + std::size_t(y) * std::size_t(w);
            for (int x = 0; x < w; ++x) {
                const Position p = row[x], left = row[x == 0 ? w - 1 : x - 1], above = up[x];
                bool l = Position(p - left) == 1, a = Position(p - above) == down;
                if (wraps) {
                    l = l || ((left & 0xFFFF) == last_x && p == left - last_x);
                    a = a || (((above >> 16) & 0xFFFF) == last_y && p == above - wrap_y);
                }
                out[x] = uint8_t(int(l) | int(a) << 1);
            }
        }
    });
    return links;
}

// Every run of one direction's borders of `pos`, cut in place: the runs
// are found and cut on the map as it was, their pixels written after.
template <class Positions>
void cut_direction(const Source<Positions>& ex, const Lines& lines, std::vector<typename Positions::Position>& pos,
                   const CutRules& rules, int threads) {
    using Position = typename Positions::Position;
    const int A = lines.across_size, U = lines.along_size;
    if (A < 4 || U < rules.min_run) return;
    const std::vector<uint8_t> links = link_map(ex, lines.width, lines.vertical ? U : A, pos, threads);
    // Bit `across` of a pixel: it goes on from its neighbour across the
    // border; bit `along`: from its neighbour before it along the border.
    const uint8_t across = lines.vertical ? 1 : 2, along = lines.vertical ? 2 : 1;
    std::vector<Writes<Position>> writes(static_cast<std::size_t>(A));
    parallel_for(threads, std::size_t(A), 1, [&](std::size_t b0, std::size_t b1) {
        for (int a = int(b0); a < int(b1); ++a) {
            const std::size_t low = std::size_t(Image::wrap(a - 1, A));
            Writes<Position>& out = writes[std::size_t(a)];
            // Runs along the border, each within its block: a run ends where
            // the border does, where either copy stops going on along it,
            // and at a block's start.
            int start = -1;
            const auto finish = [&](int end) {
                if (start >= 0 && end - start >= rules.min_run) cut_run(ex, lines, pos, links, across, out, a, start, end, rules);
                start = -1;
            };
            BlockSteps blocks(lines.origin, lines.period, rules.block);
            for (int u = 0; u < U; ++u) {
                if (u > 0 && blocks.next()) finish(u);
                const uint8_t here = links[lines.index(a, u)];
                if (here & across) {
                    finish(u);
                    continue;
                }
                if (start >= 0 && !((here & along) && (links[lines.index(int(low), u)] & along))) finish(u);
                if (start < 0) start = u;
            }
            finish(U);
        }
    });
    for (const Writes<Position>& w : writes)
        for (const auto& [i, p] : w) pos[i] = p;
}

}  // namespace

void cut_seams(const Image& example, bool wraps, int width, int height, std::vector<uint32_t>& positions,
               const CutRules& rules, int threads, int first_row, int torus_rows) {
    if (rules.reach <= 0 || width <= 0 || height <= 0) return;
    if (torus_rows <= 0) torus_rows = height;
    const Source<coherent::PixelPositions> source{&example, wraps};
    cut_direction(source, Lines{width, height, width, true, first_row, torus_rows}, positions, rules, threads);
    cut_direction(source, Lines{height, width, width, false, 0, width}, positions, rules, threads);
}

void cut_frame_seams(const std::vector<Image>& frames, bool wraps, int width, int height,
                     std::vector<uint64_t>& voxels, const CutRules& rules, int threads) {
    if (rules.reach <= 0 || width <= 0 || height <= 0 || frames.empty()) return;
    const Source<coherent::VoxelPositions> source{frames.data(), wraps};
    cut_direction(source, Lines{width, height, width, true, 0, height}, voxels, rules, threads);
    cut_direction(source, Lines{height, width, width, false, 0, width}, voxels, rules, threads);
}

}  // namespace vqtex
