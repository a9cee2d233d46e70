// planar_cut.cpp - the minimum cut of a block's pixel grid as a shortest
// path in its dual. See planar_cut.hpp.
#include "engine/planar_cut.hpp"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <bit>
#include <utility>

namespace vqtex {

void PlanarCut::RadixHeap::clear() {
    for (auto& bucket : buckets_) bucket.clear();
    filled_ = 0;
    filled_top_ = false;
    last_ = 0;
    size_ = 0;
}

void PlanarCut::RadixHeap::put(uint64_t entry) {
    const int i = int(std::bit_width(entry ^ last_));
    buckets_[i].push_back(entry);
    filled_ |= i < 64 ? uint64_t(1) << i : 0;
    filled_top_ = filled_top_ || i == 64;
}

void PlanarCut::RadixHeap::push(uint64_t entry) {
    put(entry);
    ++size_;
}

uint64_t PlanarCut::RadixHeap::pop() {
    if (buckets_[0].empty()) {
        // The lowest bucket that holds numbers: its least becomes the last
        // taken, and the others, which differ from it only in lower bits,
        // go to lower buckets.
        const int i = filled_ > 1 ? std::countr_zero(filled_ & ~uint64_t(1)) : 64;
        std::vector<uint64_t>& bucket = buckets_[i];
        last_ = *std::min_element(bucket.begin(), bucket.end());
        if (i < 64)
            filled_ &= ~(uint64_t(1) << i);
        else
            filled_top_ = false;
        for (uint64_t e : bucket) put(e);
        bucket.clear();
    }
    const uint64_t e = buckets_[0].back();
    buckets_[0].pop_back();
    if (buckets_[0].empty()) filled_ &= ~uint64_t(1);
    --size_;
    return e;
}

bool PlanarCut::solve(int side, const std::vector<uint8_t>& fresh, const std::vector<int64_t>& across_columns,
                      const std::vector<int64_t>& across_rows) {
    side_ = side;
    // The heap's entries hold a path's cost, its count of edges and a
    // point in 64 bits: at most 2^16 lattice points, and costs that sum to
    // less than 2^32 (else the maximum flow takes the block).
    if (side < 1 || side > 255) return false;
    const std::size_t n = std::size_t(side), lattice = n + 1;
    const int row = int(lattice);
    const auto is_fresh = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < side && y < side && fresh[std::size_t(y) * n + std::size_t(x)] != 0;
    };
    // The fresh pixel on the block's edge where the source and the sink
    // share a face: the first in a fixed order (top and bottom rows, then
    // left and right columns), and its edge, from lattice point a to b.
    int a = -1, b = -1;
    for (int x = 0; x < side && a < 0; ++x)
        for (int y : {0, side - 1})
            if (a < 0 && is_fresh(x, y)) {
                a = (y == 0 ? 0 : side) * row + x;
                b = a + 1;
            }
    for (int y = 0; y < side && a < 0; ++y)
        for (int x : {0, side - 1})
            if (a < 0 && is_fresh(x, y)) {
                a = y * row + (x == 0 ? 0 : side);
                b = a + row;
            }
    if (a < 0) return false;
    // What each lattice edge costs to cross, -1 where no cut may: right_[p]
    // from point p = (x, y) to (x + 1, y), across between pixels (x, y - 1)
    // and (x, y); down_[p] to (x, y + 1), between (x - 1, y) and (x, y).
    // The edge a-b is left out.
    right_.assign(lattice * lattice, -1);
    down_.assign(lattice * lattice, -1);
    int64_t total = 0;
    bool bounded = true;
    const auto crossing = [&](bool fresh0, bool fresh1, bool on_edge, int64_t cost) {
        bounded = bounded && cost >= 0 && cost < (int64_t(1) << 32) - total;
        total += cost;
        return fresh0 && fresh1 ? int64_t(-1) : (fresh0 || fresh1) && on_edge ? int64_t(0) : cost;
    };
    for (int y = 0; y <= side; ++y)
        for (int x = 0; x <= side; ++x) {
            const std::size_t p = std::size_t(y) * lattice + std::size_t(x);
            if (x < side)
                right_[p] = crossing(is_fresh(x, y - 1), is_fresh(x, y), y == 0 || y == side,
                                     across_rows[std::size_t(y) * n + std::size_t(x)]);
            if (y < side)
                down_[p] = crossing(is_fresh(x - 1, y), is_fresh(x, y), x == 0 || x == side,
                                    across_columns[std::size_t(y) * lattice + std::size_t(x)]);
        }
    if (!bounded) return false;
    (b == a + 1 ? right_ : down_)[std::size_t(a)] = -1;
    // Dijkstra's search from a to b, a path's length being its cost, then
    // its count of edges: one key, which grows along every edge, so that
    // the search can use a radix heap, and the path taken back below is
    // the same whatever order points of equal keys are taken in.
    key_.assign(lattice * lattice, kFar);
    heap_.clear();
    key_[std::size_t(a)] = 0;
    heap_.push(uint64_t(a));
    const auto step = [](int64_t cost) { return (uint64_t(cost) << kHopBits) | 1u; };
    const int points = row * row;
    while (!heap_.empty()) {
        const uint64_t top = heap_.pop();
        const uint64_t k = top >> kPointBits;
        const int p = int(top & ((uint64_t(1) << kPointBits) - 1));
        if (k != key_[std::size_t(p)]) continue;
        if (p == b) break;
        const auto relax = [&](int q, int64_t cost) {
            if (cost < 0 || k + step(cost) >= key_[std::size_t(q)]) return;
            key_[std::size_t(q)] = k + step(cost);
            heap_.push((k + step(cost)) << kPointBits | uint64_t(q));
        };
        // A point at the end of a row has no edge right, one on the last
        // row none down: those entries are -1.
        relax(p + 1 < points ? p + 1 : p, right_[std::size_t(p)]);
        if (p > 0) relax(p - 1, right_[std::size_t(p - 1)]);
        relax(p + row < points ? p + row : p, down_[std::size_t(p)]);
        if (p >= row) relax(p - row, down_[std::size_t(p - row)]);
    }
    cost_ = int64_t(key_[std::size_t(b)] >> kHopBits);
    // The path and the edge a-b close a simple curve around the fresh
    // pixels. Back from b, each time to the first neighbour (left, up,
    // right, down) whose key and edge make this point's: the keys fall
    // strictly along the way, so it ends at a. Only its upright edges are
    // kept: they are what a row crosses.
    crossed_.assign(lattice * n, 0);
    if (b == a + row) crossed_[std::size_t(a)] = 1;
    for (int q = b; q != a;) {
        int from = -1;
        const auto on_path = [&](int p, int64_t cost) {
            if (from < 0 && cost >= 0 && key_[std::size_t(p)] != kFar &&
                key_[std::size_t(p)] + step(cost) == key_[std::size_t(q)])
                from = p;
        };
        if (q > 0) on_path(q - 1, right_[std::size_t(q - 1)]);
        if (q >= row) on_path(q - row, down_[std::size_t(q - row)]);
        if (q + 1 < points) on_path(q + 1, right_[std::size_t(q)]);
        if (q + row < points) on_path(q + row, down_[std::size_t(q)]);
        if (from == q - row || from == q + row) crossed_[std::size_t(std::min(from, q))] = 1;
        q = from;
    }
    // A pixel is inside the curve, and new, when a row from the block's
    // left edge to it crosses the curve an odd number of times. Every
    // fresh pixel must be: fresh pixels apart from the one on the edge may
    // have been left outside.
    sink_.resize(n * n);
    for (std::size_t y = 0; y < n; ++y) {
        uint8_t inside = 0;
        for (std::size_t x = 0; x < n; ++x) {
            inside ^= crossed_[y * lattice + x];
            sink_[y * n + x] = inside;
            if (fresh[y * n + x] && !inside) return false;
        }
    }
    return true;
}

}  // namespace vqtex
