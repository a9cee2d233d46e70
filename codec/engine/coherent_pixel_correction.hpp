// coherent_pixel_correction.hpp - the still engine's correction pass
// (Lefebvre & Hoppe 2005 section 3.4, 2006 section 4; Tong et al. 2002;
// Ashikhmin 2001): its step of coherent::correct over pixel positions, with
// k-coherence candidates, the bars on repeating a neighbour and on the
// example's edge, and the link bias; and the skip of the pixels whose
// whole window continues their copy, found for the whole map at once.
#pragma once

#include <cstdint>

#include "dsp/dsp.hpp"
#include "engine/appearance.hpp"
#include "engine/coherence_sets.hpp"
#include "engine/coherent_pass.hpp"
#include "engine/coherent_synthesis.hpp"

namespace vqtex::coherent {

// One level of the example as a correction reads it.
struct LevelView {
    const AppearanceSpace& space;
    const CoherenceSets& sets;
    int level;       // for the coherence sets
    int spacing;
    const int16_t* features;  // kAppearanceDims per example pixel
    int k;           // coherence candidates per neighbour
    const dsp::Kernels& kernels;

    const int16_t* feature(int x, int y) const {
        return features + (std::size_t(y) * space.width + x) * kAppearanceDims;
    }
    const int16_t* feature(uint32_t p) const { return feature(position_x(p), position_y(p)); }

    // Distance between the query (kTaps vectors) and the example's window at
    // (x, y), stopping once it exceeds `bound`.
    uint32_t distance(const int16_t* query, int x, int y, uint32_t bound) const {
        return window_distance(kernels, space, features, spacing, query, x, y, bound);
    }
};

// Level l's appearance vectors, and the raw colours of the polish.
LevelView level_view(const AppearanceSpace& space, const CoherenceSets& sets, int level);
LevelView polish_view(const AppearanceSpace& space, const CoherenceSets& sets);

// Clears the revisit flag of every pixel whose correction would keep its
// position at once (with k = 1: its source lies at least the window's reach
// inside the example and its whole window continues it).
void skip_coherent(const LevelView& view, const PositionMap& map, Revisit& revisit, const Band* band, int threads,
                   bool period_bar = false);

// One correction pass over the whole level, or over a band of its rows
// (interleaved_pass).
void correction_pass(const LevelView& view, PositionMap& map, const CoherentOptions& options,
                     Revisit* revisit = nullptr, const Band* band = nullptr);

}  // namespace vqtex::coherent
