// tsvq_tree.hpp - the tree-structured VQ codebook (paper section 4): a flat
// node array without pointers, ready to serialise.
//
// Each node has a codeword (a neighbourhood vector). Internal nodes have two
// children stored next to each other; leaves carry the output pixel they
// stand for, the number of training vectors they represent and a tie key (the
// raster index of the example neighbourhood they came from), which breaks
// equal distances the same way the exhaustive search does.
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

struct TsvqNode {
    int32_t first_child = -1;  // -1 for a leaf; children are first_child and first_child + 1
    int32_t leaf = -1;         // index into the leaf arrays when a leaf
};

class Codebook {
public:
    Codebook() = default;
    Codebook(std::size_t dimension, std::size_t stride, int channels);

    std::size_t dimension() const { return dimension_; }
    std::size_t stride() const { return stride_; }
    int channels() const { return channels_; }

    std::size_t node_count() const { return nodes_.size(); }
    std::size_t leaf_count() const { return leaf_nodes_.size(); }
    const TsvqNode& node(std::size_t i) const { return nodes_[i]; }
    const uint8_t* codeword(std::size_t node) const { return codewords_.data() + node * stride_; }
    uint8_t* codeword(std::size_t node) { return codewords_.data() + node * stride_; }

    // Leaf data, by leaf index (0 .. leaf_count()-1, in node order).
    std::size_t leaf_node(std::size_t leaf) const { return leaf_nodes_[leaf]; }
    const uint8_t* leaf_codeword(std::size_t leaf) const { return codeword(leaf_nodes_[leaf]); }
    const uint8_t* leaf_pixel(std::size_t leaf) const {
        return node_pixels_.data() + std::size_t(leaf_nodes_[leaf]) * std::size_t(channels_);
    }
    uint32_t leaf_count_of(std::size_t leaf) const { return node_weights_[leaf_nodes_[leaf]]; }
    uint32_t leaf_key(std::size_t leaf) const { return node_keys_[leaf_nodes_[leaf]]; }
    int depth() const;

    // Bytes held in memory (nodes, codewords, leaf data).
    std::size_t memory_bytes() const;

    // Building: a root, then splits, then set_leaf() on every leaf node, then
    // finalize(), which numbers the leaves and derives internal codewords.
    std::size_t add_root();
    // Turns leaf node `node` into an internal node; returns its first child.
    std::size_t split(std::size_t node);
    void set_leaf(std::size_t node, const uint8_t* codeword, const uint8_t* pixel,
                  uint32_t weight, uint32_t key);
    // Numbers the leaves in node order and derives every internal codeword.
    void finalize();

    bool operator==(const Codebook& o) const;

private:
    std::size_t dimension_ = 0;
    std::size_t stride_ = 0;
    int channels_ = 0;
    std::vector<TsvqNode> nodes_;
    std::vector<uint8_t> codewords_;
    // Leaf data is kept per node (unused on internal nodes).
    std::vector<uint32_t> leaf_nodes_;
    std::vector<uint8_t> node_pixels_;
    std::vector<uint32_t> node_weights_;
    std::vector<uint32_t> node_keys_;
};

}  // namespace vqtex
