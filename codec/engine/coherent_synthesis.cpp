// coherent_synthesis.cpp - coordinate synthesis with k-coherence candidates
// in appearance space (Lefebvre & Hoppe 2005 sections 3-4, 2006 section 4;
// Tong et al. 2002; Ashikhmin 2001): the engine's entry points, from the
// example's analysis to the output. See coherent_synthesis.hpp.
#include "engine/coherent_synthesis.hpp"

#include <algorithm>
#include <chrono>

#include "common/error.hpp"
#include "engine/coherent_bands.hpp"
#include "engine/coherent_levels.hpp"
#include "engine/coherent_pixel_correction.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {

void correct_positions(const AppearanceSpace& space, const CoherenceSets& sets, int level, PositionMap& map,
                       const CoherentOptions& options) {
    coherent::correction_pass(coherent::level_view(space, sets, level), map, options);
}

PositionMap upsample_positions(const AppearanceSpace& space, const PositionMap& parent, int width, int height,
                               int spacing, int threads) {
    PositionMap out{width, height, std::vector<uint32_t>(std::size_t(width) * height)};
    coherent::StartRules rules;
    rules.threads = threads;
    coherent::start_rows<coherent::PixelPositions>(space, [&](std::size_t i) { return parent.positions[i]; },
                                                   parent.width, width, height, 0, spacing, rules, false, 0, height,
                                                   out.positions.data());
    return out;
}

PositionMap synthesize_positions(const AppearanceSpace& space, const CoherenceSets& sets,
                                 const CoherentOptions& options) {
    coherent::LevelPasses passes(space, sets, options);
    return passes.levels_down_to(0);
}

bool analysis_by_level(int width, int height, int levels) {
    return uint64_t(width) * uint64_t(height) * uint64_t(std::max(levels, 0)) * kAppearanceDims * sizeof(int16_t) >
           kAnalysisAtOnceBytes;
}

uint64_t coherent_analysis_memory(int width, int height, int channels, int levels, int coherence) {
    const uint64_t n = uint64_t(width) * uint64_t(height), l = uint64_t(std::max(levels, 0));
    // A level's appearance vectors, and its coherence sets for k > 1.
    const uint64_t level = n * (kAppearanceDims * sizeof(int16_t) + (coherence > 1 ? 4 * uint64_t(coherence) : 0));
    // The stack's colours (its finest level is a copy of the example) and
    // the raw-colour vectors, then the levels held at once; for k > 1 also
    // the sort order and ranks of the level whose sets are being built.
    return n * (l * uint64_t(channels) + kAppearanceDims * sizeof(int16_t) + (coherence > 1 ? 8 : 0)) +
           (analysis_by_level(width, height, levels) ? level : l * level);
}

int copy_margin(int width, int height, bool tileable, int margin) {
    if (tileable || margin <= 0) return 0;
    return std::min(width, height) >= 8 * margin + 16 ? margin : 0;
}

int coherent_levels(int width, int height) {
    int levels = 1;
    while (levels < VQTEX_MAX_LEVELS && (4 << levels) <= std::min(width, height)) ++levels;
    return levels;
}

namespace {

// The engine's images into the result: the example's pixels as the image,
// or the readouts' as the maps.
void take_images(CoherentResult& r, std::vector<ReadImage> images, const std::vector<Readout>& readouts) {
    if (readouts.empty())
        r.image = std::move(images[0].image);
    else
        r.maps = std::move(images);
}

}  // namespace

CoherentResult synthesize_coherent(const Image& example, int levels, bool example_tileable, int coherence,
                                   const CoherentOptions& options,
                                   const std::function<bool(uint64_t, uint64_t)>& analyse_progress,
                                   const std::vector<Readout>& readouts) {
    using Clock = std::chrono::steady_clock;
    if (example.width > VQTEX_MAX_SIDE || example.height > VQTEX_MAX_SIDE)
        fail(VQTEX_ERROR_LIMIT_EXCEEDED,
             "example larger than " + std::to_string(VQTEX_MAX_SIDE) + " pixels on a side");
    const auto t0 = Clock::now();
    if (analyse_progress && !analyse_progress(0, 1))
        fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    if (options.quilt > 0) {
        if (example.width < options.quilt || example.height < options.quilt)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "the quilting block is larger than the example");
        CoherentResult r;
        take_images(r, coherent::quilt_pixels(example, example_tileable, options, readouts), readouts);
        r.synthesise_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        return r;
    }
    // The copies are laid out in the example less its frame (copy_margin).
    const int margin = copy_margin(example.width, example.height, example_tileable, options.margin);
    Image inner;
    if (margin > 0) {
        inner = Image(example.width - 2 * margin, example.height - 2 * margin, example.channels);
        for (int y = 0; y < inner.height; ++y)
            std::copy_n(example.at(margin, y + margin), std::size_t(inner.width) * std::size_t(example.channels),
                        inner.at(0, y));
    }
    const Image& laid_out = margin > 0 ? inner : example;
    const bool by_level = options.analysis_by_level < 0
                              ? analysis_by_level(laid_out.width, laid_out.height, levels)
                              : options.analysis_by_level > 0;
    AppearanceSpace space = build_appearance_space(laid_out, levels, example_tileable, options.threads, !by_level);
    CoherenceSets sets;
    if (by_level) {
        sets.k = std::max(coherence, 1);
        sets.levels.resize(space.levels.size());
    } else {
        sets = build_coherence_sets(space, coherence, kCoherenceExclusion, options.threads);
    }
    if (analyse_progress && !analyse_progress(1, 1))
        fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    const auto t1 = Clock::now();
    CoherentResult r;
    take_images(r,
                coherent::synthesize_pixels(example, margin, space, sets, options, readouts,
                                            by_level ? &space : nullptr, by_level ? &sets : nullptr),
                readouts);
    // What the analysis makes, whether it is held at once or level by level.
    const uint64_t n = example.pixel_count();
    r.model_bytes = space.levels.size() * (example.byte_count() + n * kAppearanceDims * sizeof(int16_t));
    if (sets.k > 1) r.model_bytes += space.levels.size() * n * uint64_t(sets.k) * sizeof(uint32_t);
    r.analyse_seconds = std::chrono::duration<double>(t1 - t0).count();
    r.synthesise_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    return r;
}

}  // namespace vqtex
