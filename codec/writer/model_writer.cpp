// model_writer.cpp - the writing half of the codebook coding of
// docs/FORMAT.md (format/model_codec.cpp reads it back): quantisation,
// prediction and the section layout of a still texture's trees; the
// container compresses the sections. model_codec.cpp's opening comment says
// what is predicted from what; both halves follow it.
#include "writer/model_writer.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <tuple>

#include "common/error.hpp"
#include "engine/neighborhood.hpp"
#include "engine/noise.hpp"
#include "writer/byte_writer.hpp"

namespace vqtex {
namespace {

std::vector<int32_t> topology_of(const Codebook& b) {
    std::vector<int32_t> fc(b.node_count());
    for (std::size_t n = 0; n < b.node_count(); ++n) fc[n] = b.node(n).first_child;
    return fc;
}

// Encoder-side simplification of the codewords, invisible to the format:
// away from the pixel (beyond the ring of adjacent taps), taps are averaged
// in blocks of `smoothing` x `smoothing` per channel. Search then matches on
// the coarse structure there (fine detail nearby still counts, and entries
// carry the exact adjacent pixels), and the repeated values cost almost
// nothing after the planar layout and zstd.
std::vector<uint8_t> smoothed_codewords(const Codebook& b, const TreeLayout& layout, int smoothing) {
    const std::size_t k = b.leaf_count(), dim = b.dimension(), ch = std::size_t(layout.channels);
    std::vector<uint8_t> out(k * dim);
    for (std::size_t l = 0; l < k; ++l) std::memcpy(out.data() + l * dim, b.leaf_codeword(l), dim);
    if (smoothing <= 1) return out;
    const auto& taps = layout.taps;
    auto floor_div = [](int a, int g) { return a >= 0 ? a / g : -((-a + g - 1) / g); };
    std::vector<std::vector<std::size_t>> members;
    std::vector<std::tuple<int, int, int, int>> keys;
    for (std::size_t t = 0; t < taps.size(); ++t) {
        const Tap& tap = taps[t];
        std::tuple<int, int, int, int> key;
        if (tap.depth == 0 && std::abs(tap.dt) <= 1 && std::abs(tap.dx) <= 1 && std::abs(tap.dy) <= 1)
            key = {-1 - int(t), 0, 0, 0};  // its own group
        else
            key = {tap.depth, tap.dt, floor_div(tap.dy, smoothing), floor_div(tap.dx, smoothing)};
        auto it = std::find(keys.begin(), keys.end(), key);
        if (it == keys.end()) {
            keys.push_back(key);
            members.emplace_back();
            it = keys.end() - 1;
        }
        members[std::size_t(it - keys.begin())].push_back(t);
    }
    for (std::size_t l = 0; l < k; ++l) {
        uint8_t* cw = out.data() + l * dim;
        for (const auto& m : members)
            for (std::size_t c = 0; c < ch; ++c) {
                unsigned sum = 0;
                for (std::size_t t : m) sum += cw[t * ch + c];
                const uint8_t mean = uint8_t((sum + m.size() / 2) / m.size());
                for (std::size_t t : m) cw[t * ch + c] = mean;
            }
    }
    return out;
}

}  // namespace

TreeSections encode_tree(const Codebook& b, const TreeLayout& layout, const EncodeSettings& s) {
    TreeSections out;
    const std::size_t k = b.leaf_count(), dim = b.dimension(), ch = std::size_t(b.channels());
    const std::size_t key_len = b.key_length();
    std::size_t max_entries = 1;
    for (std::size_t l = 0; l < k; ++l) max_entries = std::max(max_entries, b.entry_count(l));

    ByteWriter topo;
    topo.varint(k);
    topo.varint(max_entries);
    topo.u8(key_len ? 1 : 0);  // whether entries carry keys
    // Breadth-first node order: one bit per node, 1 = internal.
    std::vector<uint8_t> bits((b.node_count() + 7) / 8, 0);
    for (std::size_t n = 0; n < b.node_count(); ++n)
        if (b.node(n).first_child >= 0) bits[n / 8] |= uint8_t(1u << (n % 8));
    topo.bytes(bits);
    for (std::size_t l = 0; l < k; ++l) topo.varint(b.leaf_count_of(l));
    if (max_entries > 1)
        for (std::size_t l = 0; l < k; ++l) topo.u8(uint8_t(b.entry_count(l) - 1));
    out.topology = std::move(topo.data());

    const std::vector<uint32_t> order = depth_first_leaves(topology_of(b));
    const int p = s.precision, pp = s.pixel_precision;
    const uint8_t mask = uint8_t((1u << p) - 1), pixel_mask = uint8_t((1u << pp) - 1);
    const std::vector<uint8_t> leaf_codewords = smoothed_codewords(b, layout, s.smoothing);
    // Codewords: planar, delta to the previous leaf depth-first.
    out.codewords.resize(k * dim);
    std::vector<uint8_t> dequantised(k * dim);
    for (std::size_t d = 0; d < dim; ++d) {
        uint8_t previous = 0;
        for (std::size_t i = 0; i < k; ++i) {
            const uint8_t q = quantise(leaf_codewords[order[i] * dim + d], p);
            out.codewords[d * k + i] = uint8_t((q - previous) & mask);
            previous = q;
            dequantised[order[i] * dim + d] = dequantise(q, p);
        }
    }
    // Entries: keys (planar per key position), then pixels (planar per channel).
    const PixelPredictor taps = layout.predictor;
    const auto& key_offsets = b.key_offsets();
    std::vector<uint8_t> keys, pixels;
    const int kp = layout.keys_at_pixel_precision ? pp : p;
    const uint8_t key_mask = layout.keys_at_pixel_precision ? pixel_mask : mask;
    for (std::size_t kpos = 0; kpos < key_len; ++kpos)
        for (std::size_t i = 0; i < k; ++i) {
            const uint32_t leaf = order[i];
            const uint8_t base = layout.keys_at_pixel_precision
                                     ? quantise(dequantised[leaf * dim + key_offsets[kpos]], pp)
                                     : quantise(b.leaf_codeword(leaf)[key_offsets[kpos]], p);
            for (std::size_t e = 0; e < b.entry_count(leaf); ++e)
                keys.push_back(uint8_t((quantise(b.entry(leaf, e)[ch + kpos], kp) - base) & key_mask));
        }
    std::vector<uint8_t> source(dim);
    for (std::size_t c = 0; c < ch; ++c)
        for (std::size_t i = 0; i < k; ++i) {
            const uint32_t leaf = order[i];
            for (std::size_t e = 0; e < b.entry_count(leaf); ++e) {
                // Predict from what the decoder will have: the dequantised
                // codeword, with this entry's dequantised key over it.
                std::memcpy(source.data(), dequantised.data() + leaf * dim, dim);
                for (std::size_t kpos = 0; kpos < key_len; ++kpos)
                    source[key_offsets[kpos]] = dequantise(quantise(b.entry(leaf, e)[ch + kpos], kp), kp);
                // Keyless entries are stored sorted (see tsvq_train.cpp), so
                // each is best predicted by the one before it.
                const uint8_t predicted = (key_len == 0 && e > 0)
                                              ? quantise(b.entry(leaf, e - 1)[c], pp)
                                              : quantise(taps.predict(source.data(), int(c)), pp);
                const uint8_t actual = quantise(b.entry(leaf, e)[c], pp);
                pixels.push_back(uint8_t((actual - predicted) & pixel_mask));
            }
        }
    out.entries = std::move(keys);
    out.entries.insert(out.entries.end(), pixels.begin(), pixels.end());
    return out;
}

std::vector<uint8_t> encode_histogram(const LevelHistogram& h) {
    ByteWriter w;
    for (int c = 0; c < h.channels; ++c)
        for (int v = 0; v < 256; ++v) w.varint(h.channel(c)[v]);
    return std::move(w.data());
}

void write_tree(ContainerWriter& writer, int level, TreeKind kind, const Codebook& book, const TreeLayout& layout,
                const EncodeSettings& settings) {
    TreeSections t = encode_tree(book, layout, settings);
    writer.add(kTagTopology, uint8_t(level), uint8_t(kind), std::move(t.topology));
    writer.add(kTagCodewords, uint8_t(level), uint8_t(kind), std::move(t.codewords));
    writer.add(kTagEntries, uint8_t(level), uint8_t(kind), std::move(t.entries));
}

FileHeader model_header(int channels, uint32_t exemplar_width, uint32_t exemplar_height, int levels,
                        bool any_closing, const EncodeSettings& s) {
    FileHeader h;
    h.exemplar_width = exemplar_width;
    h.exemplar_height = exemplar_height;
    h.channels = uint8_t(channels);
    h.levels = uint8_t(levels);
    h.init = s.init == LevelInit::Noise ? 1 : 0;
    h.backtrack = s.backtrack;
    h.seed = s.seed;
    if (any_closing) h.flags |= kFlagSeamClosing;
    return h;
}

void write_level_coding(ByteWriter& level, const EncodeSettings& s, bool has_closing) {
    level.u8(uint8_t(s.precision));
    level.u8(uint8_t(s.pixel_precision));
    level.u8(has_closing ? 1 : 0);
}

std::vector<uint8_t> level_section(const Shape& shape, const Shape* closing_shape, const EncodeSettings& s,
                                   bool animated) {
    ByteWriter lw;
    lw.u8(uint8_t(shape.rows));
    lw.u8(uint8_t(shape.cols));
    if (animated) lw.u8(uint8_t(shape.frames));
    lw.u8(uint8_t(shape.levels));
    write_level_coding(lw, s, closing_shape != nullptr);
    if (closing_shape) {
        lw.u8(uint8_t(closing_shape->rows));
        lw.u8(uint8_t(closing_shape->cols));
        if (animated) lw.u8(uint8_t(closing_shape->frames));
    }
    return std::move(lw.data());
}

void write_histogram(ContainerWriter& writer, int level, int levels, const EncodeSettings& s,
                     const LevelHistogram& histogram) {
    if (s.init == LevelInit::Noise || level == levels - 1)
        writer.add(kTagHistogram, uint8_t(level), 0, encode_histogram(histogram));
}

std::vector<uint8_t> encode_model(const CodecModel& model, const EncodeSettings& s) {
    bool any_closing = false;
    for (const auto& lv : model.levels) any_closing = any_closing || lv.closing != nullptr;
    const FileHeader h = model_header(model.channels, model.exemplar_width, model.exemplar_height,
                                      int(model.levels.size()), any_closing, s);
    ContainerWriter writer(h, s.zstd_level);
    const int levels = int(model.levels.size());
    for (int l = 0; l < levels; ++l) {
        const CodecModel::Level& lv = model.levels[std::size_t(l)];
        if (!lv.causal) fail(VQTEX_ERROR_INVALID_ARGUMENT, "level " + std::to_string(l) + " has no codebook");
        writer.add(kTagLevel, uint8_t(l), 0, level_section(lv.shape, lv.closing ? &lv.closing_shape : nullptr, s, false));
        write_histogram(writer, l, levels, s, lv.histogram);
        for (const TreeKind kind : {TreeKind::Causal, TreeKind::Closing}) {
            const Codebook* book = kind == TreeKind::Causal ? lv.causal.get() : lv.closing.get();
            if (!book) continue;
            Shape shape = kind == TreeKind::Causal ? lv.shape : lv.closing_shape;
            shape.causal = kind == TreeKind::Causal;
            const NeighborhoodLayout layout(shape, model.channels, l, levels);
            write_tree(writer, l, kind, *book, tree_layout_of(layout), s);
        }
    }
    return writer.write();
}

}  // namespace vqtex
