// planar_cut.hpp - the patch insertion cut of image quilting (Kwatra,
// Schödl, Essa, Turk, Bobick 2003, "Graphcut textures", section 3) found as
// a shortest path in the dual of the block's pixel grid, for blocks whose
// new pixels reach the block's edge.
//
// A block's pixels form a planar grid. Its pixels that will be new (not
// laid yet) are tied together by edges no cut may cross; the source's arcs
// come in from outside across the block's edge. When a new pixel lies on
// the edge, the source and the sink share a face of the plane graph, and a
// minimum cut is then a shortest path between the two sides of that face in
// the dual graph (Itai & Shiloach 1979; Reif 1983, for the general case):
// the dual's vertices are the grid's lattice points, and each lattice edge
// costs what the grid edge it crosses holds. Dijkstra's search over about
// (side + 1)^2 points replaces a maximum flow whose augmenting paths run
// the length of the block: several times faster on quilting's blocks, and
// the same cost.
//
// Among minimum cuts of equal cost the one returned is fixed by the costs
// alone (the shortest path with the fewest edges, then a fixed walk back
// from its end; docs/FORMAT.md §4.18), so it is the same on every run and
// build; it need not be the one a maximum flow returns.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace vqtex {

class PlanarCut {
public:
    // The graph of a side x side block: `fresh` (side^2, row major) marks
    // the pixels that must be new; `across_columns` ((side + 1) x side)
    // holds, for x = 0..side and y < side, the cost of cutting between
    // pixels (x - 1, y) and (x, y), where x = 0 and x = side are the
    // source's arcs across the block's left and right edges (0: none);
    // `across_rows` (side x (side + 1)) likewise between (x, y - 1) and
    // (x, y), for y = 0..side. Costs are >= 0; those between two fresh
    // pixels, and of arcs into a fresh pixel, weigh nothing (no cut crosses
    // the first, every cut the second). Returns false, leaving the sides
    // unset, when the shortest path does not apply (a maximum flow then
    // finds the cut): no fresh pixel on the block's edge, a fresh pixel
    // left outside the path (the fresh pixels apart), a side above 254, or
    // costs that sum to 2^32 or more.
    bool solve(int side, const std::vector<uint8_t>& fresh, const std::vector<int64_t>& across_columns,
               const std::vector<int64_t>& across_rows);
    // After solve() returned true: the cut's cost, and whether pixel
    // (x, y) stays with the source (keeps what was there).
    int64_t cost() const { return cost_; }
    bool source_side(int x, int y) const { return !sink_[std::size_t(y) * std::size_t(side_) + std::size_t(x)]; }

private:
    // A queue of 64-bit numbers that only grow from the least taken (a
    // radix heap: Ahuja, Mehlhorn, Orlin, Tarjan 1990, "Faster algorithms
    // for the shortest path problem"): a number waits in the bucket of the
    // highest bit in which it differs from the last one taken, so that
    // taking the least touches each a few times at most instead of log(n)
    // times.
    class RadixHeap {
    public:
        // Empty, with room for `capacity` pushes.
        void clear(std::size_t capacity);
        bool empty() const { return size_ == 0; }
        void push(uint64_t entry);
        uint64_t pop();

    private:
        void link(int32_t slot);
        // The numbers pushed, each in a slot of its own, and each bucket a
        // list through them (-1 ends it): the memory is the pushes', never
        // 65 buckets' worth.
        std::vector<uint64_t> entry_;
        std::vector<int32_t> next_;
        int32_t head_[65];
        // Which of buckets 0 to 63 hold numbers, and whether bucket 64 does.
        uint64_t filled_ = 0;
        bool filled_top_ = false;
        uint64_t last_ = 0;
        std::size_t size_ = 0;
    };
    // A path's key, cost << kHopBits | edges, and a heap entry, key <<
    // kPointBits | lattice point: 32 bits of cost, 16 of edges and 16 of
    // point.
    static constexpr int kHopBits = 16, kPointBits = 16;
    static constexpr uint64_t kFar = UINT64_MAX;
    int side_ = 0;
    int64_t cost_ = 0;
    std::vector<int64_t> right_, down_;
    std::vector<uint64_t> key_;
    // The curve's upright edges (lattice x, y to x, y + 1), and the new
    // pixels.
    std::vector<uint8_t> padded_, crossed_, sink_;
    RadixHeap heap_;
};

}  // namespace vqtex
