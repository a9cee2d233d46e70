// planar_cut.cpp - the minimum cut of a block's pixel grid as a shortest
// path in its dual. See planar_cut.hpp.
#include "engine/planar_cut.hpp"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <bit>
#include <utility>

namespace vqtex {

void PlanarCut::RadixHeap::clear(std::size_t capacity) {
    entry_.clear();
    next_.clear();
    entry_.reserve(capacity);
    next_.reserve(capacity);
    std::fill(std::begin(head_), std::end(head_), -1);
    filled_ = 0;
    filled_top_ = false;
    last_ = 0;
    size_ = 0;
}

void PlanarCut::RadixHeap::link(int32_t slot) {
    const int i = int(std::bit_width(entry_[std::size_t(slot)] ^ last_));
    next_[std::size_t(slot)] = head_[i];
    head_[i] = slot;
    filled_ |= i < 64 ? uint64_t(1) << i : 0;
    filled_top_ = filled_top_ || i == 64;
}

void PlanarCut::RadixHeap::push(uint64_t entry) {
    entry_.push_back(entry);
    next_.push_back(-1);
    link(int32_t(entry_.size() - 1));
    ++size_;
}

uint64_t PlanarCut::RadixHeap::pop() {
    if (head_[0] < 0) {
        // The lowest bucket that holds numbers: its least becomes the last
        // taken, and the others, which differ from it only in lower bits,
        // go to lower buckets.
        const int i = filled_ > 1 ? std::countr_zero(filled_ & ~uint64_t(1)) : 64;
        uint64_t least = UINT64_MAX;
        for (int32_t s = head_[i]; s >= 0; s = next_[std::size_t(s)]) least = std::min(least, entry_[std::size_t(s)]);
        last_ = least;
        if (i < 64)
            filled_ &= ~(uint64_t(1) << i);
        else
            filled_top_ = false;
        for (int32_t s = head_[i]; s >= 0;) {
            const int32_t after = next_[std::size_t(s)];
            link(s);
            s = after;
        }
        head_[i] = -1;
    }
    const int32_t s = head_[0];
    head_[0] = next_[std::size_t(s)];
    if (head_[0] < 0) filled_ &= ~uint64_t(1);
    --size_;
    return entry_[std::size_t(s)];
}

bool PlanarCut::solve(int side, const std::vector<uint8_t>& fresh, const std::vector<int64_t>& across_columns,
                      const std::vector<int64_t>& across_rows) {
    side_ = side;
    // The heap's entries hold a path's cost, its count of edges and a
    // point in 64 bits: at most 2^16 lattice points, and costs that sum to
    // less than 2^32 (else the maximum flow takes the block).
    if (side < 1 || side > 254) return false;
    const std::size_t n = std::size_t(side);
    // Lattice points (x, y), 0 <= x, y <= side, at p = y * row + x, one
    // spare column wide so that the pixels around a point are at fixed
    // offsets in padded_, the fresh marks with a ring of pixels that are
    // not fresh: pixel (x, y) at y * row + x + row + 1.
    const int row = side + 2;
    const std::size_t stride = std::size_t(row), points = stride * (n + 1);
    padded_.assign(stride * stride, 0);
    for (std::size_t y = 0; y < n; ++y)
        for (std::size_t x = 0; x < n; ++x) padded_[(y + 1) * stride + x + 1] = uint8_t(fresh[y * n + x] != 0);
    const auto is_fresh = [&](int x, int y) { return padded_[std::size_t(y + 1) * stride + std::size_t(x + 1)] != 0; };
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
    // The spare column and the edges off the lattice are -1, and so is the
    // edge a-b.
    right_.assign(points, -1);
    down_.assign(points, -1);
    // The sum of the costs, each taken as at most 2^32 (so that 2^17 of
    // them cannot overflow, and the sum is below 2^32 only when it is the
    // true one), and their signs: checked once at the end.
    constexpr int64_t kCap = int64_t(1) << 32;
    int64_t total = 0, signs = 0;
    const uint8_t* f = padded_.data();
    for (std::size_t y = 0; y <= n; ++y) {
        const bool edge_row = y == 0 || y == n;
        const int64_t* rows = across_rows.data() + y * n;
        const int64_t* columns = across_columns.data() + y * (n + 1);
        for (std::size_t x = 0; x <= n; ++x) {
            const std::size_t p = y * stride + x;
            if (x < n) {
                const int64_t c = rows[x];
                signs |= c;
                total += std::min(c, kCap);
                const bool above = f[p + 1], below = f[p + stride + 1];
                right_[p] = above && below ? -1 : (above || below) && edge_row ? 0 : c;
            }
            if (y < n) {
                const int64_t c = columns[x];
                signs |= c;
                total += std::min(c, kCap);
                const bool left = f[p + stride], right = f[p + stride + 1];
                down_[p] = left && right ? -1 : (left || right) && (x == 0 || x == n) ? 0 : c;
            }
        }
    }
    if (signs < 0 || total >= kCap) return false;
    (b == a + 1 ? right_ : down_)[std::size_t(a)] = -1;
    // Dijkstra's search from a to b, a path's length being its cost, then
    // its count of edges: one key, which grows along every edge, so that
    // the search can use a radix heap, and the path taken back below is
    // the same whatever order points of equal keys are taken in.
    key_.assign(points, kFar);
    // A point is pushed each time one of its four neighbours improves it.
    heap_.clear(4 * points + 1);
    key_[std::size_t(a)] = 0;
    heap_.push(uint64_t(a));
    const auto step = [](int64_t cost) { return (uint64_t(cost) << kHopBits) | 1u; };
    while (!heap_.empty()) {
        const uint64_t top = heap_.pop();
        const uint64_t k = top >> kPointBits;
        const int p = int(top & ((uint64_t(1) << kPointBits) - 1));
        if (k != key_[std::size_t(p)]) continue;
        if (p == b) break;
        // (An edge off the lattice costs -1 and is not followed, so its
        // far end is never read.)
        const auto relax = [&](int q, int64_t cost) {
            if (cost < 0 || k + step(cost) >= key_[std::size_t(q)]) return;
            key_[std::size_t(q)] = k + step(cost);
            heap_.push((k + step(cost)) << kPointBits | uint64_t(q));
        };
        relax(p + 1, right_[std::size_t(p)]);
        if (p > 0) relax(p - 1, right_[std::size_t(p - 1)]);
        relax(p + row, down_[std::size_t(p)]);
        if (p >= row) relax(p - row, down_[std::size_t(p - row)]);
    }
    cost_ = int64_t(key_[std::size_t(b)] >> kHopBits);
    // The path and the edge a-b close a simple curve around the fresh
    // pixels. Back from b, each time to the first neighbour (left, up,
    // right, down) whose key and edge make this point's: the keys fall
    // strictly along the way, so it ends at a. Only its upright edges are
    // kept: they are what a row crosses.
    crossed_.assign(points, 0);
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
        on_path(q + 1, right_[std::size_t(q)]);
        on_path(q + row, down_[std::size_t(q)]);
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
            inside ^= crossed_[y * stride + x];
            sink_[y * n + x] = inside;
        }
    }
    uint8_t outside = 0;
    for (std::size_t i = 0; i < n * n; ++i) outside = uint8_t(outside | ((fresh[i] != 0) & (sink_[i] == 0)));
    return outside == 0;
}

}  // namespace vqtex
