// min_cut.cpp - Boykov and Kolmogorov's maximum flow and the minimum cut it
// gives. See min_cut.hpp.
#include "engine/min_cut.hpp"

#include <algorithm>
#include <cstdint>

namespace vqtex {

void MinCut::reset(int nodes) {
    n_ = nodes;
    const std::size_t n = std::size_t(nodes) + 2;
    head_.assign(n, -1);
    tree_.assign(n, kFree);
    parent_.assign(n, -1);
    reached_.assign(n, 0);
    stamp_.assign(n, 0);
    time_ = 1;
    edges_.clear();
    active_.clear();
    orphans_.clear();
    active_at_ = 0;
}

void MinCut::add(int a, int b, int64_t ab, int64_t ba) {
    edges_.push_back({b, head_[std::size_t(a)], ab});
    head_[std::size_t(a)] = int(edges_.size()) - 1;
    edges_.push_back({a, head_[std::size_t(b)], ba});
    head_[std::size_t(b)] = int(edges_.size()) - 1;
}

int MinCut::parent_node(int v) const {
    const int e = parent_[std::size_t(v)];
    // An edge's tail is its reverse edge's head (edges come in pairs e, e^1).
    return tree_[std::size_t(v)] == kSourceTree ? edges_[std::size_t(e ^ 1)].to : edges_[std::size_t(e)].to;
}

// Whether v's chain of parents still reaches its tree's root; the nodes of
// a chain that does are stamped, so that later walks stop at them.
bool MinCut::rooted(int v) {
    const int root = tree_[std::size_t(v)] == kSourceTree ? source() : sink();
    int u = v;
    while (u != root && stamp_[std::size_t(u)] != time_) {
        if (parent_[std::size_t(u)] < 0) return false;
        u = parent_node(u);
    }
    for (u = v; u != root && stamp_[std::size_t(u)] != time_; u = parent_node(u)) stamp_[std::size_t(u)] = time_;
    return true;
}

// Grows the trees from their active nodes until they touch; returns the
// edge from the source tree to the sink tree with capacity left, or -1
// when they cannot grow any more.
int MinCut::grow() {
    while (active_at_ < active_.size()) {
        const int p = active_[active_at_];
        const int8_t t = tree_[std::size_t(p)];
        if (t != kFree) {
            for (int e = head_[std::size_t(p)]; e >= 0; e = edges_[std::size_t(e)].next) {
                // The edge that carries flow towards the sink: p -> q from
                // the source tree, q -> p into the sink tree.
                const int toward = t == kSourceTree ? e : (e ^ 1);
                if (edges_[std::size_t(toward)].cap <= 0) continue;
                const int q = edges_[std::size_t(e)].to;
                if (tree_[std::size_t(q)] == kFree) {
                    tree_[std::size_t(q)] = t;
                    parent_[std::size_t(q)] = toward;
                    active_.push_back(q);
                } else if (tree_[std::size_t(q)] != t) {
                    return toward;  // p stays active
                }
            }
        }
        ++active_at_;
    }
    return -1;
}

// Pushes the bottleneck along source root ... bridge ... sink root; the
// nodes whose parent edge it saturates become orphans.
int64_t MinCut::augment(int bridge) {
    const int a = edges_[std::size_t(bridge ^ 1)].to, b = edges_[std::size_t(bridge)].to;
    int64_t d = edges_[std::size_t(bridge)].cap;
    for (int v = a; v != source(); v = parent_node(v)) d = std::min(d, edges_[std::size_t(parent_[std::size_t(v)])].cap);
    for (int v = b; v != sink(); v = parent_node(v)) d = std::min(d, edges_[std::size_t(parent_[std::size_t(v)])].cap);
    const auto carry = [&](int e) {
        edges_[std::size_t(e)].cap -= d;
        edges_[std::size_t(e ^ 1)].cap += d;
    };
    carry(bridge);
    for (int end : {a, b}) {
        const int root = end == a ? source() : sink();
        for (int v = end; v != root;) {
            const int e = parent_[std::size_t(v)];
            const int up = parent_node(v);
            carry(e);
            if (edges_[std::size_t(e)].cap == 0) {
                parent_[std::size_t(v)] = -1;
                orphans_.push_back(v);
            }
            v = up;
        }
    }
    return d;
}

// Finds each orphan a new parent in its tree, or frees it: its children
// become orphans and its neighbours that could take it in become active.
void MinCut::adopt() {
    while (!orphans_.empty()) {
        const int v = orphans_.back();
        orphans_.pop_back();
        const int8_t t = tree_[std::size_t(v)];
        int found = -1;
        for (int e = head_[std::size_t(v)]; e >= 0 && found < 0; e = edges_[std::size_t(e)].next) {
            const int u = edges_[std::size_t(e)].to;
            const int toward = t == kSourceTree ? (e ^ 1) : e;  // u -> v, or v -> u
            if (tree_[std::size_t(u)] == t && edges_[std::size_t(toward)].cap > 0 && rooted(u)) found = toward;
        }
        if (found >= 0) {
            parent_[std::size_t(v)] = found;
            continue;
        }
        for (int e = head_[std::size_t(v)]; e >= 0; e = edges_[std::size_t(e)].next) {
            const int u = edges_[std::size_t(e)].to;
            if (tree_[std::size_t(u)] != t) continue;
            const int toward = t == kSourceTree ? (e ^ 1) : e;
            if (edges_[std::size_t(toward)].cap > 0) active_.push_back(u);
            if (parent_[std::size_t(u)] >= 0 && parent_node(u) == v) {
                parent_[std::size_t(u)] = -1;
                orphans_.push_back(u);
            }
        }
        tree_[std::size_t(v)] = kFree;
        // Its subtree's chains are broken: every stamp is stale.
        ++time_;
    }
}

int64_t MinCut::solve() {
    tree_[std::size_t(source())] = kSourceTree;
    tree_[std::size_t(sink())] = kSinkTree;
    active_ = {source(), sink()};
    int64_t flow = 0;
    for (int bridge; (bridge = grow()) >= 0;) {
        flow += augment(bridge);
        ++time_;
        adopt();
    }
    // The source side: what the residual graph still reaches.
    std::vector<int> queue{source()};
    reached_[std::size_t(source())] = 1;
    for (std::size_t q = 0; q < queue.size(); ++q)
        for (int e = head_[std::size_t(queue[q])]; e >= 0; e = edges_[std::size_t(e)].next) {
            const Edge& ed = edges_[std::size_t(e)];
            if (ed.cap > 0 && !reached_[std::size_t(ed.to)]) {
                reached_[std::size_t(ed.to)] = 1;
                queue.push_back(ed.to);
            }
        }
    return flow;
}

}  // namespace vqtex
