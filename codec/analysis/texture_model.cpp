// texture_model.cpp - from an example image to a TextureModel (paper
// sections 2.3, 2.5 and 4).
#include "analysis/texture_model.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>

#include "common/error.hpp"
#include "common/parallel.hpp"
#include "engine/neighborhood3d.hpp"
#include "engine/pyramid.hpp"
#include "tsvq/search_exhaustive.hpp"
#include "tsvq/tsvq_search.hpp"

namespace vqtex {

int automatic_volume_levels(int width, int height, int frames) {
    int levels = 3;
    while (levels > 1 &&
           ((std::min(width, height) >> (levels - 1)) < 8 || (frames >> (levels - 1)) < 2))
        --levels;
    return levels;
}

ModelPlan plan_model(const ModelParams& params, const std::vector<Shape>& shapes, int width, int height,
                     int frames) {
    const bool still = frames == 0;
    ModelPlan plan;
    plan.levels = params.levels ? int(params.levels)
                  : still       ? automatic_levels(width, height)
                                : automatic_volume_levels(width, height, frames);
    if (plan.levels < 1 || plan.levels > kMaxLevels)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "levels must be 1 to " + std::to_string(kMaxLevels) +
                                               " (got " + std::to_string(plan.levels) + ")");
    plan.shapes = still ? default_shapes(plan.levels) : default_volume_shapes(plan.levels);
    // The files hold windows up to 63 on a side for still textures and 31 on
    // every axis for animated ones (FORMAT.md).
    const int most = still ? 63 : 31;
    for (int l = 0; l < plan.levels && std::size_t(l) < shapes.size(); ++l) {
        const Shape& s = shapes[std::size_t(l)];
        if (s.rows == 0 && s.cols == 0 && s.levels == 0 && (still || s.frames == 0)) continue;
        if (s.rows % 2 == 0 || s.cols % 2 == 0 || s.frames % 2 == 0 || s.levels < 1 || s.rows > most ||
            s.cols > most || s.frames > most)
            fail(VQTEX_ERROR_INVALID_ARGUMENT,
                 "neighbourhood at level " + std::to_string(l) + " must be odd " +
                     (still ? "RxC up to 63x63" : "RxCxD up to 31x31x31") + " with k >= 1 (got " +
                     shape_to_string(s) + ")");
        // Causal, whatever the caller's shape says: the plan holds the
        // synthesis shapes, the closing ones derive from them.
        plan.shapes[std::size_t(l)] = Shape{.rows = s.rows, .cols = s.cols, .levels = s.levels, .frames = s.frames};
    }
    for (int l = 0; l < plan.levels; ++l) {
        Shape& s = plan.shapes[std::size_t(l)];
        s.levels = std::min(s.levels, plan.levels - l);
        if (shape_taps(s).empty())
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "neighbourhood " + shape_to_string(s) + " at level " +
                                                   std::to_string(l) + " reads no pixel: use " +
                                                   (still ? "at least 1x3" : "D >= 3, 1x3") + " or k >= 2");
    }
    return plan;
}

std::vector<Shape> still_shapes_of(const ModelParams& params) {
    std::vector<Shape> shapes;
    for (const vqtex_shape& s : params.shapes) shapes.push_back(Shape{s.rows, s.cols, s.levels});
    return shapes;
}

uint32_t codewords_for_level(const ModelParams& params, int level,
                             std::size_t training_vectors) {
    uint64_t k = params.codewords[level];
    if (k == 0) {
        const double f = params.codeword_fraction > 0 ? params.codeword_fraction : 1.0;
        k = uint64_t(std::llround(double(training_vectors) * std::min(1.0, double(f))));
        // Very coarse levels have few vectors; keep enough leaves to matter.
        k = std::max<uint64_t>(k, std::min<uint64_t>(training_vectors, 64));
    }
    return uint32_t(std::clamp<uint64_t>(k, 1, training_vectors));
}

TrainParams train_params_for(const ModelParams& params, int level, std::size_t training_vectors,
                             bool closing, int threads) {
    TrainParams tp;
    const uint32_t divisor = closing ? std::max<uint32_t>(1, params.closing_divisor) : 1;
    tp.max_leaves = std::max<uint32_t>(1, codewords_for_level(params, level, training_vectors) / divisor);
    tp.distortion_threshold = params.distortion_threshold;
    tp.representative = params.leaf == VQTEX_LEAF_CENTROID ? LeafRepresentative::Centroid
                                                           : LeafRepresentative::Medoid;
    tp.threads = threads;
    // Seam-closing trees keep at most 4 entries: one entry per leaf (the
    // single best match) makes the band visibly smoother than the texture
    // around it; a few keep its grain (measured with the seam rank of
    // tests/test_codec.cpp on the corpus).
    tp.entries_per_leaf = params.entries_per_leaf ? params.entries_per_leaf : 1;
    if (closing) tp.entries_per_leaf = std::min<uint32_t>(tp.entries_per_leaf, 4);
    return tp;
}

BuiltMatcher build_matcher(ExampleSet& set, const ModelParams& params, vqtex_search search,
                           uint32_t backtrack, int threads, int level, bool closing, const MatcherRecipe& recipe) {
    BuiltMatcher built;
    if (search == VQTEX_SEARCH_EXHAUSTIVE) {
        built.bytes = set.vectors.size() + set.pixels.size();
        built.matcher = std::make_shared<ExhaustiveMatcher>(std::move(set));
        return built;
    }
    std::size_t subset_size = set.count();
    if (params.train_fraction > 0 && params.train_fraction < 1)
        subset_size = std::max<std::size_t>(std::min(set.count(), recipe.min_training),
                                            std::size_t(std::llround(double(subset_size) * params.train_fraction)));
    if (params.train_count > 0) subset_size = std::min<std::size_t>(subset_size, params.train_count);
    const std::vector<uint32_t> subset =
        choose_training_subset(set.count(), subset_size, params.training_seed + uint64_t(level) + recipe.seed_offset);
    TrainParams tp = train_params_for(params, level, subset.size(), closing, threads);
    tp.key_offsets = recipe.key_offsets;
    tp.keys_on_single_entries = recipe.keys_on_single_entries;
    built.codebook = std::make_shared<const Codebook>(train_codebook(set, subset, tp));
    built.bytes = built.codebook->memory_bytes();
    built.matcher = std::make_shared<TsvqMatcher>(built.codebook, backtrack);
    return built;
}

AnalysisResult analyse_example(const Image& example, const ModelParams& params,
                               vqtex_search search, uint32_t backtrack, int threads,
                               const ProgressFn& progress) {
    if (example.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "example image is empty (0x0)");
    const ModelPlan plan = plan_model(params, still_shapes_of(params), example.width, example.height, 0);
    const bool tileable = params.example_tileable != 0;
    const std::vector<Image> pyramid =
        build_pyramid(example, plan.levels, tileable ? EdgeMode::Wrap : EdgeMode::Mirror);

    AnalysisResult result;
    result.model.channels = example.channels;
    result.model.levels.resize(std::size_t(plan.levels));
    result.codebooks.resize(std::size_t(plan.levels));
    result.closing_codebooks.resize(std::size_t(plan.levels));
    result.training_vectors.resize(std::size_t(plan.levels));

    // The training sets first (cheap), then the trees: every tree depends
    // only on its own set, so the trees are trained side by side, largest
    // first, and each is the same whatever the thread count.
    struct Task {
        int level;
        bool closing;
        ExampleSet set;
        NeighborhoodLayout layout;
        BuiltMatcher built;
    };
    std::vector<Task> tasks;
    for (int l = 0; l < plan.levels; ++l) {
        const NeighborhoodLayout layout(plan.shapes[std::size_t(l)], example.channels, l, plan.levels);
        ExampleSet set = collect_examples(layout, pyramid, tileable);
        if (set.count() == 0) {
            const Image& img = pyramid[std::size_t(l)];
            fail(VQTEX_ERROR_IMAGE_TOO_SMALL,
                 "example " + std::to_string(example.width) + "x" + std::to_string(example.height) +
                     " is too small for neighbourhood " + shape_to_string(layout.shape()) +
                     " at pyramid level " + std::to_string(l) + " (" + std::to_string(img.width) +
                     "x" + std::to_string(img.height) +
                     "): use fewer --levels, smaller --shapes, or --tileable-example");
        }
        result.training_vectors[std::size_t(l)] = set.count();
        LevelModel& lm = result.model.levels[std::size_t(l)];
        lm.shape = layout.shape();
        lm.histogram = histogram_of(pyramid[std::size_t(l)]);
        tasks.push_back(Task{l, false, std::move(set), layout, {}});
        if (params.seam_closing) {
            Shape closing_shape = lm.shape;
            if (params.closing_window) {
                closing_shape.rows = std::min<int>(closing_shape.rows, int(params.closing_window));
                closing_shape.cols = std::min<int>(closing_shape.cols, int(params.closing_window));
            }
            // The file's closing windows are 3 to 63 on a side (a causal
            // window may be 1 wide).
            closing_shape.rows = std::max(closing_shape.rows, 3);
            closing_shape.cols = std::max(closing_shape.cols, 3);
            closing_shape.causal = false;
            const NeighborhoodLayout closing_layout(closing_shape, example.channels, l, plan.levels);
            ExampleSet closing_set = collect_examples(closing_layout, pyramid, tileable);
            // A level too small for the symmetric window simply keeps its seam.
            if (closing_set.count() > 0)
                tasks.push_back(Task{l, true, std::move(closing_set), closing_layout, {}});
        }
    }

    // Tasks are ordered by level (finest, largest first); several threads
    // take them in that order, each tree on one thread. With fewer trees than
    // threads, each tree's own training runs on the threads instead.
    const int workers = std::max(1, std::min(threads, int(tasks.size())));
    const int inner_threads = workers > 1 ? 1 : threads;
    std::atomic<std::size_t> next{0}, done{0};
    std::atomic<bool> stop{false};
    std::vector<std::exception_ptr> errors(tasks.size());
    auto work = [&](bool caller) {
        for (;;) {
            if (caller && progress && !stop.load() && !progress(done.load(), tasks.size())) stop.store(true);
            if (stop.load()) return;
            const std::size_t i = next.fetch_add(1);
            if (i >= tasks.size()) return;
            Task& t = tasks[i];
            try {
                MatcherRecipe recipe;
                if (!params.no_entry_keys) recipe.key_offsets = t.layout.entry_key_offsets();
                t.built = build_matcher(t.set, params, search, backtrack, inner_threads, t.level, t.closing, recipe);
            } catch (...) {
                errors[i] = std::current_exception();
                stop.store(true);
            }
            done.fetch_add(1);
        }
    };
    run_together(workers, [&](int w) { work(w == 0); });
    for (const auto& e : errors)
        if (e) std::rethrow_exception(e);
    if (stop.load() || (progress && !progress(tasks.size(), tasks.size())))
        fail(VQTEX_ERROR_CANCELLED, "analysis cancelled by the progress callback");

    for (Task& t : tasks) {
        LevelModel& lm = result.model.levels[std::size_t(t.level)];
        result.model_bytes += t.built.bytes;
        if (t.closing) {
            lm.closing_shape = t.layout.shape();
            lm.closing = t.built.matcher;
            result.closing_codebooks[std::size_t(t.level)] = t.built.codebook;
        } else {
            lm.matcher = t.built.matcher;
            result.codebooks[std::size_t(t.level)] = t.built.codebook;
        }
    }
    return result;
}

}  // namespace vqtex
