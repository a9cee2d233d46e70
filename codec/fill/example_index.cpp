// example_index.cpp - a level's example neighbourhoods and their search
// for hole filling (paper section 5.1; see example_index.hpp).
#include "fill/example_index.hpp"

#include <algorithm>
#include <cmath>

#include "tsvq/tsvq_train.hpp"

namespace vqtex::constrained {

ExampleIndex::ExampleIndex(ExampleSet set, int width, int height, const FillOptions& o)
    : set_(std::move(set)), width_(width), height_(height), backtrack_(o.backtrack) {
    at_.assign(std::size_t(width) * std::size_t(height), -1);
    for (std::size_t i = 0; i < set_.count(); ++i) at_[set_.positions[i]] = int32_t(i);
    if (o.exhaustive) {
        exhaustive_ = std::make_unique<ExhaustiveMatcher>(set_);
        return;
    }
    TrainParams tp;
    std::vector<uint32_t> subset(set_.count());
    for (std::size_t i = 0; i < subset.size(); ++i) subset[i] = uint32_t(i);
    if (o.max_train && subset.size() > o.max_train)
        subset = choose_training_subset(set_.count(), o.max_train, o.seed ^ 0x7472616Eull /* "tran" */);
    const double fraction = std::clamp(o.codeword_fraction, 1e-6, 1.0);
    const std::size_t wanted = std::size_t(std::llround(double(subset.size()) * fraction));
    tp.max_leaves = uint32_t(std::clamp<std::size_t>(wanted, std::min<std::size_t>(subset.size(), 64), subset.size()));
    // Medoid leaves: real example neighbourhoods, whose tie key is their
    // index in the set, so a leaf names a position in the example.
    tp.representative = LeafRepresentative::Medoid;
    tp.entries_per_leaf = 1;
    tp.threads = o.threads;
    tsvq_ = std::make_unique<TsvqMatcher>(std::make_shared<const Codebook>(train_codebook(set_, subset, tp)),
                                          o.backtrack);
}

}  // namespace vqtex::constrained
