// min_cut.hpp - a minimum s-t cut on a small graph, for the patch
// insertion cut of image quilting (Kwatra, Schödl, Essa, Turk, Bobick 2003,
// "Graphcut textures", section 3), by the maximum flow of Boykov and
// Kolmogorov 2004 ("An experimental comparison of min-cut/max-flow
// algorithms for energy minimization in vision"): two search trees grown
// from the source and the sink and kept between augmentations, which on
// the grid graphs of an image overlap beats re-searching from scratch.
//
// Capacities are exact integers, and the cut returned is the set of nodes
// the residual graph still reaches from the source after the maximum flow:
// the same set for every maximum flow, so the result is a function of the
// graph alone, on every run and build.
#pragma once

#include <cstdint>
#include <vector>

namespace vqtex {

class MinCut {
public:
    // `nodes` nodes besides the source and the sink.
    explicit MinCut(int nodes = 0) { reset(nodes); }
    // An empty graph of `nodes` nodes, keeping the memory of the last.
    void reset(int nodes);
    int source() const { return n_; }
    int sink() const { return n_ + 1; }
    // An edge a -> b of capacity ab and b -> a of capacity ba (both >= 0).
    void add(int a, int b, int64_t ab, int64_t ba);
    // Runs the maximum flow; returns its value (the cut's cost).
    int64_t solve();
    // After solve(): whether node v stays with the source.
    bool source_side(int v) const { return reached_[std::size_t(v)] != 0; }

private:
    // The edges as added, turned into arcs grouped by their tail (arcs of
    // one node side by side: a node's arcs are read together) when solve()
    // starts; rev is the index of the arc back.
    struct Added {
        int a, b;
        int64_t ab, ba;
    };
    struct Arc {
        int to, rev;
        int64_t cap;
    };
    enum : int8_t { kFree = 0, kSourceTree = 1, kSinkTree = 2 };
    void build_arcs();
    void activate(int v);
    bool rooted(int v);
    int grow();
    int64_t augment(int bridge);
    void adopt();
    int n_;
    std::vector<Added> added_;
    std::vector<Arc> arcs_;
    std::vector<int> first_;  // node v's arcs: first_[v] .. first_[v + 1]
    std::vector<int8_t> tree_;
    // A node's parent in its tree (-1 for a root, a free node or an
    // orphan), and the arc that joins them, carrying flow towards the
    // sink: parent -> node in the source tree, node -> parent in the sink
    // tree. The parent is kept beside the arc so that a walk to the root
    // reads one value a step.
    std::vector<int> parent_, parent_arc_;
    std::vector<int> active_, orphans_;
    // Nodes found rooted since the trees last lost a node (stamp_ ==
    // time_), so that a walk to the root stops at them (Boykov &
    // Kolmogorov's timestamps).
    std::vector<int> stamp_;
    int time_ = 1;
    std::size_t active_at_ = 0;
    std::vector<char> reached_;
    // Whether a node is on the active list (its front not taken yet).
    std::vector<char> queued_;
};

}  // namespace vqtex
