// search_exhaustive.hpp - exhaustive nearest-neighbour search over every
// example neighbourhood (paper section 2.2): the exact reference that TSVQ is
// measured against. Distances are exact integer SSD; on a tie the earliest
// neighbourhood in raster order wins.
#pragma once

#include "engine/matcher.hpp"
#include "engine/neighborhood.hpp"

namespace vqtex {

class ExhaustiveMatcher final : public Matcher {
public:
    explicit ExhaustiveMatcher(ExampleSet examples);
    std::size_t stride() const override { return examples_.stride; }
    const uint8_t* match(const uint8_t* query, const MatchContext& context,
                         MatchScratch* scratch) const override;
    // Index of the chosen example: the nearest (lowest index on ties), or
    // with a tolerance the near-tie that ranks first (see MatchContext).
    std::size_t nearest(const uint8_t* query, const MatchContext& context = {}) const;
    const ExampleSet& examples() const { return examples_; }

private:
    ExampleSet examples_;
};

}  // namespace vqtex
