// temporal_model.cpp - from an example frame sequence to a VolumeModel
// (paper section 5.2, with the training of section 4).
#include "analysis/temporal_model.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "tsvq/search_exhaustive.hpp"
#include "analysis/texture_model.hpp"
#include "tsvq/tsvq_search.hpp"
#include "tsvq/tsvq_train.hpp"

namespace vqtex {

namespace {

constexpr std::size_t kMinTraining = 2048;


// The matcher of a level's tree; kind: 0 the causal tree, 1 loop closing,
// 2 frame-seam closing.
BuiltMatcher build_volume_matcher(ExampleSet& set, const NeighborhoodLayout3& layout, const ModelParams& params,
                                  vqtex_search search, uint32_t backtrack, int threads, int level, int kind) {
    const int predecessor = layout.predecessor_offset();
    if (search == VQTEX_SEARCH_EXHAUSTIVE && predecessor >= 0) {
        // Each example pixel followed by its predecessor, as a TSVQ entry's
        // pixel is followed by its key (temporal_synthesis.hpp).
        const std::size_t ch = std::size_t(set.channels);
        std::vector<uint8_t> pairs(set.count() * 2 * ch);
        for (std::size_t i = 0; i < set.count(); ++i) {
            std::copy(set.pixel(i), set.pixel(i) + ch, pairs.data() + 2 * i * ch);
            std::copy(set.vector(i) + predecessor, set.vector(i) + std::size_t(predecessor) + ch,
                      pairs.data() + (2 * i + 1) * ch);
        }
        set.pixels = std::move(pairs);
        set.channels *= 2;
    }
    MatcherRecipe recipe;
    // The paper trains on a random 10% of the neighbourhoods; the coarse
    // levels of a small example have only a few hundred, and 10% of those
    // leaves the coarsest level a handful of codewords, from which every
    // output collapses into a flat field (measured on corpus/flicker_32_anim
    // decoded at 128x128). So the fraction applies above kMinTraining.
    recipe.min_training = kMinTraining;
    recipe.seed_offset = 64u * uint64_t(kind);
    // Every entry carries its predecessor as its key, whatever
    // params.no_entry_keys says (neighborhood3d.hpp).
    recipe.key_offsets = layout.entry_key_offsets();
    recipe.keys_on_single_entries = true;
    return build_matcher(set, params, search, backtrack, threads, level, kind != 0, recipe);
}

// Whether some position of level `level` has the whole window of `shape`
// inside the pyramid (a window that does not fit has no training example).
bool window_fits(const Shape& shape, int channels, int level, int levels, const std::vector<Volume>& pyramid) {
    const NeighborhoodLayout3 layout(shape, channels, level, levels);
    const Volume& v = pyramid[std::size_t(level)];
    for (int t = 0; t < v.frames; ++t)
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x)
                if (layout.fits_inside(pyramid, x, y, t)) return true;
    return false;
}

int odd_at_most(int limit, int n) { return std::max(1, std::min(limit, n % 2 ? n : n - 1)); }

// The default plan made to fit a small or short example, so that the
// defaults encode every sequence the encoder accepts: first each level's
// window no larger than its volume (fewer frames in time, then a smaller
// square), then fewer levels. A sequence of 64x64x16 frames read its
// coarsest level (16x16x4) with a 5-frame window and could not be encoded.
void fit_default_plan(const Volume& example, const ModelParams& params, ModelPlan& plan,
                      std::vector<Volume>& pyramid) {
    for (;;) {
        bool fits = true;
        for (int l = 0; l < plan.levels && fits; ++l) {
            Shape& s = plan.shapes[std::size_t(l)];
            const Volume& v = pyramid[std::size_t(l)];
            if (window_fits(s, example.channels, l, plan.levels, pyramid)) continue;
            Shape smaller = s;
            smaller.frames = odd_at_most(s.frames, v.frames);
            smaller.rows = smaller.cols = odd_at_most(s.rows, std::min(v.width, v.height));
            if (!shape_taps(smaller).empty() && window_fits(smaller, example.channels, l, plan.levels, pyramid))
                s = smaller;
            else
                fits = false;
        }
        if (fits || plan.levels == 1) return;
        ModelParams fewer = params;
        fewer.levels = uint32_t(plan.levels - 1);
        plan = plan_model(fewer, {}, example.width, example.height, example.frames);
        pyramid = build_volume_pyramid(example, plan.levels, EdgeMode::Mirror);
    }
}

}  // namespace

VolumeAnalysis analyse_volume(const Volume& example, const ModelParams& params,
                              const std::vector<Shape>& shapes, vqtex_search search, uint32_t backtrack,
                              int threads, const ProgressFn& progress) {
    if (example.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "example sequence is empty");
    ModelPlan plan = plan_model(params, shapes, example.width, example.height, example.frames);
    const bool tileable = params.example_tileable != 0;
    std::vector<Volume> pyramid =
        build_volume_pyramid(example, plan.levels, tileable ? EdgeMode::Wrap : EdgeMode::Mirror);
    const bool chosen = params.levels != 0 ||
                        std::any_of(shapes.begin(), shapes.end(), [](const Shape& s) { return s.rows || s.cols || s.frames; });
    if (!tileable && !chosen) fit_default_plan(example, params, plan, pyramid);

    VolumeAnalysis result;
    result.model.channels = example.channels;
    result.model.levels.resize(std::size_t(plan.levels));
    result.codebooks.resize(std::size_t(plan.levels));
    result.closing_codebooks.resize(std::size_t(plan.levels));
    result.seam_codebooks.resize(std::size_t(plan.levels));
    result.training_vectors.resize(std::size_t(plan.levels));
    for (int l = plan.levels - 1; l >= 0; --l) {
        const NeighborhoodLayout3 layout(plan.shapes[std::size_t(l)], example.channels, l, plan.levels);
        ExampleSet set = collect_volume_examples(layout, pyramid, tileable);
        const Volume& v = pyramid[std::size_t(l)];
        if (set.count() == 0)
            fail(VQTEX_ERROR_IMAGE_TOO_SMALL,
                 "example sequence " + std::to_string(example.width) + "x" + std::to_string(example.height) + "x" +
                     std::to_string(example.frames) + " is too small for neighbourhood " +
                     shape_to_string(layout.shape()) + " at pyramid level " + std::to_string(l) + " (" +
                     std::to_string(v.width) + "x" + std::to_string(v.height) + "x" + std::to_string(v.frames) +
                     "): use fewer --levels, more frames, or --tileable-example");
        result.training_vectors[std::size_t(l)] = set.count();
        VolumeLevelModel& lm = result.model.levels[std::size_t(l)];
        lm.shape = layout.shape();
        lm.histogram = histogram_of(v.stack);
        BuiltMatcher causal = build_volume_matcher(set, layout, params, search, backtrack, threads, l, 0);
        lm.matcher = causal.matcher;
        result.codebooks[std::size_t(l)] = causal.codebook;
        result.model_bytes += causal.bytes;
        if (params.seam_closing) {
            Shape closing_shape = layout.shape();
            if (params.closing_window) {
                closing_shape.rows = std::min<int>(closing_shape.rows, int(params.closing_window));
                closing_shape.cols = std::min<int>(closing_shape.cols, int(params.closing_window));
            }
            closing_shape.frames = std::max(3, closing_shape.frames);
            closing_shape.causal = false;
            const NeighborhoodLayout3 closing_layout(closing_shape, example.channels, l, plan.levels);
            ExampleSet closing_set = collect_volume_examples(closing_layout, pyramid, tileable);
            // Frame-seam closing: the causal shape with the whole current
            // frame's window (temporal_synthesis.hpp).
            Shape seam_shape = layout.shape();
            seam_shape.rows = closing_layout.shape().rows;
            seam_shape.cols = closing_layout.shape().cols;
            seam_shape.whole_frame = true;
            const NeighborhoodLayout3 seam_layout(seam_shape, example.channels, l, plan.levels);
            ExampleSet seam_set = collect_volume_examples(seam_layout, pyramid, tileable);
            // The decoder runs both sweeps or neither (FORMAT.md): a sequence
            // too short for one of the two windows gets neither.
            const bool both = closing_set.count() > 0 && seam_set.count() > 0;
            if (both) {
                BuiltMatcher closing =
                    build_volume_matcher(closing_set, closing_layout, params, search, backtrack, threads, l, 1);
                lm.closing_shape = closing_layout.shape();
                lm.closing = closing.matcher;
                result.closing_codebooks[std::size_t(l)] = closing.codebook;
                result.model_bytes += closing.bytes;
                BuiltMatcher seam = build_volume_matcher(seam_set, seam_layout, params, search, backtrack, threads, l, 2);
                lm.seam_shape = seam_layout.shape();
                lm.seam = seam.matcher;
                result.seam_codebooks[std::size_t(l)] = seam.codebook;
                result.model_bytes += seam.bytes;
            }
        }
        if (progress && !progress(uint64_t(plan.levels - l), uint64_t(plan.levels)))
            fail(VQTEX_ERROR_CANCELLED, "analysis cancelled by the progress callback");
    }
    return result;
}

}  // namespace vqtex
