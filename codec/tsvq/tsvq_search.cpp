// tsvq_search.cpp - best-first TSVQ descent with limited backtracking
// (paper section 4, search).
#include "tsvq/tsvq_search.hpp"

#include <algorithm>
#include <functional>
#include <vector>

#include "dsp/dsp.hpp"
#include "common/error.hpp"

namespace vqtex {
namespace {

struct TsvqScratch final : MatchScratch {
    // Pending branches packed as (distance << 32 | node): a min-heap on this
    // key orders by distance, then by node index, so ties are deterministic.
    std::vector<uint64_t> heap;
    std::vector<std::pair<uint32_t, uint32_t>> visited;  // (distance, leaf)
    std::vector<int8_t> signed_query;                    // query bytes - 128
    std::vector<uint64_t> fresh;                         // one descent's branches (heap path)
    std::vector<uint64_t> walks;                         // both walks' branches (two_walks)
};

}  // namespace

TsvqMatcher::TsvqMatcher(std::shared_ptr<const Codebook> book, uint32_t backtrack_leaves)
    : book_(std::move(book)), backtrack_(std::max<uint32_t>(1, backtrack_leaves)) {
    if (!book_ || book_->leaf_count() == 0) fail(VQTEX_ERROR_INVALID_ARGUMENT, "empty codebook");
    depth_ = book_->depth();
    const Codebook& b = *book_;
    const std::size_t n = b.stride();
    // |q - c|^2 = |q|^2 + |c|^2 - 2 q.c, and with q = s + 128 (s signed),
    // q.c = s.c + 128 sum(c): so |q - c|^2 = |q|^2 + bias(c) - 2 s.c with
    // bias(c) = |c|^2 - 256 sum(c). Exact integers: the same distances as
    // ssd, from one unsigned-by-signed dot product per codeword.
    node_bias_.assign(b.node_count(), 0);
    first_child_.assign(b.node_count(), -1);
    node_key_.assign(b.node_count(), UINT32_MAX);
    for (std::size_t node = 0; node < b.node_count(); ++node) {
        const uint8_t* c = b.codeword(node);
        int64_t bias = 0;
        for (std::size_t d = 0; d < n; ++d) bias += int64_t(c[d]) * c[d] - 256 * int64_t(c[d]);
        node_bias_[node] = bias;
        first_child_[node] = b.node(node).first_child;
        node_key_[node] = b.node(node).leaf >= 0 ? b.leaf_key(std::size_t(b.node(node).leaf)) : UINT32_MAX;
    }
    leaf_entries_.resize(b.leaf_count());
    leaf_entry_count_.resize(b.leaf_count());
    for (std::size_t leaf = 0; leaf < b.leaf_count(); ++leaf) {
        leaf_entries_[leaf] = b.entry(leaf, 0);
        leaf_entry_count_[leaf] = uint32_t(std::min<std::size_t>(b.entry_count(leaf), kMaxEntries));
        ranked_entries_ = std::max(ranked_entries_, leaf_entry_count_[leaf]);
    }
    tree_ = dsp::DescentTree{first_child_.data(), node_bias_.data(), b.codeword(0), n};
    kernels_ = &dsp::kernels();
}

std::unique_ptr<MatchScratch> TsvqMatcher::make_scratch() const {
    auto s = std::make_unique<TsvqScratch>();
    // Each descent leaves at most one pending branch per level.
    s->heap.reserve(std::size_t(kLinearScanLeaves) * std::size_t(depth_ + 1));
    s->signed_query.resize(book_->stride());
    s->fresh.resize(std::size_t(depth_) + 1);
    s->walks.resize(2 * (std::size_t(depth_) + 1));
    return s;
}

std::size_t TsvqMatcher::search(const uint8_t* query, uint32_t leaves, MatchScratch* scratch,
                                const MatchContext& context) const {
    // Made only when the caller has none: constructing it per call (four
    // vectors) showed in profiles of the per-pixel search.
    if (!scratch) {
        const std::unique_ptr<MatchScratch> owned = make_scratch();
        return search(query, leaves, owned.get(), context);
    }
    TsvqScratch& work = *static_cast<TsvqScratch*>(scratch);
    // The default budget (the decoder's) apart from the general search,
    // whose set-up showed in the decoder's profile at every pixel.
    if (leaves == 2 && context.tolerance == 0 && first_child_[0] >= 0)
        return two_walks(query, work.signed_query.data(), work.walks.data());
    return search_general(query, std::max<uint32_t>(1, leaves), work, context);
}

std::size_t TsvqMatcher::search_general(const uint8_t* query, uint32_t leaves, MatchScratch& scratch,
                                        const MatchContext& context) const {
    const Codebook& b = *book_;
    const dsp::Kernels& k = *kernels_;
    const std::size_t n = b.stride();
    TsvqScratch& work = static_cast<TsvqScratch&>(scratch);
    work.visited.clear();
    // Pending branches are ordered by (distance, node), a total order, so a
    // heap and a linear scan for the minimum pop them in the same order. For
    // the small budgets used in synthesis the scan is cheaper than keeping a
    // heap of every branch not taken; large budgets (up to exhaustive) need
    // the heap.
    const bool use_heap = leaves > kLinearScanLeaves;
    std::vector<uint64_t>& heap = work.heap;
    // The linear path uses the buffer as a plain array (grown once, never
    // cleared); the heap path as a heap.
    if (use_heap)
        heap.clear();
    else if (const std::size_t need = std::size_t(leaves) * std::size_t(depth_ + 1) + 1; heap.size() < need)
        heap.resize(need);
    uint64_t* pending = heap.data();
    std::size_t pending_count = 0;
    const auto later = std::greater<uint64_t>();

    work.signed_query.resize(n);
    int8_t* signed_query = work.signed_query.data();
    if (use_heap) work.fresh.resize(std::size_t(depth_) + 1);

    uint32_t best_distance = UINT32_MAX, best_key = UINT32_MAX;
    std::size_t best_leaf = 0;
    // The root's own distance only matters when it is a leaf.
    uint64_t next = uint64_t(b.node(0).first_child < 0 ? k.ssd(query, b.codeword(0), n) : 0) << 32;
    for (uint32_t visited = 0;;) {
        // The linear path collects the branches not taken in place; the heap
        // path moves them from a side buffer into the heap.
        std::size_t fresh = use_heap ? 0 : pending_count;
        uint64_t lowest_unused = UINT64_MAX;  // the minimum is scanned for below: later pops need it too
        const uint64_t reached = k.descend(tree_, query, signed_query, next,
                                           use_heap ? work.fresh.data() : pending, &fresh, &lowest_unused);
        if (use_heap) {
            for (std::size_t i = 0; i < fresh; ++i) {
                heap.push_back(work.fresh[i]);
                std::push_heap(heap.begin(), heap.end(), later);
            }
        } else {
            pending_count = fresh;
        }
        const std::size_t node = std::size_t(reached & 0xFFFFFFFFu);
        const uint32_t distance = uint32_t(reached >> 32);
        const std::size_t leaf = std::size_t(b.node(node).leaf);
        const uint32_t key = node_key_[node];
        if (distance < best_distance || (distance == best_distance && key < best_key))
            best_distance = distance, best_key = key, best_leaf = leaf;
        if (context.tolerance) work.visited.emplace_back(distance, uint32_t(leaf));
        if (++visited >= leaves) break;
        if (use_heap) {
            if (heap.empty()) break;
            std::pop_heap(heap.begin(), heap.end(), later);
            next = heap.back();
            heap.pop_back();
        } else {
            if (pending_count == 0) break;
            // Branch-free minimum (the keys are distinct): which branch is
            // nearest is unpredictable.
            std::size_t lowest = 0;
            uint64_t lowest_key = pending[0];
            for (std::size_t i = 1; i < pending_count; ++i) {
                const uint64_t lower = 0 - uint64_t(pending[i] < lowest_key);
                lowest_key = (pending[i] & lower) | (lowest_key & ~lower);
                lowest = (i & lower) | (lowest & ~lower);
            }
            next = pending[lowest];
            pending[lowest] = pending[--pending_count];
        }
    }
    if (context.tolerance == 0) return best_leaf;
    const uint32_t threshold = tolerance_threshold(best_distance, context.tolerance);
    std::size_t chosen = best_leaf;
    NearTieChoice choice(context.salt, best_key);
    for (const auto& [d, leaf] : work.visited)
        if (d <= threshold && choice.offer(b.leaf_key(leaf))) chosen = leaf;
    return chosen;
}

std::size_t TsvqMatcher::two_walks(const uint8_t* query, int8_t* signed_query, uint64_t* pending) const {
    // The default budget, in short: one walk, then one more from the nearest
    // branch it passed, which the walk tracked as it went. The same leaves
    // and the same choice as search's general loop.
    const dsp::Kernels& k = *kernels_;
    std::size_t count = 0;
    uint64_t lowest = UINT64_MAX;
    const uint64_t first = k.descend(tree_, query, signed_query, 0, pending, &count, &lowest);
    uint64_t unused = UINT64_MAX;
    const uint64_t second = k.descend(tree_, query, signed_query, lowest, pending, &count, &unused);
    const std::size_t first_node = std::size_t(first & 0xFFFFFFFFu), second_node = std::size_t(second & 0xFFFFFFFFu);
    const uint32_t first_distance = uint32_t(first >> 32), second_distance = uint32_t(second >> 32);
    const bool take_second = second_distance < first_distance ||
                             (second_distance == first_distance && node_key_[second_node] < node_key_[first_node]);
    return std::size_t(book_->node(take_second ? second_node : first_node).leaf);
}

std::size_t TsvqMatcher::nearest_leaf_exhaustive(const uint8_t* query) const {
    const Codebook& b = *book_;
    const dsp::Kernels& k = dsp::kernels();
    uint32_t best_distance = UINT32_MAX, best_key = UINT32_MAX;
    std::size_t best_leaf = 0;
    for (std::size_t leaf = 0; leaf < b.leaf_count(); ++leaf) {
        const uint32_t d = k.ssd(query, b.leaf_codeword(leaf), b.stride());
        const uint32_t key = b.leaf_key(leaf);
        if (d < best_distance || (d == best_distance && key < best_key))
            best_distance = d, best_key = key, best_leaf = leaf;
    }
    return best_leaf;
}

void TsvqMatcher::rank_entries(uint64_t salt, EntryRanking& ranking) const {
    ranking.records = 1;
    if (ranked_entries_ > 1) ranking.records = kernels_->rank_candidates(salt ^ kEntrySalt, ranked_entries_, ranking.rank);
}

std::size_t TsvqMatcher::choose_entry(std::size_t leaf, const uint8_t* query, const EntryRanking& ranking) const {
    const Codebook& b = *book_;
    const std::size_t n = leaf_entry_count_[leaf];
    if (n == 1) return 0;
    // The entry whose short key is nearest the query's adjacent pixels; among
    // near-ties (within a quarter of the best plus a small absolute slack,
    // so exact local copies do not always win) the one the pixel's salt ranks
    // first. The leaf's other continuations then appear about as often as
    // they do in the example, instead of its commonest one everywhere.
    // Entries without keys all qualify: the salt alone chooses, so each
    // appears about as often as its member did in the example. (Choosing the
    // entry nearest the pixel the query's neighbours predict was tried: it
    // favours smooth continuations and the texture collapses into flat
    // blocks.)
    const auto& offsets = b.key_offsets();
    if (offsets.empty()) {
        const uint64_t below_n = ranking.records & (n < 64 ? (uint64_t(1) << n) - 1 : ~uint64_t(0));
        return std::size_t(63 - __builtin_clzll(below_n));
    }
    const dsp::Kernels& kernels = *kernels_;
    const std::size_t ch = std::size_t(b.channels()), entry_size = b.entry_size();
    uint32_t distance[kMaxEntries];
    uint32_t best = UINT32_MAX;
    for (std::size_t i = 0; i < n; ++i) {
        const uint8_t* key = leaf_entries_[leaf] + i * entry_size + ch;
        uint32_t d = 0;
        for (std::size_t k = 0; k < offsets.size(); ++k) {
            const int diff = int(key[k]) - int(query[offsets[k]]);
            d += uint32_t(diff * diff);
        }
        distance[i] = d;
        best = std::min(best, d);
    }
    const uint32_t threshold = best + best / 4 + uint32_t(4 * offsets.size());
    uint64_t qualifying = 0;
    for (std::size_t i = 0; i < n; ++i) qualifying |= uint64_t(distance[i] <= threshold) << i;
    return kernels.lowest_ranked(ranking.rank, uint32_t(n), qualifying);
}

const uint8_t* TsvqMatcher::match(const uint8_t* query, const MatchContext& context,
                                  MatchScratch* scratch) const {
    // Ranked before the search, which does not need them: the hashes then
    // run alongside the descent rather than after it, on the path from this
    // pixel to the next (whose query reads this one).
    EntryRanking ranking;
    rank_entries(context.salt, ranking);
    const std::size_t leaf = search(query, backtrack_, scratch, context);
    return leaf_entries_[leaf] + choose_entry(leaf, query, ranking) * book_->entry_size();
}

}  // namespace vqtex
