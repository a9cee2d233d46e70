// search_exhaustive.cpp - the exact reference search (paper section 2.2).
#include "tsvq/search_exhaustive.hpp"

#include "dsp/dsp.hpp"
#include "common/error.hpp"

namespace vqtex {

ExhaustiveMatcher::ExhaustiveMatcher(ExampleSet examples) : examples_(std::move(examples)) {
    if (examples_.count() == 0)
        fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "no example neighbourhood to search");
}

std::size_t ExhaustiveMatcher::nearest(const uint8_t* query, const MatchContext& context) const {
    const dsp::Kernels& k = dsp::kernels();
    uint32_t best = UINT32_MAX;
    // Every distance is below UINT32_MAX (at most 255^2 per byte of a vector
    // far shorter than 66,000 bytes), so some row always wins.
    const uint32_t index = k.nearest(query, examples_.vectors.data(), examples_.stride,
                                     examples_.stride, examples_.count(), &best);
    if (context.tolerance == 0) return index;
    const uint32_t threshold = tolerance_threshold(best, context.tolerance);
    NearTieChoice choice(context.salt, index);
    for (std::size_t i = 0; i < examples_.count(); ++i)
        if (k.ssd(query, examples_.vector(i), examples_.stride) <= threshold) choice.offer(uint32_t(i));
    return choice.key();
}

const uint8_t* ExhaustiveMatcher::match(const uint8_t* query, const MatchContext& context,
                                        MatchScratch*) const {
    return examples_.pixel(nearest(query, context));
}

}  // namespace vqtex
