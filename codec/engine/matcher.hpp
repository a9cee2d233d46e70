// matcher.hpp - the search interface the synthesis engine calls per pixel:
// given the neighbourhood of an output pixel, return the example pixel to
// copy (paper section 2.2). Exhaustive search and TSVQ both implement it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "dsp/dsp.hpp"

namespace vqtex {

// Per-pixel inputs of a search besides the query.
struct MatchContext {
    // Near-ties: every candidate within best * (1 + tolerance / 256) of the
    // best distance qualifies, and the one whose key hashes lowest with
    // `salt` wins. The salt depends on the seed and the pixel's position only,
    // so the choice is deterministic whatever the thread count or visit
    // order. tolerance 0 is a plain nearest-neighbour search (lowest key on
    // exact ties).
    uint64_t salt = 0;
    uint32_t tolerance = 0;
};

// The winner among qualifying candidates: lowest (hash, key).
inline uint64_t candidate_rank(uint64_t salt, uint32_t key) { return dsp::rank_hash(salt, key); }

inline uint32_t tolerance_threshold(uint32_t best, uint32_t tolerance) {
    const uint64_t t = uint64_t(best) + uint64_t(best) * tolerance / 256;
    return t > UINT32_MAX ? UINT32_MAX : uint32_t(t);
}

// The near-tie choice every search makes (exhaustive, TSVQ, hole filling):
// start from the nearest candidate, offer each candidate within the
// threshold, keep the lowest (rank, key). The winner depends on the set of
// qualifying keys only, never on the order they are offered in.
class NearTieChoice {
public:
    NearTieChoice(uint64_t salt, uint32_t nearest_key)
        : salt_(salt), key_(nearest_key), rank_(candidate_rank(salt, nearest_key)) {}
    // True when `key` beats every candidate offered so far (it is then kept).
    bool offer(uint32_t key) {
        const uint64_t rank = candidate_rank(salt_, key);
        if (rank > rank_ || (rank == rank_ && key >= key_)) return false;
        key_ = key;
        rank_ = rank;
        return true;
    }
    uint32_t key() const { return key_; }

private:
    uint64_t salt_;
    uint32_t key_;
    uint64_t rank_;
};

// Per-thread working memory of a matcher, made once per thread so that the
// per-pixel search allocates nothing.
struct MatchScratch {
    virtual ~MatchScratch() = default;
};

class Matcher {
public:
    virtual ~Matcher() = default;
    // Bytes of a query (the neighbourhood's padded stride).
    virtual std::size_t stride() const = 0;
    virtual std::unique_ptr<MatchScratch> make_scratch() const { return nullptr; }
    // The pixel (channels bytes) to write for this query. Must be a pure
    // function of the query: thread-safe and deterministic.
    virtual const uint8_t* match(const uint8_t* query, const MatchContext& context,
                                 MatchScratch* scratch) const = 0;
};

}  // namespace vqtex
