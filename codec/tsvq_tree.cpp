// tsvq_tree.cpp - flat TSVQ codebook storage and the derivation of internal
// codewords from the leaves (paper section 4).
#include "tsvq_tree.hpp"

#include <algorithm>
#include <cstring>

#include "error.hpp"

namespace vqtex {

Codebook::Codebook(std::size_t dimension, std::size_t stride, int channels)
    : dimension_(dimension), stride_(stride), channels_(channels) {}

std::size_t Codebook::add_root() {
    nodes_.assign(1, TsvqNode{});
    codewords_.assign(stride_, 0);
    node_pixels_.assign(std::size_t(channels_), 0);
    node_weights_.assign(1, 0);
    node_keys_.assign(1, 0);
    return 0;
}

std::size_t Codebook::split(std::size_t node) {
    const std::size_t first = nodes_.size();
    nodes_[node].first_child = int32_t(first);
    nodes_.resize(first + 2);
    codewords_.resize(nodes_.size() * stride_, 0);
    node_pixels_.resize(nodes_.size() * std::size_t(channels_), 0);
    node_weights_.resize(nodes_.size(), 0);
    node_keys_.resize(nodes_.size(), 0);
    return first;
}

void Codebook::set_leaf(std::size_t node, const uint8_t* cw, const uint8_t* pixel, uint32_t weight,
                        uint32_t key) {
    std::memcpy(codeword(node), cw, dimension_);
    std::memset(codeword(node) + dimension_, 0, stride_ - dimension_);
    std::memcpy(node_pixels_.data() + node * std::size_t(channels_), pixel, std::size_t(channels_));
    node_weights_[node] = weight;
    node_keys_[node] = key;
}

void Codebook::finalize() {
    if (nodes_.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "codebook has no root");
    leaf_nodes_.clear();
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        if (nodes_[i].first_child >= 0) {
            nodes_[i].leaf = -1;
            continue;
        }
        nodes_[i].leaf = int32_t(leaf_nodes_.size());
        leaf_nodes_.push_back(uint32_t(i));
    }
    // Post-order walk with an explicit stack; sums live only along the
    // current path (one buffer per depth), so memory is O(depth x dimension)
    // rather than O(nodes x dimension). Sums are exact 64-bit integers.
    struct Frame {
        std::size_t node;
        bool expanded;
    };
    std::vector<Frame> stack{{0, false}};
    std::vector<std::vector<uint64_t>> sums;  // sums[d]: subtree sum of the node at stack depth d
    std::vector<uint64_t> weights;
    while (!stack.empty()) {
        Frame& f = stack.back();
        const std::size_t depth = stack.size() - 1;
        if (sums.size() <= depth + 2) {
            sums.resize(depth + 3, std::vector<uint64_t>(dimension_, 0));
            weights.resize(depth + 3, 0);
        }
        const TsvqNode& nd = nodes_[f.node];
        if (nd.first_child < 0) {
            // A leaf with weight 0 (possible only in hand-made codebooks)
            // still counts once, so every mean is defined.
            const uint64_t w = std::max<uint64_t>(1, node_weights_[f.node]);
            const uint8_t* cw = codeword(f.node);
            for (std::size_t d = 0; d < dimension_; ++d) sums[depth][d] = uint64_t(cw[d]) * w;
            weights[depth] = w;
            stack.pop_back();
        } else if (!f.expanded) {
            f.expanded = true;
            // Both children are summed into depth + 1 and depth + 2 scratch
            // slots in turn; accumulate into this frame's slot.
            std::fill(sums[depth].begin(), sums[depth].end(), 0);
            weights[depth] = 0;
            stack.push_back({std::size_t(nd.first_child) + 1, false});
            stack.push_back({std::size_t(nd.first_child), false});
            continue;
        } else {
            const uint64_t w = weights[depth];
            uint8_t* cw = codeword(f.node);
            for (std::size_t d = 0; d < dimension_; ++d) cw[d] = uint8_t((sums[depth][d] + w / 2) / w);
            std::memset(cw + dimension_, 0, stride_ - dimension_);
            stack.pop_back();
        }
        // A finished subtree adds itself into its parent's slot.
        if (!stack.empty()) {
            const std::size_t parent = stack.size() - 1;
            // The sibling frame (if still pending) sits between; find the
            // expanded ancestor, which is the nearest expanded frame.
            std::size_t p = parent;
            while (!stack[p].expanded) --p;
            for (std::size_t d = 0; d < dimension_; ++d) sums[p][d] += sums[depth][d];
            weights[p] += weights[depth];
        }
    }
}

int Codebook::depth() const {
    if (nodes_.empty()) return 0;
    std::vector<int> d(nodes_.size(), 0);
    int deepest = 0;
    for (std::size_t n = 0; n < nodes_.size(); ++n) {
        deepest = std::max(deepest, d[n]);
        if (nodes_[n].first_child >= 0) {
            d[std::size_t(nodes_[n].first_child)] = d[n] + 1;
            d[std::size_t(nodes_[n].first_child) + 1] = d[n] + 1;
        }
    }
    return deepest;
}

std::size_t Codebook::memory_bytes() const {
    return nodes_.size() * sizeof(TsvqNode) + codewords_.size() + node_pixels_.size() +
           (node_weights_.size() + node_keys_.size() + leaf_nodes_.size()) * sizeof(uint32_t);
}

bool Codebook::operator==(const Codebook& o) const {
    if (dimension_ != o.dimension_ || stride_ != o.stride_ || channels_ != o.channels_ ||
        nodes_.size() != o.nodes_.size())
        return false;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
        if (nodes_[i].first_child != o.nodes_[i].first_child || nodes_[i].leaf != o.nodes_[i].leaf)
            return false;
    if (codewords_ != o.codewords_ || leaf_nodes_ != o.leaf_nodes_) return false;
    for (std::size_t l = 0; l < leaf_count(); ++l)
        if (leaf_count_of(l) != o.leaf_count_of(l) || leaf_key(l) != o.leaf_key(l) ||
            !std::equal(leaf_pixel(l), leaf_pixel(l) + channels_, o.leaf_pixel(l)))
            return false;
    return true;
}

}  // namespace vqtex
