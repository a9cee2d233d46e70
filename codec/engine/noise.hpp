// noise.hpp - noise initialisation of the output pyramid (paper section 2.5).
//
// Each output level starts as white noise whose per-channel histogram equals
// the histogram of the matching example level (Heeger-Bergen histogram
// matching). We build it exactly rather than by equalising random values: the
// target histogram is scaled to the output pixel count (largest remainders),
// the resulting multiset of values is laid out and shuffled with our own PRNG.
#pragma once

#include <cstdint>
#include <vector>

#include "common/image.hpp"

namespace vqtex {

struct LevelHistogram {
    int channels = 0;
    std::vector<uint32_t> counts;  // channels x 256

    const uint32_t* channel(int c) const { return counts.data() + std::size_t(c) * 256; }
    bool operator==(const LevelHistogram&) const = default;
};

// What a level holds before it is synthesised: what the first rows read
// through the top wrap and each row's first pixels read through the row wrap.
enum class LevelInit {
    // Every level starts as histogram-matched white noise (paper section 2.5).
    Noise,
    // The coarsest level starts as noise; each finer level starts as the
    // finished coarser level, upsampled. The first rows then read, through
    // the wrap, a coarse version of what the bottom rows will become, instead
    // of noise: fewer broken rows at the top, much less visible wrap-around
    // seams. The randomness still comes from the coarsest level's noise.
    Parent,
};

LevelHistogram histogram_of(const Image& image);

// The histogram scaled to `total` samples per channel, each bin within one of
// its exact proportional share; ties in the remainder go to the lower value.
std::vector<uint32_t> scale_histogram(const uint32_t* counts, uint64_t total);

// Fill `image` (already sized) with noise matching `target`.
void fill_matched_noise(Image& image, const LevelHistogram& target, uint64_t seed, int level);

}  // namespace vqtex
