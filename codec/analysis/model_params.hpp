// model_params.hpp - what the analysis needs to turn an example into a
// TSVQ model (paper sections 2.3 and 4): pyramid depth, neighbourhood
// shapes, whether the example wraps, and how the codebooks are trained.
// The public API spreads these over the params of each call (common fields,
// the paper engine's or a trees file's shapes, vqtex_tsvq_params); the
// analysis reads them from one place.
#pragma once

#include <cstdint>

#include "vqtex/vqtex.h"

namespace vqtex {

struct ModelParams {
    uint32_t levels = 0;                         // 0 = automatic
    vqtex_shape shapes[VQTEX_MAX_LEVELS] = {};   // [0] = finest; {0,0,0} = default
    uint32_t example_tileable = 0;
    uint32_t codewords[VQTEX_MAX_LEVELS] = {};   // 0 = codeword_fraction
    // Every example neighbourhood a leaf: smaller codebooks lose rare
    // continuations and the texture drifts into its commonest patterns
    // (measured in bench/; the paper's "under 10% without visible loss"
    // does not hold for our corpus).
    float codeword_fraction = 1.0f;
    float train_fraction = 1.0f;
    uint32_t train_count = 0;
    vqtex_leaf leaf = VQTEX_LEAF_MEDOID;
    float distortion_threshold = 0.0f;
    uint64_t training_seed = 0;
    uint32_t entries_per_leaf = 0;
    uint32_t no_entry_keys = 0;
    uint32_t closing_divisor = 0;
    uint32_t closing_window = 0;
    uint32_t seam_closing = 1;
};

// The codebook fields of `p`, as the public struct holds them.
inline vqtex_tsvq_params tsvq_params_of(const ModelParams& p) {
    vqtex_tsvq_params t{};
    for (int l = 0; l < VQTEX_MAX_LEVELS; ++l) t.codewords[l] = p.codewords[l];
    t.codeword_fraction = p.codeword_fraction;
    t.train_fraction = p.train_fraction;
    t.train_count = p.train_count;
    t.leaf = p.leaf;
    t.distortion_threshold = p.distortion_threshold;
    t.training_seed = p.training_seed;
    t.entries_per_leaf = p.entries_per_leaf;
    t.no_entry_keys = p.no_entry_keys;
    t.closing_divisor = p.closing_divisor;
    t.closing_window = p.closing_window;
    t.seam_closing = p.seam_closing;
    return t;
}

// One place for what a call's params spread over: `shapes` may be null
// (animations give theirs to the analysis apart).
inline ModelParams model_params_of(uint32_t levels, uint32_t example_tileable, const vqtex_shape* shapes,
                                   const vqtex_tsvq_params& t) {
    ModelParams p;
    p.levels = levels;
    p.example_tileable = example_tileable;
    for (int l = 0; l < VQTEX_MAX_LEVELS; ++l) {
        p.shapes[l] = shapes ? shapes[l] : vqtex_shape{0, 0, 0};
        p.codewords[l] = t.codewords[l];
    }
    p.codeword_fraction = t.codeword_fraction;
    p.train_fraction = t.train_fraction;
    p.train_count = t.train_count;
    p.leaf = t.leaf;
    p.distortion_threshold = t.distortion_threshold;
    p.training_seed = t.training_seed;
    p.entries_per_leaf = t.entries_per_leaf;
    p.no_entry_keys = t.no_entry_keys;
    p.closing_divisor = t.closing_divisor;
    p.closing_window = t.closing_window;
    p.seam_closing = t.seam_closing;
    return p;
}

}  // namespace vqtex
