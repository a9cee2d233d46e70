// model_codec.cpp - reading the codebook coding of docs/FORMAT.md:
// quantisation, prediction, and the section layout (the writing half is
// writer/model_writer.cpp, only in the full library vqtex). zstd (container.cpp)
// does the rest.
//
// What is predicted from what:
//   - Leaf codewords are quantised to `precision` bits and, visiting the
//     leaves depth-first so that neighbours in the tree are neighbours in
//     the stream, each is coded as its difference from the previous leaf.
//     The stream is planar (all leaves' first sample, then the second ...),
//     which is the layout zstd models best.
//   - Entry keys are the same pixels as some samples of the codeword (the
//     taps next to the centre), so each is coded as its difference from the
//     leaf codeword at that tap; entry 0's key usually is the codeword's.
//   - Entry pixels are predicted from their own key (or the codeword) with
//     the median edge detector of LOCO-I: left, above and upper-left; the
//     entries of a keyless leaf are stored in ascending order, and each
//     after the first is predicted by the previous one.
#include "format/model_codec.hpp"

#include <algorithm>
#include <cstring>

#include "common/bitstream.hpp"
#include "common/error.hpp"
#include "engine/neighborhood.hpp"
#include "engine/noise.hpp"
#include "tsvq/tsvq_search.hpp"

namespace vqtex {
namespace {


constexpr uint32_t kMaxLeaves = 1u << 24;

bool tag_is(const Section& s, const char tag[4]) { return std::memcmp(s.tag.data(), tag, 4) == 0; }

}  // namespace

std::vector<uint32_t> depth_first_leaves(const std::vector<int32_t>& first_child) {
    std::vector<uint32_t> leaves, stack{0};
    uint32_t leaf = 0;
    std::vector<uint32_t> leaf_of(first_child.size(), 0);
    for (std::size_t n = 0; n < first_child.size(); ++n)
        if (first_child[n] < 0) leaf_of[n] = leaf++;
    while (!stack.empty()) {
        const uint32_t n = stack.back();
        stack.pop_back();
        if (first_child[n] < 0) {
            leaves.push_back(leaf_of[n]);
        } else {
            stack.push_back(uint32_t(first_child[n]) + 1);
            stack.push_back(uint32_t(first_child[n]));
        }
    }
    return leaves;
}

TreeLayout tree_layout_of(const NeighborhoodLayout& layout) {
    TreeLayout t;
    t.dimension = layout.dimension();
    t.stride = layout.stride();
    t.channels = layout.channels();
    t.key_offsets = layout.entry_key_offsets();
    t.predictor = layout.pixel_predictor();
    t.taps = layout.taps();
    return t;
}

std::shared_ptr<const Codebook> decode_tree(const std::vector<uint8_t>& topology_bytes,
                                            const std::vector<uint8_t>& codeword_bytes,
                                            const std::vector<uint8_t>& entry_bytes,
                                            const TreeLayout& layout, int precision,
                                            int pixel_precision, const std::string& where,
                                            std::size_t& memory_budget) {
    ByteReader topo(topology_bytes.data(), topology_bytes.size(), "topology of " + where);
    // Each leaf costs at least two topology bits and one weight byte, so a
    // leaf count above the section size is a lie; check before allocating.
    const uint64_t k = topo.varint_in("leaf count", 1, std::min<uint64_t>(kMaxLeaves, topology_bytes.size()));
    const uint64_t max_entries = topo.varint_in("entries per leaf", 1, TsvqMatcher::kMaxEntries);
    const uint8_t has_keys = topo.u8("key flag");
    if (has_keys > 1) topo.corrupt("key flag must be 0 or 1");
    const std::size_t nodes = std::size_t(2 * k - 1);
    // What the rebuilt tree will hold, checked before anything is allocated,
    // against what the trees before it left of the limit.
    {
        const std::size_t entry_size = std::size_t(layout.channels) + (has_keys ? layout.key_offsets.size() : 0);
        // Codewords with room for the search's per-node data (two more
        // bytes a sample, an upper bound), the decoded entries twice (here and in the tree), and
        // finalize()'s 64-bit sums along the deepest path.
        const uint64_t depth_bound = std::min<uint64_t>(k, kMaxTreeDepth + 1);
        const uint64_t tree_bytes = uint64_t(nodes) * (3 * layout.stride + 64) + 2 * k * max_entries * entry_size +
                                    depth_bound * (8 * layout.dimension + 32);
        if (tree_bytes > memory_budget)
            fail(VQTEX_ERROR_LIMIT_EXCEEDED, where + " would need " + std::to_string(tree_bytes) +
                                                 " bytes; " + std::to_string(memory_budget) +
                                                 " are left of the memory limit: raise the limit if the file is trusted");
        memory_budget -= std::size_t(tree_bytes);
    }
    const uint8_t* bits = topo.bytes((nodes + 7) / 8, "topology bits");
    std::vector<int32_t> first_child(nodes, -1);
    std::vector<uint16_t> depth(nodes, 0);
    std::size_t next = 1, leaves = 0;
    for (std::size_t n = 0; n < nodes; ++n) {
        if (n >= next) topo.corrupt("topology is not a tree (node " + std::to_string(n) + " unreachable)");
        if (bits[n / 8] & (1u << (n % 8))) {
            if (next + 2 > nodes) topo.corrupt("topology has more nodes than 2 x leaves - 1");
            if (depth[n] >= kMaxTreeDepth)
                topo.corrupt("tree is deeper than " + std::to_string(kMaxTreeDepth) + " levels (node " +
                             std::to_string(n) + ")");
            first_child[n] = int32_t(next);
            depth[next] = depth[next + 1] = uint16_t(depth[n] + 1);
            next += 2;
        } else {
            ++leaves;
        }
    }
    if (leaves != k || next != nodes) topo.corrupt("topology does not have the declared " + std::to_string(k) + " leaves");
    for (std::size_t n = nodes; n < ((nodes + 7) / 8) * 8; ++n)
        if (bits[n / 8] & (1u << (n % 8))) topo.corrupt("padding bits after the topology are not zero");
    std::vector<uint32_t> weights(k), entry_counts(k, 1);
    for (auto& w : weights) w = uint32_t(topo.varint_in("leaf weight", 1, UINT32_MAX));
    if (max_entries > 1)
        for (auto& e : entry_counts) {
            e = uint32_t(topo.u8("entry count")) + 1;
            if (e > max_entries) topo.corrupt("a leaf has more entries than the declared maximum");
        }
    topo.expect_end();

    const std::size_t dim = layout.dimension, ch = std::size_t(layout.channels);
    const std::vector<uint16_t> key_offsets = has_keys ? layout.key_offsets : std::vector<uint16_t>{};
    const std::size_t key_len = key_offsets.size();
    if (codeword_bytes.size() != k * dim)
        fail(VQTEX_ERROR_CORRUPT, "codewords of " + where + ": " + std::to_string(codeword_bytes.size()) +
                                      " bytes for " + std::to_string(k) + " leaves of " + std::to_string(dim) +
                                      " samples");
    uint64_t total_entries = 0;
    for (uint32_t e : entry_counts) total_entries += e;
    if (entry_bytes.size() != total_entries * (key_len + ch))
        fail(VQTEX_ERROR_CORRUPT, "entries of " + where + ": " + std::to_string(entry_bytes.size()) +
                                      " bytes for " + std::to_string(total_entries) + " entries");

    const std::vector<uint32_t> order = depth_first_leaves(first_child);
    const uint8_t mask = uint8_t((1u << precision) - 1), pixel_mask = uint8_t((1u << pixel_precision) - 1);
    std::vector<uint8_t> quantised(k * dim), codewords(k * dim);
    for (std::size_t d = 0; d < dim; ++d) {
        uint8_t previous = 0;
        for (std::size_t i = 0; i < k; ++i) {
            const uint8_t q = uint8_t((previous + codeword_bytes[d * k + i]) & mask);
            quantised[order[i] * dim + d] = q;
            codewords[order[i] * dim + d] = dequantise(q, precision);
            previous = q;
        }
    }
    // Entry storage: per leaf, entry_counts[leaf] entries of (pixel, key).
    std::vector<std::size_t> entry_start(k + 1, 0);
    for (std::size_t l = 0; l < k; ++l) entry_start[l + 1] = entry_start[l] + entry_counts[l];
    const std::size_t entry_size = ch + key_len;
    std::vector<uint8_t> entries(total_entries * entry_size);
    std::size_t pos = 0;
    const int key_precision = layout.keys_at_pixel_precision ? pixel_precision : precision;
    const uint8_t key_mask = layout.keys_at_pixel_precision ? pixel_mask : mask;
    for (std::size_t kpos = 0; kpos < key_len; ++kpos)
        for (std::size_t i = 0; i < k; ++i) {
            const uint32_t leaf = order[i];
            const uint8_t base = layout.keys_at_pixel_precision
                                     ? quantise(codewords[leaf * dim + key_offsets[kpos]], pixel_precision)
                                     : quantised[leaf * dim + key_offsets[kpos]];
            for (std::size_t e = 0; e < entry_counts[leaf]; ++e) {
                const uint8_t q = uint8_t((base + entry_bytes[pos++]) & key_mask);
                entries[(entry_start[leaf] + e) * entry_size + ch + kpos] = dequantise(q, key_precision);
            }
        }
    const PixelPredictor taps = layout.predictor;
    std::vector<uint8_t> source(dim);
    for (std::size_t c = 0; c < ch; ++c)
        for (std::size_t i = 0; i < k; ++i) {
            const uint32_t leaf = order[i];
            for (std::size_t e = 0; e < entry_counts[leaf]; ++e) {
                uint8_t* entry = entries.data() + (entry_start[leaf] + e) * entry_size;
                std::memcpy(source.data(), codewords.data() + leaf * dim, dim);
                for (std::size_t kpos = 0; kpos < key_len; ++kpos) source[key_offsets[kpos]] = entry[ch + kpos];
                // (The previous entry's sample: entry - entry_size, never
                // entry[c - entry_size], whose unsigned index wraps.)
                const uint8_t predicted = (key_len == 0 && e > 0)
                                              ? quantise((entry - entry_size)[c], pixel_precision)
                                              : quantise(taps.predict(source.data(), int(c)), pixel_precision);
                entry[c] = dequantise(uint8_t((predicted + entry_bytes[pos++]) & pixel_mask), pixel_precision);
            }
        }

    Codebook book(dim, layout.stride, layout.channels, key_offsets);
    book.add_root();
    for (std::size_t n = 0; n < nodes; ++n)
        if (first_child[n] >= 0) book.split(n);  // appends children in breadth-first order
    std::size_t leaf = 0;
    for (std::size_t n = 0; n < nodes; ++n) {
        if (first_child[n] >= 0) continue;
        // Ties between equal distances go to the lower leaf index.
        book.set_leaf(n, codewords.data() + leaf * dim, weights[leaf], uint32_t(leaf),
                      entries.data() + entry_start[leaf] * entry_size, entry_counts[leaf]);
        ++leaf;
    }
    book.finalize();
    return std::make_shared<const Codebook>(std::move(book));
}

LevelHistogram decode_histogram(const std::vector<uint8_t>& bytes, int channels, const std::string& where) {
    ByteReader r(bytes.data(), bytes.size(), "histogram of " + where);
    LevelHistogram h;
    h.channels = channels;
    h.counts.resize(std::size_t(channels) * 256);
    for (auto& n : h.counts) n = uint32_t(r.varint_in("histogram count", 0, UINT32_MAX));
    r.expect_end();
    for (int c = 0; c < channels; ++c) {
        uint64_t total = 0;
        for (int v = 0; v < 256; ++v) total += h.channel(c)[v];
        if (total == 0) fail(VQTEX_ERROR_CORRUPT, "histogram of " + where + " is empty");
    }
    return h;
}

const char* section_kind_name(TreeKind kind) {
    return kind == TreeKind::Closing ? "closing" : kind == TreeKind::FrameSeam ? "frame seam" : "";
}

const char* tree_name(TreeKind kind) {
    return kind == TreeKind::Closing ? "closing" : kind == TreeKind::FrameSeam ? "frame-seam" : "causal";
}

const Section& require_section(const Container& c, const char tag[4], int level, TreeKind kind) {
    const std::string kind_name = section_kind_name(kind);
    const Section* found = nullptr;
    for (const Section& s : c.sections) {
        if (!tag_is(s, tag) || s.level != level || s.kind != uint8_t(kind)) continue;
        if (found) fail(VQTEX_ERROR_CORRUPT, "section " + s.name() + " appears twice");
        found = &s;
    }
    if (!found)
        fail(VQTEX_ERROR_CORRUPT, "missing section " + std::string(tag, 4) + "[level " + std::to_string(level) +
                                      (kind_name.empty() ? "]" : ", " + kind_name + "]"));
    return *found;
}

namespace {

std::size_t tree_budget_of(const Container& c, std::size_t memory_limit) {
    std::size_t section_total = 0;
    for (const Section& s : c.sections) section_total += s.raw_size;
    return memory_limit - std::min(memory_limit, section_total);
}

}  // namespace

LevelReader::LevelReader(const Container& c, const uint8_t* file, std::size_t memory_limit)
    : c_(c), file_(file), budget_start_(tree_budget_of(c, memory_limit)), budget_(budget_start_) {}

std::vector<uint8_t> LevelReader::section(const char tag[4], int level) {
    std::vector<uint8_t> bytes = section_bytes(file_, require_section(c_, tag, level));
    ++used_;
    return bytes;
}

LevelReader::Coding LevelReader::read_coding(ByteReader& r) {
    Coding coding;
    coding.precision = r.u8("precision");
    coding.pixel_precision = r.u8("pixel precision");
    coding.has_closing = r.u8("closing flag");
    return coding;
}

void LevelReader::check_coding(const Coding& coding, const std::string& where_level) const {
    if (coding.precision < 1 || coding.precision > 8 || coding.pixel_precision < 1 || coding.pixel_precision > 8 ||
        coding.has_closing > 1)
        fail(VQTEX_ERROR_CORRUPT, where_level + " has invalid precision or flags");
    if (coding.has_closing && !(c_.header.flags & kFlagSeamClosing))
        fail(VQTEX_ERROR_CORRUPT, where_level + " has a closing tree the header does not announce");
}

LevelReader::LevelShapes LevelReader::level_shapes(int level, bool animated, const std::string& where_level) {
    const std::vector<uint8_t> bytes = section(kTagLevel, level);
    ByteReader r(bytes.data(), bytes.size(), where_level + " parameters");
    const int most = animated ? 31 : 63;
    auto valid = [most](int v, int lowest) { return v % 2 == 1 && v >= lowest && v <= most; };
    LevelShapes ls;
    Shape& shape = ls.shape;
    shape.rows = r.u8("window rows");
    shape.cols = r.u8("window columns");
    if (animated) shape.frames = r.u8("window frames");
    shape.levels = r.u8("window levels");
    ls.coding = read_coding(r);
    Shape& closing = ls.closing_shape;
    closing = shape;
    closing.causal = false;
    if (ls.coding.has_closing == 1) {
        closing.rows = r.u8("closing window rows");
        closing.cols = r.u8("closing window columns");
        if (animated) closing.frames = r.u8("closing window frames");
        // A still closing window is at least 3 on a side; an animated one
        // at least 3 frames long (it closes the temporal wrap).
        const int side = animated ? 1 : 3;
        if (!valid(closing.rows, side) || !valid(closing.cols, side) || !valid(closing.frames, animated ? 3 : 1))
            fail(VQTEX_ERROR_CORRUPT, where_level + " has an invalid closing window");
    }
    r.expect_end();
    if (!valid(shape.rows, 1) || !valid(shape.cols, 1) || !valid(shape.frames, 1) || shape.levels < 1 ||
        shape.levels > c_.header.levels - level || shape_taps(shape).empty())
        fail(VQTEX_ERROR_CORRUPT, where_level + " has an invalid neighbourhood " + shape_to_string(shape));
    check_coding(ls.coding, where_level);
    return ls;
}

LevelHistogram LevelReader::histogram(int level, LevelInit init, const std::string& where_level) {
    if (init != LevelInit::Noise && level != c_.header.levels - 1) return {};
    return decode_histogram(section(kTagHistogram, level), c_.header.channels, where_level);
}

std::shared_ptr<const Codebook> LevelReader::tree(int level, TreeKind kind, const TreeLayout& layout,
                                                  const Coding& coding, const std::string& where) {
    const auto topology = section_bytes(file_, require_section(c_, kTagTopology, level, kind));
    const auto codewords = section_bytes(file_, require_section(c_, kTagCodewords, level, kind));
    const auto entries = section_bytes(file_, require_section(c_, kTagEntries, level, kind));
    used_ += 3;
    return decode_tree(topology, codewords, entries, layout, coding.precision, coding.pixel_precision, where,
                       budget_);
}

std::size_t LevelReader::finish(bool any_closing) const {
    if (any_closing != bool(c_.header.flags & kFlagSeamClosing))
        fail(VQTEX_ERROR_CORRUPT, "the header's seam-closing flag disagrees with the closing trees present");
    if (used_ != c_.sections.size())
        fail(VQTEX_ERROR_CORRUPT, "file has " + std::to_string(c_.sections.size() - used_) +
                                      " sections this decoder does not know");
    return budget_start_ - budget_;
}

DecodedFile decode_file(const uint8_t* data, std::size_t size, std::size_t memory_limit) {
    DecodedFile f;
    const Container c = read_container(data, size, memory_limit);
    if (c.header.flags & kFlagVolume)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "file holds an animated texture (frames of " + std::to_string(c.header.exemplar_width) +
                                               "x" + std::to_string(c.header.exemplar_height) +
                                               "): decode it with vqtex_decode_volume (vqtex-decode --frames)");
    LevelReader reader(c, data, memory_limit);
    f.header = c.header;
    f.sections = c.sections;
    const int levels = c.header.levels, ch = c.header.channels;
    f.init = reader.init();
    f.model.channels = ch;
    f.model.exemplar_width = c.header.exemplar_width;
    f.model.exemplar_height = c.header.exemplar_height;
    f.model.levels.resize(std::size_t(levels));

    for (int l = 0; l < levels; ++l) {
        const std::string where_level = "level " + std::to_string(l);
        const LevelReader::LevelShapes ls = reader.level_shapes(l, false, where_level);
        const Shape& shape = ls.shape;
        const Shape& closing_shape = ls.closing_shape;
        const LevelReader::Coding& coding = ls.coding;
        if (l == 0) f.precision = coding.precision, f.pixel_precision = coding.pixel_precision;

        CodecModel::Level& lv = f.model.levels[std::size_t(l)];
        lv.shape = shape;
        lv.histogram = reader.histogram(l, f.init, where_level);
        for (int k = 0; k < 1 + coding.has_closing; ++k) {
            const TreeKind kind = TreeKind(k);
            Shape s = kind == TreeKind::Causal ? shape : closing_shape;
            s.causal = kind == TreeKind::Causal;
            const NeighborhoodLayout layout(s, ch, l, levels);
            auto book = reader.tree(l, kind, tree_layout_of(layout), coding,
                                    std::string(tree_name(kind)) + " tree of " + where_level);
            if (kind == TreeKind::Causal) {
                lv.causal = book;
            } else {
                lv.closing = book;
                lv.closing_shape = s;
            }
        }
    }
    f.model_bytes = reader.finish_levels(f.model.levels);
    return f;
}

}  // namespace vqtex
