// tsvq_search.hpp - searching a TSVQ codebook (paper section 4): best-first
// descent with a budget of L leaves, the branches not taken kept in a
// priority queue by distance. With L >= the number of leaves the answer is
// exactly the exhaustive nearest leaf (ties to the lowest tie key).
#pragma once

#include <memory>
#include <vector>

#include "dsp/dsp.hpp"
#include "engine/matcher.hpp"
#include "tsvq/tsvq_tree.hpp"

namespace vqtex {

class TsvqMatcher final : public Matcher {
public:
    TsvqMatcher(std::shared_ptr<const Codebook> book, uint32_t backtrack_leaves);
    // tree_ points into the matcher's own arrays.
    TsvqMatcher(const TsvqMatcher&) = delete;
    TsvqMatcher& operator=(const TsvqMatcher&) = delete;
    std::size_t stride() const override { return book_->stride(); }
    std::unique_ptr<MatchScratch> make_scratch() const override;
    const uint8_t* match(const uint8_t* query, const MatchContext& context,
                         MatchScratch* scratch) const override;

    // The leaf found for `query` visiting at most `leaves` leaves: the
    // nearest visited (lowest tie key on ties), or with a tolerance the
    // visited near-tie that ranks first (see MatchContext).
    std::size_t search(const uint8_t* query, uint32_t leaves, MatchScratch* scratch,
                       const MatchContext& context = {}) const;
    // The exactly nearest leaf by brute force over all leaves (the oracle).
    std::size_t nearest_leaf_exhaustive(const uint8_t* query) const;
    // A pixel's ranking of entry indices, made from its salt before its
    // search: rank[i] = rank_hash(salt ^ kEntrySalt, i), and the record mask
    // (Kernels::rank_candidates), whose highest bit below n is the choice
    // among n entries that all qualify.
    struct EntryRanking {
        alignas(64) uint64_t rank[dsp::kMaxRanked];
        uint64_t records;
    };
    void rank_entries(uint64_t salt, EntryRanking& ranking) const;
    // Which entry of `leaf` to output for this query (see tsvq_tree.hpp).
    std::size_t choose_entry(std::size_t leaf, const uint8_t* query, const EntryRanking& ranking) const;
    static constexpr uint64_t kEntrySalt = 0x5EED;
    const Codebook& codebook() const { return *book_; }

    // Entries per leaf the search considers; more are never stored.
    static constexpr std::size_t kMaxEntries = 64;
    static_assert(kMaxEntries <= dsp::kMaxRanked, "every entry of a leaf must be rankable");
    // Up to this many leaves, pending branches are kept unsorted (see search).
    static constexpr uint32_t kLinearScanLeaves = 8;

private:
    std::shared_ptr<const Codebook> book_;
    uint32_t backtrack_;
    int depth_ = 0;
    std::vector<int64_t> node_bias_;    // per node: |c|^2 - 256 sum(c) (see search)
    std::vector<int32_t> first_child_;  // per node, as the descent kernel reads it
    // Leaf data the per-pixel path reads, without the codebook's indirections
    // (and the division entry_count() does).
    std::vector<uint32_t> node_key_;            // per node: the leaf's tie key
    std::vector<const uint8_t*> leaf_entries_;  // per leaf: its first entry
    std::vector<uint32_t> leaf_entry_count_;    // per leaf: entries considered (<= kMaxEntries)
    uint32_t ranked_entries_ = 1;               // the most entries of any leaf
    dsp::DescentTree tree_{};
    const dsp::Kernels* kernels_ = nullptr;  // dsp::kernels(), fixed for the process
    // L = 2 without near-ties (the decoder's default): one walk from the
    // root, one from the nearest branch it passed; the nearer leaf.
    // `pending` has room for 2 * (depth + 1) branches. The root must not be
    // a leaf.
    std::size_t two_walks(const uint8_t* query, int8_t* signed_query, uint64_t* pending) const;
    // Any budget, with near-ties: best-first with pending branches unsorted
    // or in a heap (search gives it a scratch and leaves >= 1).
    std::size_t search_general(const uint8_t* query, uint32_t leaves, MatchScratch& scratch,
                               const MatchContext& context) const;
};

}  // namespace vqtex
