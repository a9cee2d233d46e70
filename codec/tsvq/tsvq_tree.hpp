// tsvq_tree.hpp - the tree-structured VQ codebook (paper section 4): a flat
// node array without pointers, the object the codec serialises.
//
// Each node has a codeword (a neighbourhood vector). Internal nodes have two
// children stored next to each other; nodes are numbered breadth-first, so
// the numbering is a function of the tree's shape alone. Leaves carry:
//   - the number of training vectors they represent (their weight),
//   - a tie key (the raster index of the example neighbourhood they came
//     from), which breaks equal distances the way exhaustive search does,
//   - one or more entries: an output pixel plus a short key (the pixels of
//     the adjacent current-level taps, in tap order). Entry 0 is the leaf's own
//     representative. With several entries, search picks the leaf by its
//     codeword, then the entry whose short key best fits the query; this
//     keeps a leaf's rarer continuations alive (see tsvq_search.cpp).
//
// The search structure is a pure function of the topology and the leaves:
// internal codewords are derived (finalize()) as the count-weighted rounded
// mean of the leaves below them. A decoder that has only the leaves rebuilds
// exactly the tree the encoder searched.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vqtex {

// No root-to-leaf path is longer: the trainer stops splitting there and the
// decoder rejects deeper trees, so search cost per pixel stays bounded on
// any file. (Trees of 61504 leaves from the corpus are 115 to 165 deep.)
inline constexpr int kMaxTreeDepth = 1024;

struct TsvqNode {
    int32_t first_child = -1;  // -1 for a leaf; children are first_child and first_child + 1
    int32_t leaf = -1;         // leaf index when a leaf
};

class Codebook {
public:
    Codebook() = default;
    // key_offsets: byte offsets, within a neighbourhood vector, of the short
    // key stored with each entry (empty: entries carry only a pixel).
    Codebook(std::size_t dimension, std::size_t stride, int channels,
             std::vector<uint16_t> key_offsets = {});

    std::size_t dimension() const { return dimension_; }
    std::size_t stride() const { return stride_; }
    int channels() const { return channels_; }
    const std::vector<uint16_t>& key_offsets() const { return key_offsets_; }
    std::size_t key_length() const { return key_offsets_.size(); }
    std::size_t entry_size() const { return std::size_t(channels_) + key_offsets_.size(); }

    std::size_t node_count() const { return nodes_.size(); }
    std::size_t leaf_count() const { return leaf_nodes_.size(); }
    const TsvqNode& node(std::size_t i) const { return nodes_[i]; }
    const uint8_t* codeword(std::size_t node) const { return codewords_.data() + node * stride_; }
    uint8_t* codeword(std::size_t node) { return codewords_.data() + node * stride_; }

    // Leaf data by leaf index (0 .. leaf_count()-1, in node order).
    std::size_t leaf_node(std::size_t leaf) const { return leaf_nodes_[leaf]; }
    const uint8_t* leaf_codeword(std::size_t leaf) const { return codeword(leaf_nodes_[leaf]); }
    uint32_t leaf_count_of(std::size_t leaf) const { return node_weights_[leaf_nodes_[leaf]]; }
    uint32_t leaf_key(std::size_t leaf) const { return node_keys_[leaf_nodes_[leaf]]; }
    std::size_t entry_count(std::size_t leaf) const { return node_entries_[leaf_nodes_[leaf]].size() / entry_size(); }
    // Entry i of a leaf: channels pixel bytes, then key_length() key bytes.
    const uint8_t* entry(std::size_t leaf, std::size_t i) const {
        return node_entries_[leaf_nodes_[leaf]].data() + i * entry_size();
    }
    const uint8_t* leaf_pixel(std::size_t leaf) const { return entry(leaf, 0); }
    std::size_t total_entries() const;
    int depth() const;

    // Bytes held in memory.
    std::size_t memory_bytes() const;

    // Building: a root, then splits, then set_leaf() on every leaf node, then
    // finalize().
    std::size_t add_root();
    // Turns leaf node `node` into an internal node; returns its first child.
    std::size_t split(std::size_t node);
    // `entries` holds entry_count entries of entry_size() bytes (at least one).
    void set_leaf(std::size_t node, const uint8_t* codeword, uint32_t weight, uint32_t key,
                  const uint8_t* entries, std::size_t entry_count);
    // Renumbers nodes breadth-first, numbers the leaves and derives every
    // internal codeword. Idempotent.
    void finalize();

    bool operator==(const Codebook& o) const;

private:
    std::size_t dimension_ = 0;
    std::size_t stride_ = 0;
    int channels_ = 0;
    std::vector<uint16_t> key_offsets_;
    std::vector<TsvqNode> nodes_;
    std::vector<uint8_t> codewords_;
    std::vector<uint32_t> leaf_nodes_;
    // Per node; meaningful on leaves only.
    std::vector<uint32_t> node_weights_;
    std::vector<uint32_t> node_keys_;
    std::vector<std::vector<uint8_t>> node_entries_;
};

}  // namespace vqtex
