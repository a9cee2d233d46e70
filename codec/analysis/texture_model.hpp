// texture_model.hpp - analysis: an example image becomes a TextureModel
// (pyramid, neighbourhood shapes, noise histograms, and per level either the
// exhaustive candidate set or a trained TSVQ codebook; paper sections 2-4).
// The plan and the matcher builder serve animated examples as well
// (temporal_model.hpp), which keeps only what differs.
#pragma once

#include <memory>
#include <vector>

#include "engine/synthesis.hpp"
#include "analysis/model_params.hpp"
#include "tsvq/tsvq_train.hpp"
#include "tsvq/tsvq_tree.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {

struct ModelPlan {
    int levels = 0;
    std::vector<Shape> shapes;  // [0] = finest
};

// Pyramid depth for an example volume when none is given: the paper's 3,
// fewer when the coarsest level would be under 8 pixels on a side or under 2
// frames.
int automatic_volume_levels(int width, int height, int frames);

// Resolves depth and shapes and checks them, for a still example (frames 0)
// or an animated one. `shapes` are the caller's, [0] = finest; a missing or
// all-zero one means the default. The two kinds differ only in their
// defaults (automatic depth, default shapes) and in the largest window their
// files hold; throws a clear error when a shape is out of range.
ModelPlan plan_model(const ModelParams& params, const std::vector<Shape>& shapes, int width, int height,
                     int frames);

// The still shapes params.shapes asks for, [0] = finest.
std::vector<Shape> still_shapes_of(const ModelParams& params);

// Leaves wanted at `level` for `training_vectors` vectors.
uint32_t codewords_for_level(const ModelParams& params, int level,
                             std::size_t training_vectors);

// Exhaustive candidates or a trained codebook for one level's example set.
struct BuiltMatcher {
    std::shared_ptr<const Matcher> matcher;
    std::shared_ptr<const Codebook> codebook;  // TSVQ only
    std::size_t bytes = 0;
};

// The training settings of a level's tree from the model parameters:
// leaves (closing trees get fewer), stopping threshold, leaf representative
// and entries per leaf. Callers add the entry keys their shapes define.
TrainParams train_params_for(const ModelParams& params, int level, std::size_t training_vectors,
                             bool closing, int threads);

// What differs between the trees of still and animated levels.
struct MatcherRecipe {
    // A training fraction below 1 keeps at least this many vectors (all of
    // them when there are fewer).
    std::size_t min_training = 1;
    uint64_t seed_offset = 0;            // added to training_seed + level: one subset per tree kind
    std::vector<uint16_t> key_offsets;   // the entries' keys (empty: none)
    bool keys_on_single_entries = false;
};

// The matcher of one level and tree from its example set: the set itself
// for the exhaustive search (moved out of `set`), or a TSVQ codebook trained
// on a seeded subset of it.
BuiltMatcher build_matcher(ExampleSet& set, const ModelParams& params, vqtex_search search,
                           uint32_t backtrack, int threads, int level, bool closing, const MatcherRecipe& recipe);

struct AnalysisResult {
    TextureModel model;
    std::vector<std::shared_ptr<const Codebook>> codebooks;          // TSVQ only; [0] = finest
    std::vector<std::shared_ptr<const Codebook>> closing_codebooks;  // TSVQ with seam closing
    std::vector<std::size_t> training_vectors;
    std::size_t model_bytes = 0;
};

AnalysisResult analyse_example(const Image& example, const ModelParams& params,
                               vqtex_search search, uint32_t backtrack, int threads,
                               const ProgressFn& progress);

}  // namespace vqtex
