// fill_coherence.hpp - coherent candidates for hole filling (after
// Ashikhmin 2001, beside the paper's search of section 5.1): where each
// filled pixel was copied from, and the example neighbourhoods that continue
// its neighbours' patches.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/coherent_candidates.hpp"
#include "fill/example_index.hpp"

namespace vqtex::constrained {

// Where each pixel of a target level was copied from: an example position
// (y * example width + x at the same level), or -1 (known pixels, and pixels
// not synthesised yet).
struct SourceMap {
    int width = 0, height = 0;
    std::vector<int32_t> at;
    SourceMap(int w, int h) : width(w), height(h), at(std::size_t(w) * std::size_t(h), -1) {}
    int32_t get(int x, int y) const {
        if (x < 0 || y < 0 || x >= width || y >= height) return -1;
        return at[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
};

// Coherence (after Ashikhmin 2001, as a candidate set beside the tree's
// answer): a pixel whose neighbour at offset d was copied from example
// position s is offered the example neighbourhood at s - d, which continues
// the neighbour's patch. The tree's answer and the coherent candidates are
// compared on the same query with exact distances; a coherent candidate wins
// when it is within the bias of the tree's (bias in 1/256: 0 = only when at
// least as close). Ties go to the lower index, so the choice is a pure
// function of the query and the neighbours' sources.
// The list is the one the coherent engine uses (engine/coherent_candidates.hpp);
// here its values are neighbourhood indices, every one a continuation.
struct Candidates {
    CandidateList<32> list;
    void add(int32_t i) {
        if (i >= 0) list.add(uint32_t(i), true);
    }
};

// The tree's answer `found`, or the nearest coherent candidate when it is
// within the bias of it.
uint32_t coherent_choice(const ExampleSet& set, const uint8_t* query, uint32_t found, const Candidates& c,
                         uint32_t bias);

// The coherent candidates of pixel (x, y): for each neighbour within
// `radius` with a source s, the neighbourhood at s - offset.
void add_coherent(Candidates& c, const SourceMap& src, const ExampleIndex& ex, int x, int y, int radius,
                  bool include_self);

}  // namespace vqtex::constrained
