// coherent_levels.cpp - the still coherent engine's schedule of levels
// and passes (Lefebvre & Hoppe 2005 section 3). See coherent_levels.hpp.
#include "engine/coherent_levels.hpp"

#include <algorithm>
#include <vector>

#include "engine/coherent_pixel_correction.hpp"
#include "engine/copy_relocation.hpp"
#include "engine/pyramid.hpp"
#include "engine/seam_blend.hpp"
#include "engine/seam_cut.hpp"

namespace vqtex::coherent {

LevelPasses::LevelPasses(const AppearanceSpace& s, const CoherenceSets& c, const CoherentOptions& o)
    : space(s), sets(c), options(o), top(int(s.levels.size()) - 1), progress{o.progress} {
    for (int l = top; l >= 0; --l) progress.total += level_area(options.width, options.height, l) * uint64_t(passes_at(l));
}

void LevelPasses::enter(int l) {
    if (!by_level_space) return;
    if (l < top) {
        std::vector<int16_t>().swap(by_level_space->levels[std::size_t(l + 1)].features);
        std::vector<uint32_t>().swap(by_level_sets->levels[std::size_t(l + 1)]);
    }
    build_level_features(*by_level_space, l, options.threads);
    by_level_sets->levels[std::size_t(l)] =
        build_level_coherence_sets(*by_level_space, l, by_level_sets->k, kCoherenceExclusion, options.threads);
    // The level's stack colours served only to make its vectors (the
    // finest level's are the example's, whose channel count the vectors'
    // making reads).
    if (l > 0) by_level_space->levels[std::size_t(l)].colours = Image();
}

int LevelPasses::band_margin() const {
    return 4 * (passes_at(0) + std::max(0, options.polish_passes)) + 2 + cut_reach_rows(cut_rules(options)) +
           cover_reach_rows(cover_rules(options)) +
           std::clamp(options.blend, 0, kMaxBlendRadius);
}

void LevelPasses::run(int l, PositionMap& map, const Band* band, int own_rows) {
    const LevelView view = level_view(space, sets, l);
    Revisit revisit(map.positions.size());
    for (int pass = 0; pass < passes_at(l); ++pass) {
        skip_coherent(view, map, revisit, band, options.threads, options.period_bar);
        correction_pass(view, map, options, &revisit, band);
        progress.add(uint64_t(map.width) * uint64_t(band ? own_rows : map.height));
    }
    if (!band && l >= kRelocationMinLevel) relocate_copies(space, l, map, options.relocate, options.seed, options.threads);
    if (l == 0 && options.polish_passes > 0) {
        // Seams between coherent copies are placed by colours at last: the
        // coherence of the output's own pixels is what a viewer sees. Every
        // pixel is due again (other features); the flags of the level's
        // passes are reused rather than a second set allocated beside them
        // (a byte per output pixel).
        const LevelView polish = polish_view(space, sets);
        std::fill(revisit.due.begin(), revisit.due.end(), uint8_t(1));
        for (int pass = 0; pass < options.polish_passes; ++pass) {
            skip_coherent(polish, map, revisit, band, options.threads);
            correction_pass(polish, map, options, &revisit, band);
        }
    }
}

PositionMap LevelPasses::levels_down_to(int last) {
    PositionMap map;
    for (int l = top; l >= last; --l) {
        enter(l);
        const int w = pyramid_level_size(options.width, l), h = pyramid_level_size(options.height, l);
        PositionMap child{w, h, std::vector<uint32_t>(std::size_t(w) * h)};
        if (l == top) {
            // The coarsest level starts anywhere: positions drawn at random.
            random_start<PixelPositions>(space, 1, options.seed, l, w, h, child.positions.data());
        } else {
            start_rows<PixelPositions>(space, [&](std::size_t i) { return map.positions[i]; }, map.width, w, h, l,
                                       space.levels[std::size_t(l)].spacing, start_rules(options), true, 0, h,
                                       child.positions.data());
        }
        map = std::move(child);
        run(l, map);
    }
    return map;
}

}  // namespace vqtex::coherent
