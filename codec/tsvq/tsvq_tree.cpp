// tsvq_tree.cpp - flat TSVQ codebook storage, canonical numbering and the
// derivation of internal codewords from the leaves (paper section 4).
#include "tsvq/tsvq_tree.hpp"

#include <algorithm>
#include <cstring>

#include "common/error.hpp"

namespace vqtex {

Codebook::Codebook(std::size_t dimension, std::size_t stride, int channels,
                   std::vector<uint16_t> key_offsets)
    : dimension_(dimension), stride_(stride), channels_(channels), key_offsets_(std::move(key_offsets)) {
    for (uint16_t o : key_offsets_)
        if (o >= dimension_) fail(VQTEX_ERROR_INVALID_ARGUMENT, "codebook key offset outside the vector");
}

std::size_t Codebook::add_root() {
    nodes_.assign(1, TsvqNode{});
    codewords_.assign(stride_, 0);
    node_weights_.assign(1, 0);
    node_keys_.assign(1, 0);
    node_entries_.assign(1, {});
    return 0;
}

std::size_t Codebook::split(std::size_t node) {
    const std::size_t first = nodes_.size();
    nodes_[node].first_child = int32_t(first);
    nodes_.resize(first + 2);
    codewords_.resize(nodes_.size() * stride_, 0);
    node_weights_.resize(nodes_.size(), 0);
    node_keys_.resize(nodes_.size(), 0);
    node_entries_.resize(nodes_.size());
    node_entries_[node].clear();
    return first;
}

void Codebook::set_leaf(std::size_t node, const uint8_t* cw, uint32_t weight, uint32_t key,
                        const uint8_t* entries, std::size_t entry_count) {
    if (entry_count < 1) fail(VQTEX_ERROR_INVALID_ARGUMENT, "a leaf needs at least one entry");
    std::memcpy(codeword(node), cw, dimension_);
    std::memset(codeword(node) + dimension_, 0, stride_ - dimension_);
    node_weights_[node] = weight;
    node_keys_[node] = key;
    node_entries_[node].assign(entries, entries + entry_count * entry_size());
}

void Codebook::finalize() {
    if (nodes_.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "codebook has no root");
    // Breadth-first renumbering: siblings stay adjacent and the numbering
    // (which orders equal-distance branches during search) depends only on
    // the shape of the tree, so an encoder and a decoder agree on it.
    std::vector<uint32_t> order;  // new index -> old index
    order.reserve(nodes_.size());
    order.push_back(0);
    std::vector<TsvqNode> nodes(nodes_.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        const TsvqNode& old = nodes_[order[i]];
        if (old.first_child >= 0) {
            nodes[i].first_child = int32_t(order.size());
            order.push_back(uint32_t(old.first_child));
            order.push_back(uint32_t(old.first_child) + 1);
        }
    }
    if (order.size() != nodes_.size()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "codebook nodes unreachable from the root");
    std::vector<uint8_t> codewords(codewords_.size());
    std::vector<uint32_t> node_weights(nodes_.size()), keys(nodes_.size());
    std::vector<std::vector<uint8_t>> entries(nodes_.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        std::memcpy(codewords.data() + i * stride_, codeword(order[i]), stride_);
        node_weights[i] = node_weights_[order[i]];
        keys[i] = node_keys_[order[i]];
        entries[i] = std::move(node_entries_[order[i]]);
    }
    nodes_.swap(nodes);
    codewords_.swap(codewords);
    node_weights_.swap(node_weights);
    node_keys_.swap(keys);
    node_entries_.swap(entries);

    leaf_nodes_.clear();
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        if (nodes_[i].first_child >= 0) continue;
        if (node_entries_[i].empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "codebook leaf without entries");
        nodes_[i].leaf = int32_t(leaf_nodes_.size());
        leaf_nodes_.push_back(uint32_t(i));
    }

    // Internal codewords by a post-order walk with an explicit stack; sums
    // live only along the current path (one buffer per stack depth), so
    // memory is O(depth x dimension) rather than O(nodes x dimension). Sums
    // are exact 64-bit integers.
    struct Frame {
        std::size_t node;
        bool expanded;
    };
    std::vector<Frame> stack{{0, false}};
    std::vector<std::vector<uint64_t>> sums;
    std::vector<uint64_t> weights;
    while (!stack.empty()) {
        Frame& f = stack.back();
        const std::size_t depth = stack.size() - 1;
        if (sums.size() <= depth) {
            sums.resize(depth + 1, std::vector<uint64_t>(dimension_, 0));
            weights.resize(depth + 1, 0);
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
            // The children are pushed above this frame (the second child
            // waits below the first); each adds itself into this frame's
            // slot when it completes.
            f.expanded = true;
            std::fill(sums[depth].begin(), sums[depth].end(), 0);
            weights[depth] = 0;
            const std::size_t first = std::size_t(nd.first_child);
            stack.push_back({first + 1, false});
            stack.push_back({first, false});
            continue;
        } else {
            const uint64_t w = weights[depth];
            uint8_t* cw = codeword(f.node);
            for (std::size_t d = 0; d < dimension_; ++d) cw[d] = uint8_t((sums[depth][d] + w / 2) / w);
            std::memset(cw + dimension_, 0, stride_ - dimension_);
            stack.pop_back();
        }
        if (!stack.empty()) {
            std::size_t parent = stack.size() - 1;
            while (!stack[parent].expanded) --parent;  // skip a pending sibling
            for (std::size_t d = 0; d < dimension_; ++d) sums[parent][d] += sums[depth][d];
            weights[parent] += weights[depth];
        }
    }
}

std::size_t Codebook::total_entries() const {
    std::size_t n = 0;
    for (std::size_t l = 0; l < leaf_count(); ++l) n += entry_count(l);
    return n;
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
    std::size_t entries = 0;
    for (const auto& e : node_entries_) entries += e.capacity() + sizeof(e);
    return nodes_.size() * sizeof(TsvqNode) + codewords_.size() + entries +
           (node_weights_.size() + node_keys_.size() + leaf_nodes_.size()) * sizeof(uint32_t);
}

bool Codebook::operator==(const Codebook& o) const {
    if (dimension_ != o.dimension_ || stride_ != o.stride_ || channels_ != o.channels_ ||
        key_offsets_ != o.key_offsets_ || nodes_.size() != o.nodes_.size())
        return false;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
        if (nodes_[i].first_child != o.nodes_[i].first_child || nodes_[i].leaf != o.nodes_[i].leaf)
            return false;
    if (codewords_ != o.codewords_ || leaf_nodes_ != o.leaf_nodes_) return false;
    for (std::size_t l = 0; l < leaf_count(); ++l)
        if (leaf_count_of(l) != o.leaf_count_of(l) || leaf_key(l) != o.leaf_key(l) ||
            node_entries_[leaf_nodes_[l]] != o.node_entries_[o.leaf_nodes_[l]])
            return false;
    return true;
}

}  // namespace vqtex
