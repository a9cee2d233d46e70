// descent.hpp - the TSVQ descent (paper section 4, search) and the other
// per-pixel helpers as kernel templates. Each instruction-set file
// instantiates them with its own inline dot2, so the per-level step has no
// indirect call, and every set gives the same answer (the arithmetic is exact
// integers, the decisions identical).
//
// Everything here has internal linkage (an unnamed namespace): each file
// compiles its own copy with its own instruction-set flags. An inline
// function with external linkage would be emitted by every file, and the
// linker would keep one of them, possibly one with AVX-512 instructions, for
// the scalar set too.
#pragma once

#include <cstddef>
#include <cstdint>

#include "dsp/dsp.hpp"

namespace vqtex::dsp::detail {
namespace {

// Distance from the query to a codeword, from its dot product with the
// signed query (see DescentTree::bias). Wraps to 32 bits as the callers'
// formula does.
inline uint32_t descent_distance(int64_t query_norm, int64_t bias, int32_t dot) {
    return uint32_t(query_norm + bias - 2 * int64_t(dot));
}

// The walk of Kernels::descend, which every set shares: from `start` into
// the nearer of siblings a and a + 1 (the first on ties) until a leaf, the
// other queued as pending (distance << 32 | node) and the least pending kept.
// pair_distances(a, d) gives the distances to a and a + 1 in d[0], d[1]. GCC
// compiles the choice of child to a branch, and that is the fast form: the
// core starts on the predicted child's pair before the comparison is known,
// which hides the step's latency whenever the guess is right. Measured on the
// decoder: a branch-free form (min, max and an index add) was 40% slower, and
// computing two levels per step (the pairs under both children alongside the
// children) no faster.
template <class PairDistances>
VQTEX_DSP_INLINE uint64_t walk_to_leaf(const int32_t* first_child, uint64_t start, uint64_t* pending,
                                       std::size_t* pending_count, uint64_t* lowest_pending,
                                       PairDistances pair_distances) {
    std::size_t count = *pending_count;
    uint64_t lowest = *lowest_pending;
    std::size_t node = std::size_t(start & 0xFFFFFFFFu);
    uint32_t distance = uint32_t(start >> 32);
    for (int32_t first = first_child[node]; first >= 0; first = first_child[node]) {
        const std::size_t a = std::size_t(first);
        uint32_t d[2];
        pair_distances(a, d);
        const bool take_first = d[0] <= d[1];
        node = take_first ? a : a + 1;
        distance = take_first ? d[0] : d[1];
        const uint64_t other = take_first ? (uint64_t(d[1]) << 32 | (a + 1)) : (uint64_t(d[0]) << 32 | a);
        pending[count++] = other;
        lowest = other < lowest ? other : lowest;
    }
    *pending_count = count;
    *lowest_pending = lowest;
    return uint64_t(distance) << 32 | node;
}

// Kernels::descend from a set's dot2 and prepare_query (Dot2(query, pair, n,
// out) and Prepare(query, signed_query, n), its exact kernels).
template <class Dot2, class Prepare>
inline uint64_t descend_tree(const DescentTree& tree, const uint8_t* query, int8_t* signed_query,
                             uint64_t start, uint64_t* pending, std::size_t* pending_count,
                             uint64_t* lowest_pending, Dot2 dot2,
                             Prepare prepare_query) {
    const int64_t query_norm = prepare_query(query, signed_query, tree.stride);
    const int64_t* bias = tree.bias;
    const std::size_t n = tree.stride;
    return walk_to_leaf(tree.first_child, start, pending, pending_count, lowest_pending,
                        [&](std::size_t a, uint32_t* d) {
                            int32_t dots[2];
                            dot2(signed_query, tree.codewords + a * n, n, dots);
                            d[0] = descent_distance(query_norm, bias[a], dots[0]);
                            d[1] = descent_distance(query_norm, bias[a + 1], dots[1]);
                        });
}

// The signed query (bytes - 128) and |query|^2, for every set: compilers
// vectorise it for the flags of the file that includes it, and hand-written
// AVX2 and AVX-512 forms were no faster (in-process A/B on the decoder).
inline int64_t prepare_query_portable(const uint8_t* __restrict query, int8_t* __restrict signed_query,
                                      std::size_t n) {
    for (std::size_t d = 0; d < n; ++d) signed_query[d] = int8_t(query[d] ^ 0x80);
    // 32-bit partial sums (4096 * 255^2 < 2^32) vectorise; 64-bit ones do not.
    uint64_t norm = 0;
    for (std::size_t start = 0; start < n; start += 4096) {
        const std::size_t end = start + 4096 < n ? start + 4096 : n;
        uint32_t partial = 0;
        for (std::size_t d = start; d < end; ++d) partial += uint32_t(query[d]) * uint32_t(query[d]);
        norm += partial;
    }
    return int64_t(norm);
}

// The record mask of rank_candidates (see dsp.hpp), without branches: which
// candidate sets a record is random.
inline uint64_t record_mask_portable(const uint64_t* ranks, uint32_t count) {
    uint64_t records = 1, lowest = ranks[0];
    for (uint32_t i = 1; i < count; ++i) {
        const uint64_t lower = 0 - uint64_t(ranks[i] < lowest);
        records |= (uint64_t(1) << i) & lower;
        lowest = (ranks[i] & lower) | (lowest & ~lower);
    }
    return records;
}

// rank_candidates without vectors. Only the baseline-compiled sets may use
// it (it calls rank_hash; see dsp.hpp).
inline uint64_t rank_candidates_portable(uint64_t salt, uint32_t count, uint64_t* ranks) {
    for (uint32_t i = 0; i < count; ++i) ranks[i] = rank_hash(salt, i);
    return record_mask_portable(ranks, count);
}

// lowest_ranked without vectors: the running minimum is kept with masks
// rather than branches.
inline uint32_t lowest_ranked_portable(const uint64_t* ranks, uint32_t n, uint64_t allowed) {
    uint64_t best = UINT64_MAX;
    uint32_t chosen = UINT32_MAX;
    for (uint32_t i = 0; i < n; ++i) {
        const uint64_t rank = ranks[i];
        // Take i if allowed and strictly lower, or if nothing is chosen yet
        // (a rank of UINT64_MAX is still a candidate).
        const bool take = ((allowed >> i) & 1) && (rank < best || chosen == UINT32_MAX);
        const uint64_t mask = 0 - uint64_t(take);
        best = (rank & mask) | (best & ~mask);
        chosen = uint32_t((i & mask) | (chosen & ~mask));
    }
    return chosen;
}

// The descend kernel of a set, from its dot2 and prepare_query.
template <auto Dot2, auto Prepare>
uint64_t descend_with(const DescentTree& tree, const uint8_t* query, int8_t* signed_scratch, uint64_t start,
                      uint64_t* pending, std::size_t* pending_count, uint64_t* lowest_pending) {
    return descend_tree(tree, query, signed_scratch, start, pending, pending_count, lowest_pending, Dot2, Prepare);
}

}  // namespace
}  // namespace vqtex::dsp::detail
