// coherence_sets.hpp - k-coherence candidate sets (Tong, Zhang, Liu, Wang,
// Guo & Shum 2002, section 4.1; used per level as in Lefebvre & Hoppe 2005).
//
// For every example position, the positions whose appearance vectors are
// nearest to its own, itself first. During synthesis a pixel's candidates
// are these sets of its neighbours' shifted sources: coherent copies of the
// example plus the few places that look the same, so that a search stays
// local without getting stuck in one copy.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/appearance.hpp"

namespace vqtex {

struct CoherenceSets {
    int k = 0;  // entries per position, the position itself included
    // Per level, k positions (y * width + x) per example position; empty
    // for k = 1 (a set of the position alone, which the engine never reads)
    // and for a level whose sets are not made yet or no longer needed.
    std::vector<std::vector<uint32_t>> levels;

    const uint32_t* of(int level, uint32_t position) const {
        return levels[std::size_t(level)].data() + std::size_t(position) * std::size_t(k);
    }
};

// Exact k nearest by appearance distance (ties to the lower position),
// excluding positions closer than `exclusion` * spacing to the position
// itself in x and y, so that a set does not fill with the same feature
// shifted by a pixel. Sets with fewer candidates repeat the position itself.
CoherenceSets build_coherence_sets(const AppearanceSpace& space, int k, int exclusion, int threads);

// The exclusion the coherent engine's sets use: they leave out positions
// within this many of a level's spacings.
inline constexpr int kCoherenceExclusion = 2;

// One level's sets (`space` must hold that level's appearance vectors).
std::vector<uint32_t> build_level_coherence_sets(const AppearanceSpace& space, int level, int k, int exclusion,
                                                int threads);

}  // namespace vqtex
