// quilt.cpp - image quilting on the output torus with the patch insertion
// cut (Efros & Freeman 2001; Kwatra et al. 2003). See quilt.hpp.
#include "engine/quilt.hpp"

#include <algorithm>
#include <cstdint>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <queue>
#include <utility>

#include "common/error.hpp"
#include "common/hash.hpp"
#include "common/parallel.hpp"
#include "dsp/dsp.hpp"
#include "engine/coherent_positions.hpp"
#include "engine/min_cut.hpp"
#include "engine/planar_cut.hpp"
#include "engine/quilt_search.hpp"

namespace vqtex {
namespace {

constexpr uint32_t kUnplaced = 0xFFFFFFFFu;

// Where block k (= j * nx + i) of an nx x ny grid lies on the width x
// height output (quilt_grid): (i * width / nx, j * height / ny).
std::pair<int, int> block_origin(int k, int nx, int ny, int width, int height) {
    return {int(int64_t(k % nx) * width / nx), int(int64_t(k / nx) * height / ny)};
}

// Whether two blocks of `block` pixels at these origins, each with the ring
// of pixels around it that laying it reads, meet on the width x height
// torus.
bool blocks_meet(std::pair<int, int> a, std::pair<int, int> b, int block, int width, int height) {
    const auto meet = [&](int u, int v, int side) {
        const int d = Image::wrap(v - u, side), reach = block + 2;
        return reach >= side || d < reach || d > side - reach;
    };
    return meet(a.first, b.first, width) && meet(a.second, b.second, height);
}

// Where block k (= j * nx + i) comes in `order`: a key that sorts as the
// order does (raster: k; wavefront: step i + 2j, then j).
int64_t order_key(int k, int nx, QuiltOrder order) {
    if (order == QuiltOrder::kRaster) return k;
    return (int64_t(k % nx + 2 * (k / nx)) << 32) | int64_t(k / nx);
}

// Calls fn(k) for every block in `order`.
template <typename Fn>
void each_in_order(int nx, int ny, QuiltOrder order, Fn&& fn) {
    if (order == QuiltOrder::kRaster) {
        for (int k = 0; k < nx * ny; ++k) fn(k);
        return;
    }
    for (int t = 0; t <= (nx - 1) + 2 * (ny - 1); ++t)
        for (int j = 0; j < ny; ++j)
            if (t - 2 * j >= 0 && t - 2 * j < nx) fn(j * nx + (t - 2 * j));
}

// Lays every block through lay(k, worker) on `workers` threads at once,
// each block as soon as every block before it in `order` that it meets is
// laid. A block then reads what it would read if the blocks were laid one
// after the other in that order, so the output is the same for any number
// of workers. Blocks three or more steps apart never meet (a step is at
// least three quarters of a block), so a block's neighbours are found
// within two steps, when needed, and only a count per block is held.
void lay_in_parallel(int nx, int ny, int width, int height, int block, QuiltOrder order, int workers,
                     const std::function<bool(uint64_t, uint64_t)>& progress,
                     const std::function<void(int k, int worker)>& lay) {
    const int count = nx * ny;
    const auto origin = [&](int k) { return block_origin(k, nx, ny, width, height); };
    // fn(m) for every other block m that block k meets.
    const auto each_met = [&](int k, auto&& fn) {
        int seen[25], n_seen = 0;
        for (int dj = -2; dj <= 2; ++dj)
            for (int di = -2; di <= 2; ++di) {
                const int m = ((k / nx + dj) % ny + ny) % ny * nx + ((k % nx + di) % nx + nx) % nx;
                if (m == k || std::find(seen, seen + n_seen, m) != seen + n_seen) continue;
                seen[n_seen++] = m;
                if (blocks_meet(origin(k), origin(m), block, width, height)) fn(m);
            }
    };
    // How many of the blocks it meets that come before it are not laid yet
    // (at most 24).
    std::vector<uint8_t> pending(static_cast<std::size_t>(count), 0);
    for (int k = 0; k < count; ++k)
        each_met(k, [&](int m) {
            if (order_key(m, nx, order) < order_key(k, nx, order)) ++pending[std::size_t(k)];
        });
    // Ready blocks, the earliest in the order first.
    std::priority_queue<std::pair<int64_t, int>, std::vector<std::pair<int64_t, int>>, std::greater<>> ready;
    for (int k = 0; k < count; ++k)
        if (pending[std::size_t(k)] == 0) ready.push({order_key(k, nx, order), k});
    std::mutex lock;
    std::condition_variable changed;
    int done = 0;
    bool stop = false, cancelled = false;
    run_together(workers, [&](int worker) {
        std::unique_lock<std::mutex> held(lock);
        // Whatever a worker throws, the others stop at their next block.
        const auto halt = [&] {
            stop = true;
            changed.notify_all();
        };
        // Progress is heard on the calling thread (worker 0) only: of every
        // block laid, by any worker, as soon as it is free to tell, so that
        // it hears of blocks and can cancel whichever worker lays them.
        int told = 0;
        const auto to_tell = [&] { return worker == 0 && progress && done != told && done < count; };
        for (;;) {
            changed.wait(held, [&] { return stop || done == count || !ready.empty() || to_tell(); });
            if (stop) return;
            if (to_tell()) {
                told = done;
                held.unlock();
                bool go_on = false;
                try {
                    go_on = progress(uint64_t(told), uint64_t(count));
                } catch (...) {
                    held.lock();
                    halt();
                    throw;
                }
                held.lock();
                if (!go_on) {
                    cancelled = true;
                    halt();
                }
                continue;
            }
            if (ready.empty()) return;
            const int k = ready.top().second;
            ready.pop();
            held.unlock();
            try {
                lay(k, worker);
            } catch (...) {
                held.lock();
                halt();
                throw;
            }
            held.lock();
            ++done;
            each_met(k, [&](int m) {
                if (order_key(k, nx, order) < order_key(m, nx, order) && --pending[std::size_t(m)] == 0)
                    ready.push({order_key(m, nx, order), m});
            });
            changed.notify_all();
        }
    });
    if (cancelled) fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
}

}  // namespace

std::vector<int> quilt_order(int nx, int ny, QuiltOrder order) {
    std::vector<int> sequence;
    each_in_order(nx, ny, order, [&](int k) { sequence.push_back(k); });
    return sequence;
}

namespace {

// A bound on the bytes one block's graphs and working lists take, per
// pixel of the block: the maximum flow's nodes and arcs (at most four edges
// a pixel, each added, then two arcs) and its active and orphan lists,
// about 265; the block's runs, colours, differences, sides and edge costs,
// about 60; the planar cut's edge costs, keys and heap (four pushes a
// lattice point at most) on (B + 2)(B + 1) lattice points, about 73 bytes
// each, at most 105 a pixel for the least block the memory check counts
// (8; smaller blocks only come with a smaller output).
constexpr uint64_t kBlockBytesPerPixel = 480;

// The bytes of the example's transforms and `searches` searches, each with
// its block's graph (a block's pairs of planes transformed together, or one
// at a time).
uint64_t layout_memory(int example_width, int example_height, int channels, int block, int searches,
                       bool pairs_at_once) {
    const uint64_t graph =
        kBlockBytesPerPixel * uint64_t(block) * uint64_t(block) +
        sizeof(uint32_t) * uint64_t(example_width - block + 1) * uint64_t(example_height - block + 1);
    return QuiltExample::shared_memory(example_width, example_height, channels) +
           uint64_t(searches) *
               (QuiltExample::search_memory(example_width, example_height, channels, block, pairs_at_once) + graph);
}

}  // namespace

uint64_t quilt_memory(int example_width, int example_height, int channels, int workers) {
    const int block = quilt_block(example_width, example_height);
    if (block == 0) return 0;
    return layout_memory(example_width, example_height, channels, block, std::max(workers, 1), workers <= 1);
}

int quilt_block(int example_width, int example_height) {
    if (std::min(example_width, example_height) < kMinQuiltSide) return 0;
    return std::min(64, std::min(example_width, example_height) / 2) / 4 * 4;
}

QuiltGrid quilt_grid(int block, int width, int height) {
    const int side = std::min(width, height);
    const int b = std::max(std::min(block, side / 2), std::min(side, 4));
    QuiltGrid g{b, b / 4, 0, 0};
    const int step = b - g.overlap;
    // The count nearest to the side over the step, so that the steps stay
    // within a quarter of it and every block has pixels of its own; never
    // so few that the blocks leave a gap (small blocks, whose overlap
    // rounds down).
    g.nx = std::max({1, (2 * width + step) / (2 * step), (width + b - 1) / b});
    g.ny = std::max({1, (2 * height + step) / (2 * step), (height + b - 1) / b});
    return g;
}

std::vector<uint32_t> quilt_positions(const Image& example, int width, int height, int block, uint64_t seed,
                                      int threads, const std::function<bool(uint64_t, uint64_t)>& progress,
                                      uint64_t search_memory, QuiltOrder order, QuiltCut cut_method) {
    const QuiltGrid grid = quilt_grid(block, width, height);
    const int B = grid.block, nx = grid.nx, ny = grid.ny, ch = example.channels;
    const int count = nx * ny;
    // Origins of a block inside the example.
    const int cx = example.width - B + 1, cy = example.height - B + 1;
    const std::size_t n = std::size_t(width) * std::size_t(height);
    std::vector<uint32_t> pos(n, kUnplaced);
    std::vector<uint8_t> colour(n * std::size_t(ch));
    // Each block's place in the output, and in the example once it is
    // laid (sx < 0: not yet).
    struct Source {
        int sx, sy;
    };
    const auto origin = [&](std::size_t k) { return block_origin(int(k), nx, ny, width, height); };
    std::vector<Source> source(std::size_t(count), Source{-1, -1});
    // Which blocks are laid at once: in raster order one after the other;
    // in wavefront order any that are ready, each on a thread of its own
    // with a search of its own, as many as the searches' memory allows.
    // The search by transforms is used when it fits `search_memory`, the
    // direct search otherwise (the same places).
    const auto fits = [&](int searches, bool pairs_at_once) {
        return layout_memory(example.width, example.height, ch, B, searches, pairs_at_once) <= search_memory;
    };
    int workers = 1;
    if (order == QuiltOrder::kWavefront)
        while (workers < std::min({std::max(threads, 1), count, kQuiltWorkers}) && fits(workers + 1, false)) ++workers;
    const bool pairs_at_once = workers == 1 && fits(1, true);
    const QuiltExample shared_example(example, B,
                                      workers > 1 || fits(1, false) ? QuiltExample::Method::kTransform
                                                                    : QuiltExample::Method::kDirect);
    struct Worker {
        std::vector<std::pair<int, int>> excluded;
        std::vector<uint8_t> old;
        std::vector<int> node;
        std::vector<QuiltRun> runs;
        std::vector<uint32_t> near;
        std::unique_ptr<QuiltSearch> search;
        MinCut cut;
        PlanarCut planar;
        std::vector<int64_t> own_at, columns, rows;
        std::vector<uint8_t> unplaced;
        std::vector<std::size_t> columns_at, rows_at;
    };
    std::vector<Worker> pool(static_cast<std::size_t>(workers));
    for (Worker& wk : pool) {
        wk.old.resize(std::size_t(B) * std::size_t(B) * std::size_t(ch));
        wk.node.resize(std::size_t(B) * std::size_t(B));
        wk.search = std::make_unique<QuiltSearch>(shared_example, pairs_at_once);
    }
    // A block's search shares the threads only when blocks are laid one at
    // a time.
    const int inner_threads = workers == 1 ? threads : 1;
    // The output's index of (xo + dx, yo + dy) for dx, dy from -1 to B,
    // around the torus: a block's columns and rows wrapped once.
    const auto wrap_block = [&](Worker& w, int xo, int yo) {
        w.columns_at.resize(std::size_t(B) + 2);
        w.rows_at.resize(std::size_t(B) + 2);
        for (int d = -1; d <= B; ++d) {
            w.columns_at[std::size_t(d + 1)] = std::size_t(Image::wrap(xo + d, width));
            w.rows_at[std::size_t(d + 1)] = std::size_t(Image::wrap(yo + d, height)) * std::size_t(width);
        }
    };
    // One pixel's squared colour distance.
    const auto d2 = [&](const uint8_t* a, const uint8_t* b) { return int64_t(dsp::ssd_bytes(a, b, std::size_t(ch))); };
    // Lays block k (k = bj * nx + bi): reads and writes the output only
    // within the block and the ring of pixels around it.
    const auto lay = [&](int k, Worker& w) {
        std::vector<std::pair<int, int>>& excluded = w.excluded;
        std::vector<uint8_t>& old = w.old;
        std::vector<int>& node = w.node;
        std::vector<QuiltRun>& runs = w.runs;
        std::vector<uint32_t>& near = w.near;
        MinCut& cut = w.cut;
        const int bi = k % nx, bj = k / nx;
        const int xo = origin(std::size_t(k)).first, yo = origin(std::size_t(k)).second;
        wrap_block(w, xo, yo);
        const auto out_index = [&](int dx, int dy) {
            return w.rows_at[std::size_t(dy + 1)] + w.columns_at[std::size_t(dx + 1)];
        };
        // What the output already holds under the block, row by row in
        // runs, and its colours.
        runs.clear();
        int placed = 0;
        for (int dy = 0; dy < B; ++dy) {
            int start = -1;
            for (int dx = 0; dx < B; ++dx) {
                const std::size_t i = out_index(dx, dy);
                const bool known = pos[i] != kUnplaced;
                node[std::size_t(dy) * std::size_t(B) + std::size_t(dx)] = known ? placed++ : -1;
                if (known) {
                    std::copy_n(colour.data() + i * std::size_t(ch), ch,
                                old.data() + (std::size_t(dy) * std::size_t(B) + std::size_t(dx)) * std::size_t(ch));
                    if (start < 0) start = dx;
                } else if (start >= 0) {
                    runs.push_back({dy, start, dx - start});
                    start = -1;
                }
            }
            if (start >= 0) runs.push_back({dy, start, B - start});
        }
        // The places where an overlapping block's copy would simply go
        // on: excluded, or the output would be the example again.
        excluded.clear();
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                if (!di && !dj) continue;
                const int ii = (bi + di + nx) % nx, jj = (bj + dj + ny) % ny;
                const std::size_t m = std::size_t(jj) * std::size_t(nx) + std::size_t(ii);
                // The other block's place relative to this one's, the
                // nearer way round the torus. Only a block that overlaps
                // this one is read: it is placed before it or after it,
                // never at the same time.
                int ox = Image::wrap(origin(m).first - xo, width), oy = Image::wrap(origin(m).second - yo, height);
                if (ox > width / 2) ox -= width;
                if (oy > height / 2) oy -= height;
                if (ox <= -B || ox >= B || oy <= -B || oy >= B) continue;
                const Source& o = source[m];
                if (o.sx < 0) continue;
                excluded.push_back({o.sx - ox, o.sy - oy});
            }
        const uint64_t salt = mix64(seed ^ mix64((uint64_t(bj) << 32) | uint64_t(bi)));
        int sx = 0, sy = 0;
        if (runs.empty()) {
            sx = int(salt % uint64_t(cx));
            sy = int((salt >> 32) % uint64_t(cy));
        } else {
            w.search->near_places(runs, old.data(), excluded, inner_threads, near);
            // The near-best places, in raster order; the seed picks one.
            if (near.empty()) fail(VQTEX_ERROR_INTERNAL, "quilting found no place for a block");
            const uint32_t at = near[std::size_t(salt % near.size())];
            sx = int(at % uint32_t(cx));
            sy = int(at / uint32_t(cx));
        }
        source[std::size_t(k)] = {sx, sy};
        // The patch insertion cut over the placed pixels: the source
        // side keeps the output as it is, the sink side takes the new
        // block. Between two neighbours on different sides the seam
        // costs how much old and new differ at both (Kwatra et al.'s
        // cost); a pixel next to one of the block that is not placed yet
        // (which will be new) pays its own difference if it stays old;
        // one next to a placed pixel outside the block (which stays old)
        // pays both differences if it turns new.
        const auto fresh = [&](int dx, int dy) { return example.at(sx + dx, sy + dy); };
        const auto was = [&](int dx, int dy) {
            return old.data() + (std::size_t(dy) * std::size_t(B) + std::size_t(dx)) * std::size_t(ch);
        };
        // Whether the planar cut decided the sides (else the maximum flow).
        bool planar = false;
        if (placed > 0) {
            // What a cut between two neighbours costs (0 where it cannot
            // be between old and new): across the block's columns x =
            // 0..B between pixels (x - 1, y) and (x, y), across its rows
            // likewise; the block's outer lines hold the arcs from the
            // placed pixels around it.
            const std::size_t b = std::size_t(B), lattice = b + 1;
            std::vector<uint8_t>& unplaced = w.unplaced;
            std::vector<int64_t>& columns = w.columns;
            std::vector<int64_t>& rows = w.rows;
            std::vector<int64_t>& own_at = w.own_at;
            unplaced.resize(b * b);
            own_at.resize(b * b);
            columns.resize(lattice * b);
            rows.resize(b * lattice);
            // Each placed pixel's own difference, 0 for the others.
            for (int dy = 0; dy < B; ++dy)
                for (int dx = 0; dx < B; ++dx) {
                    const std::size_t i = std::size_t(dy) * b + std::size_t(dx);
                    unplaced[i] = node[i] < 0;
                    own_at[i] = node[i] < 0 ? 0 : d2(fresh(dx, dy), was(dx, dy));
                }
            // The arc into placed pixel (dx, dy) from (ex, ey) outside the
            // block, when that is placed: both differences.
            const auto arc_in = [&](int dx, int dy, int ex, int ey) {
                if (node[std::size_t(dy) * b + std::size_t(dx)] < 0) return int64_t(0);
                const std::size_t j = out_index(ex, ey);
                if (pos[j] == kUnplaced) return int64_t(0);
                const int64_t here = own_at[std::size_t(dy) * b + std::size_t(dx)];
                const int X = sx + ex, Y = sy + ey;
                const bool inside = X >= 0 && Y >= 0 && X < example.width && Y < example.height;
                return here + (inside ? d2(example.at(X, Y), colour.data() + j * std::size_t(ch)) : here);
            };
            for (std::size_t y = 0; y < b; ++y) {
                const int64_t* here = own_at.data() + y * b;
                int64_t* across = columns.data() + y * lattice;
                across[0] = arc_in(0, int(y), -1, int(y));
                across[b] = arc_in(B - 1, int(y), B, int(y));
                for (std::size_t x = 1; x < b; ++x) across[x] = here[x - 1] + here[x];
            }
            for (std::size_t y = 1; y < b; ++y) {
                const int64_t* above = own_at.data() + (y - 1) * b;
                const int64_t* here = own_at.data() + y * b;
                int64_t* across = rows.data() + y * b;
                for (std::size_t x = 0; x < b; ++x) across[x] = above[x] + here[x];
            }
            for (int x = 0; x < B; ++x) {
                rows[std::size_t(x)] = arc_in(x, 0, x, -1);
                rows[b * b + std::size_t(x)] = arc_in(x, B - 1, x, B);
            }
            planar = cut_method == QuiltCut::kPlanar && w.planar.solve(B, unplaced, columns, rows);
            if (!planar) {
                // The same graph for the maximum flow: a node for each
                // placed pixel; a neighbour not placed is the sink's, one
                // outside the block the source's.
                cut.reset(placed);
                const auto join = [&](int p, int q, int64_t c) {
                    if (c == 0) return;
                    const int u = p < 0 ? -1 : node[std::size_t(p)], v = q < 0 ? -1 : node[std::size_t(q)];
                    if (u >= 0 && v >= 0) cut.add(u, v, c, c);
                    else if (u >= 0 && q >= 0) cut.add(u, cut.sink(), c, 0);
                    else if (v >= 0 && p >= 0) cut.add(v, cut.sink(), c, 0);
                    else if (u >= 0 || v >= 0) cut.add(cut.source(), u >= 0 ? u : v, c, 0);
                };
                for (int y = 0; y < B; ++y)
                    for (int x = 0; x <= B; ++x)
                        join(x > 0 ? y * B + x - 1 : -1, x < B ? y * B + x : -1, columns[std::size_t(y) * lattice + std::size_t(x)]);
                for (int y = 0; y <= B; ++y)
                    for (int x = 0; x < B; ++x)
                        join(y > 0 ? (y - 1) * B + x : -1, y < B ? y * B + x : -1, rows[std::size_t(y) * b + std::size_t(x)]);
                cut.solve();
            }
        }
        const auto keeps = [&](int dx, int dy, int v) {
            return v >= 0 && (planar ? w.planar.source_side(dx, dy) : cut.source_side(v));
        };
        for (int dy = 0; dy < B; ++dy)
            for (int dx = 0; dx < B; ++dx) {
                const int v = node[std::size_t(dy) * std::size_t(B) + std::size_t(dx)];
                // A placed pixel on the cut's source side keeps its copy.
                if (keeps(dx, dy, v)) continue;
                const std::size_t i = out_index(dx, dy);
                pos[i] = pack_position(sx + dx, sy + dy);
                std::copy_n(fresh(dx, dy), ch, colour.data() + i * std::size_t(ch));
            }
    };
    if (progress && !progress(0, uint64_t(count)))
        fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    if (workers == 1) {
        int laid = 0;
        each_in_order(nx, ny, order, [&](int k) {
            if (laid > 0 && progress && !progress(uint64_t(laid), uint64_t(count)))
                fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
            lay(k, pool[0]);
            ++laid;
        });
    } else {
        lay_in_parallel(nx, ny, width, height, B, order, workers, progress,
                        [&](int k, int worker) { lay(k, pool[std::size_t(worker)]); });
    }
    if (progress && !progress(uint64_t(count), uint64_t(count)))
        fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    return pos;
}

}  // namespace vqtex
