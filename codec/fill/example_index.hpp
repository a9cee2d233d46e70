// example_index.hpp - one level's example neighbourhoods for hole filling
// (paper section 5.1) with the search over them: a TSVQ tree trained on a
// seeded subset (or the exhaustive search), and the map from example
// position to neighbourhood that coherence needs.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/matcher.hpp"
#include "engine/neighborhood.hpp"
#include "fill/constrained.hpp"
#include "tsvq/search_exhaustive.hpp"
#include "tsvq/tsvq_search.hpp"

namespace vqtex::constrained {

// One level's example neighbourhoods (pass-2 windows or pass-1 blocks) with
// the tree over them, and a map from example position to neighbourhood, so
// that the position a pixel was copied from can be turned back into
// candidates for its neighbours (coherence, see coherent_choice).
class ExampleIndex {
public:
    // `width` x `height`: the grid the set's positions index (the example
    // level, or the level above it for blocks).
    ExampleIndex(ExampleSet set, int width, int height, const FillOptions& o);

    const ExampleSet& set() const { return set_; }
    int width() const { return width_; }
    std::unique_ptr<MatchScratch> make_scratch() const {
        return tsvq_ ? tsvq_->make_scratch() : nullptr;
    }
    // The neighbourhood the tree (or the exhaustive search) finds.
    uint32_t search(const uint8_t* query, const MatchContext& context, MatchScratch* scratch) const {
        if (exhaustive_) return uint32_t(exhaustive_->nearest(query, context));
        const std::size_t leaf = tsvq_->search(query, backtrack_, scratch, context);
        return tsvq_->codebook().leaf_key(leaf);
    }
    // The neighbourhood at example position (x, y), or -1 when there is none
    // (outside, or its window is not wholly known).
    int32_t at(int x, int y) const {
        if (x < 0 || y < 0 || x >= width_ || y >= height_) return -1;
        return at_[std::size_t(y) * std::size_t(width_) + std::size_t(x)];
    }

private:
    ExampleSet set_;
    int width_, height_;
    uint32_t backtrack_;
    std::vector<int32_t> at_;
    std::unique_ptr<TsvqMatcher> tsvq_;
    std::unique_ptr<ExhaustiveMatcher> exhaustive_;
};

}  // namespace vqtex::constrained
