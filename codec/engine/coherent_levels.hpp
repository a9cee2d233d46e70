// coherent_levels.hpp - the level schedule of the still coherent engine
// (Lefebvre & Hoppe 2005 section 3): coarse to fine over the appearance
// space's levels, each started (coherent_start.hpp) and corrected a number
// of passes, the copies relocated, the finest polished on raw colours; the
// analysis of a large example made level by level as the schedule reaches
// each; the passes counted for the progress callback.
#pragma once

#include <algorithm>
#include <cstdint>

#include "engine/appearance.hpp"
#include "engine/coherence_sets.hpp"
#include "engine/coherent_pass.hpp"
#include "engine/coherent_progress.hpp"
#include "engine/coherent_start.hpp"
#include "engine/coherent_synthesis.hpp"

namespace vqtex::coherent {

// How the still engine starts a level from the options.
inline StartRules start_rules(const CoherentOptions& options) {
    return StartRules{options.seed, options.jitter, options.clamp_children, options.threads};
}

// Correction passes at each level, counted for the progress callback.
struct LevelPasses {
    const AppearanceSpace& space;
    const CoherenceSets& sets;
    const CoherentOptions& options;
    int top;
    PassProgress progress;
    // When the analysis is made level by level: the space and sets above,
    // whose levels enter() fills and empties (otherwise null).
    AppearanceSpace* by_level_space = nullptr;
    CoherenceSets* by_level_sets = nullptr;

    LevelPasses(const AppearanceSpace& s, const CoherenceSets& c, const CoherentOptions& o);

    // The finest level runs one pass fewer: the colour polish follows it,
    // and with the link bias its second pass changed the corpus scores by
    // under 0.5% for a tenth of the synthesis time (SYNTHESIS.md).
    int passes_at(int l) const {
        return l == top ? options.coarse_passes : l == 0 ? std::max(1, options.passes - 1) : options.passes;
    }

    // Before level l's passes when the analysis is made level by level:
    // the coarser level's vectors and sets are let go, then l's are made
    // (one level's at a time).
    void enter(int l);

    // Rows from a band's edges that the finest level's passes may leave
    // wrong: 2 more than its subsets, four a pass (Band). With a blend, its
    // radius more: a band's own pixels read the map that far past them.
    int band_margin() const;

    // Level l's passes on `map` (the whole level, or with `band` some of its
    // rows, of which `own_rows` count for progress), then at the finest
    // level the colour polish.
    void run(int l, PositionMap& map, const Band* band = nullptr, int own_rows = 0);

    // Levels from the coarsest down to `last`, whole.
    PositionMap levels_down_to(int last);
};

}  // namespace vqtex::coherent
