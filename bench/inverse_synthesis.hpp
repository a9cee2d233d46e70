// inverse_synthesis.hpp - a compaction of a large example: a small image
// such that every window of the example has a close window in it and the
// reverse (Wei, Han, Zhou, Bao, Guo & Shum 2008, "Inverse texture
// synthesis"). It is learnt coarse to fine by alternating a search step
// and an update step: each example window (every few pixels) finds its
// nearest window of the compaction, and each window of the compaction its
// nearest window of the example, both by PatchMatch (Barnes, Shechtman,
// Finkelstein & Goldman 2009); then every pixel of the compaction becomes
// the mean of the example pixels the matched windows put on it. The
// compaction is a torus, so its windows wrap. Measured as an atlas for
// large examples against parts of the example (docs/ATLAS.md "Large
// examples"); part of the study, not the codec.
#pragma once

#include <cstdint>

#include "common/image.hpp"

namespace vqtex {

struct InverseSynthesisOptions {
    int side = 256;          // the compaction is side x side (a multiple of 2^(scales - 1))
    int patch = 8;           // window side
    int iterations = 6;      // search and update steps at the finest scale (2 more at the coarser)
    int scales = 3;          // the example reduced 2x this many times minus one
    double coherence = 1.0;  // weight of the compaction-to-example term against the example-to-compaction one
    bool sharp = true;       // the last update takes the vote nearest the mean instead of the mean
    uint64_t seed = 1;
};

// The compaction of `example` (8-bit, every channel matched). Single
// threaded and seeded: the same bytes on every run and build. Throws
// std::invalid_argument for a side the scales cannot halve, or larger
// than the example.
Image inverse_synthesis(const Image& example, const InverseSynthesisOptions& options);

}  // namespace vqtex
