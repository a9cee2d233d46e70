// encode_support.hpp - what the exported encoders of still textures
// (encode_api.cpp) and of animations (volume_encode_api.cpp) share: the
// caller's output pointers, how TSVQ trees are stored (paper section 6:
// only the codebook is transmitted), and the stats of a trees file.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/error.hpp"
#include "format/model_codec.hpp"
#include "writer/model_writer.hpp"
#include "tsvq/tsvq_tree.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {

// Refuses null output pointers and empties the output, so that a failure
// leaves *data NULL.
inline void clear_output(uint8_t** data, size_t* size) {
    if (!data || !size) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output pointers are NULL");
    *data = nullptr;
    *size = 0;
}

// How the file coder stores the trees: the same fields for still and
// animated textures.
inline EncodeSettings tree_settings(uint32_t precision, uint32_t pixel_precision, uint32_t smoothing,
                                    uint32_t backtrack, vqtex_init init, uint64_t seed) {
    EncodeSettings s;
    s.precision = int(precision);
    s.pixel_precision = int(pixel_precision);
    s.smoothing = int(smoothing);
    s.backtrack = uint8_t(backtrack);
    s.init = init == VQTEX_INIT_NOISE ? LevelInit::Noise : LevelInit::Parent;
    s.seed = seed;
    return s;
}

// A quality preset's codebook sizes and precision, for a still texture's
// trees (vqtex_trees_params) and an animation's (vqtex_volume_encode_params)
// alike: both hold tsvq, precision, pixel_precision and smoothing. quality
// is 0 to 100.
template <typename Trees>
void apply_tree_preset(Trees& t, int quality) {
    // Measured with vqtex-bench's protocol (held-out crops of 8 corpus
    // textures, sliced Wasserstein distance and completeness; docs/RATE.md):
    // bytes are best spent on entries and precision, not on more codewords
    // (doubling them cost 75% more bytes for no measurable gain) nor on
    // larger windows (5x5 at the two finest levels beat 7x7 and 9x9 at every
    // size tried below 35 KB, because fewer samples per codeword leave room
    // for more entries). Keys on entries doubled their cost and scored worse.
    // So codewords grow slowly (48 at quality 0, doubling every 30 points,
    // each coarser level half, at least 32), entries from 8 to 20, codeword
    // precision from 3 to 6 bits, pixel precision from 5 to 8 bits. (The
    // paper's 9x9 window at quality 100 made files twice as large and
    // scored worse than 5x5.)
    const double q = quality;
    const double finest = 48.0 * std::pow(2.0, q / 30.0);
    for (int l = 0; l < VQTEX_MAX_LEVELS; ++l)
        t.tsvq.codewords[l] = uint32_t(std::max(32.0, std::round(finest / double(1 << l))));
    t.tsvq.codeword_fraction = 1.0f;
    t.tsvq.entries_per_leaf = uint32_t(8 + quality / 8);
    t.tsvq.no_entry_keys = 1;
    t.tsvq.seam_closing = 1;
    t.tsvq.closing_divisor = quality < 40 ? 4u : 2u;
    t.smoothing = quality < 20 ? 3u : 2u;
    t.precision = quality < 30 ? 3u : quality < 60 ? 4u : quality < 85 ? 5u : 6u;
    t.pixel_precision = quality < 20 ? 5u : quality < 40 ? 6u : quality < 60 ? 7u : 8u;
}

inline double seconds_since(std::chrono::steady_clock::time_point t0, std::chrono::steady_clock::time_point t1) {
    return std::chrono::duration<double>(t1 - t0).count();
}

// The stats of a trees file: its bytes and each level's causal codebook.
inline void tree_stats(vqtex_encode_stats* stats, std::size_t bytes,
                       const std::vector<std::shared_ptr<const Codebook>>& codebooks, uint32_t quality,
                       uint32_t attempts, double seconds) {
    if (!stats) return;
    *stats = vqtex_encode_stats{};
    stats->bytes = bytes;
    stats->quality = quality;
    stats->levels = uint32_t(codebooks.size());
    for (std::size_t l = 0; l < codebooks.size() && l < VQTEX_MAX_LEVELS; ++l) {
        stats->codewords[l] = uint32_t(codebooks[l]->leaf_count());
        stats->entries[l] = uint32_t(codebooks[l]->total_entries());
    }
    stats->attempts = attempts;
    stats->seconds = seconds;
}

}  // namespace vqtex
