// min_cut.cpp - Boykov and Kolmogorov's maximum flow and the minimum cut it
// gives. See min_cut.hpp.
#include "engine/min_cut.hpp"

#include <algorithm>
#include <cstdint>

namespace vqtex {

void MinCut::reset(int nodes) {
    n_ = nodes;
    const std::size_t n = std::size_t(nodes) + 2;
    tree_.assign(n, kFree);
    parent_.assign(n, -1);
    parent_arc_.assign(n, -1);
    reached_.assign(n, 0);
    queued_.assign(n, 0);
    stamp_.assign(n, 0);
    time_ = 1;
    added_.clear();
    arcs_.clear();
    active_.clear();
    orphans_.clear();
    active_at_ = 0;
}

void MinCut::add(int a, int b, int64_t ab, int64_t ba) { added_.push_back({a, b, ab, ba}); }

void MinCut::build_arcs() {
    const std::size_t n = std::size_t(n_) + 2;
    first_.assign(n + 1, 0);
    for (const Added& e : added_) {
        ++first_[std::size_t(e.a) + 1];
        ++first_[std::size_t(e.b) + 1];
    }
    for (std::size_t v = 0; v < n; ++v) first_[v + 1] += first_[v];
    arcs_.resize(std::size_t(first_[n]));
    std::vector<int> at(first_.begin(), first_.end() - 1);
    for (const Added& e : added_) {
        const int i = at[std::size_t(e.a)]++, j = at[std::size_t(e.b)]++;
        arcs_[std::size_t(i)] = {e.b, j, e.ab};
        arcs_[std::size_t(j)] = {e.a, i, e.ba};
    }
}

// Whether v's chain of parents still reaches its tree's root; the nodes of
// a chain that does are stamped, so that later walks stop at them.
bool MinCut::rooted(int v) {
    const int root = tree_[std::size_t(v)] == kSourceTree ? source() : sink();
    int u = v;
    while (u != root && stamp_[std::size_t(u)] != time_) {
        u = parent_[std::size_t(u)];
        if (u < 0) return false;
    }
    for (u = v; u != root && stamp_[std::size_t(u)] != time_; u = parent_[std::size_t(u)]) stamp_[std::size_t(u)] = time_;
    return true;
}

// Grows the trees from their active nodes until they touch; returns the
// arc from the source tree to the sink tree with capacity left, or -1
// when they cannot grow any more.
void MinCut::activate(int v) {
    if (queued_[std::size_t(v)]) return;
    queued_[std::size_t(v)] = 1;
    // The list holds each node once at most; what was taken off its front
    // is dropped once it is as long as the rest can be, so that it stays
    // within twice the nodes.
    if (active_at_ > 0 && active_at_ >= queued_.size()) {
        active_.erase(active_.begin(), active_.begin() + std::ptrdiff_t(active_at_));
        active_at_ = 0;
    }
    active_.push_back(v);
}

int MinCut::grow() {
    while (active_at_ < active_.size()) {
        const int p = active_[active_at_];
        const int8_t t = tree_[std::size_t(p)];
        if (t != kFree) {
            for (int a = first_[std::size_t(p)], end = first_[std::size_t(p) + 1]; a < end; ++a) {
                // The arc that carries flow towards the sink: p -> q from
                // the source tree, q -> p into the sink tree.
                const int toward = t == kSourceTree ? a : arcs_[std::size_t(a)].rev;
                if (arcs_[std::size_t(toward)].cap <= 0) continue;
                const int q = arcs_[std::size_t(a)].to;
                if (tree_[std::size_t(q)] == kFree) {
                    tree_[std::size_t(q)] = t;
                    parent_[std::size_t(q)] = p;
                    parent_arc_[std::size_t(q)] = toward;
                    activate(q);
                } else if (tree_[std::size_t(q)] != t) {
                    return toward;  // p stays active
                }
            }
        }
        queued_[std::size_t(p)] = 0;
        ++active_at_;
    }
    return -1;
}

// Pushes the bottleneck along source root ... bridge ... sink root; the
// nodes whose parent arc it saturates become orphans.
int64_t MinCut::augment(int bridge) {
    const int a = arcs_[std::size_t(arcs_[std::size_t(bridge)].rev)].to, b = arcs_[std::size_t(bridge)].to;
    int64_t d = arcs_[std::size_t(bridge)].cap;
    for (int v = a; v != source(); v = parent_[std::size_t(v)])
        d = std::min(d, arcs_[std::size_t(parent_arc_[std::size_t(v)])].cap);
    for (int v = b; v != sink(); v = parent_[std::size_t(v)])
        d = std::min(d, arcs_[std::size_t(parent_arc_[std::size_t(v)])].cap);
    const auto carry = [&](int e) {
        Arc& arc = arcs_[std::size_t(e)];
        arc.cap -= d;
        arcs_[std::size_t(arc.rev)].cap += d;
        return arc.cap;
    };
    carry(bridge);
    for (int end : {a, b}) {
        const int root = end == a ? source() : sink();
        for (int v = end; v != root;) {
            const int up = parent_[std::size_t(v)];
            if (carry(parent_arc_[std::size_t(v)]) == 0) {
                parent_[std::size_t(v)] = -1;
                parent_arc_[std::size_t(v)] = -1;
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
        const int begin = first_[std::size_t(v)], end = first_[std::size_t(v) + 1];
        int found = -1, from = -1;
        for (int a = begin; a < end && found < 0; ++a) {
            const int u = arcs_[std::size_t(a)].to;
            const int toward = t == kSourceTree ? arcs_[std::size_t(a)].rev : a;  // u -> v, or v -> u
            if (tree_[std::size_t(u)] == t && arcs_[std::size_t(toward)].cap > 0 && rooted(u)) {
                found = toward;
                from = u;
            }
        }
        if (found >= 0) {
            parent_[std::size_t(v)] = from;
            parent_arc_[std::size_t(v)] = found;
            continue;
        }
        for (int a = begin; a < end; ++a) {
            const int u = arcs_[std::size_t(a)].to;
            if (tree_[std::size_t(u)] != t) continue;
            const int toward = t == kSourceTree ? arcs_[std::size_t(a)].rev : a;
            if (arcs_[std::size_t(toward)].cap > 0) activate(u);
            if (parent_[std::size_t(u)] == v) {
                parent_[std::size_t(u)] = -1;
                parent_arc_[std::size_t(u)] = -1;
                orphans_.push_back(u);
            }
        }
        tree_[std::size_t(v)] = kFree;
        // Its subtree's chains are broken: every stamp is stale.
        ++time_;
    }
}

int64_t MinCut::solve() {
    build_arcs();
    tree_[std::size_t(source())] = kSourceTree;
    tree_[std::size_t(sink())] = kSinkTree;
    activate(source());
    activate(sink());
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
        for (int a = first_[std::size_t(queue[q])], end = first_[std::size_t(queue[q]) + 1]; a < end; ++a) {
            const Arc& arc = arcs_[std::size_t(a)];
            if (arc.cap > 0 && !reached_[std::size_t(arc.to)]) {
                reached_[std::size_t(arc.to)] = 1;
                queue.push_back(arc.to);
            }
        }
    return flow;
}

}  // namespace vqtex
