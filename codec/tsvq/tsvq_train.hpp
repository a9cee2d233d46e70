// tsvq_train.hpp - growing a TSVQ codebook from example neighbourhoods
// (paper section 4, training).
#pragma once

#include <cstdint>
#include <vector>

#include "engine/neighborhood.hpp"
#include "tsvq/tsvq_tree.hpp"

namespace vqtex {

enum class LeafRepresentative {
    // The real example neighbourhood nearest the leaf's centroid, with its
    // real centre pixel. The default: see tsvq_train.cpp for why.
    Medoid,
    // The centroid, and the mean of the cluster's centre pixels.
    Centroid,
};

struct TrainParams {
    uint32_t max_leaves = 512;           // K
    double distortion_threshold = 0.0;   // stop when mean SSD per vector <= this (0: off)
    LeafRepresentative representative = LeafRepresentative::Medoid;
    int max_lloyd_iterations = 20;
    // Entries per leaf (see tsvq_tree.hpp): the representative plus up to
    // entries_per_leaf - 1 more members, each with its short key.
    uint32_t entries_per_leaf = 1;
    std::vector<uint16_t> key_offsets;
    // Keys are normally kept only with several entries (they choose among
    // them); temporal codebooks need them on every entry (neighborhood3d.hpp).
    bool keys_on_single_entries = false;
    int threads = 1;
};

// Indices (sorted) of the vectors to train on: all of them, or a random
// subset of `count` chosen with our PRNG.
std::vector<uint32_t> choose_training_subset(std::size_t total, std::size_t count, uint64_t seed);

// Train on examples.vector(i) for i in `subset`. Deterministic: the same
// inputs give the same codebook for any thread count.
Codebook train_codebook(const ExampleSet& examples, const std::vector<uint32_t>& subset,
                        const TrainParams& params);

}  // namespace vqtex
