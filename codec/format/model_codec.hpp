// model_codec.hpp - the sections of a vqtex file that hold a texture model,
// and reading them back into the model (docs/FORMAT.md; the writing half is
// writer/model_writer.hpp; paper section 6, "only the codebook
// would be transmitted"). The file holds, per pyramid level, the
// neighbourhood shape and the TSVQ codebooks (tree topology, leaf weights,
// quantised leaf codewords, leaf entries), plus the histograms that seed the
// noise. Never the example's pixels as an image.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/bitstream.hpp"
#include "engine/neighborhood.hpp"
#include "engine/noise.hpp"
#include "format/tree_model.hpp"
#include "format/container.hpp"
#include "tsvq/tsvq_tree.hpp"

namespace vqtex {

// What the tree coding needs to know of a neighbourhood shape, 2D or 3D
// (temporal shapes have dt != 0; volume_codec.cpp): sizes, the taps (for the
// encoder's smoothing), the entry keys and the pixel predictor.
struct TreeLayout {
    std::size_t dimension = 0, stride = 0;
    int channels = 0;
    std::vector<Tap> taps;
    std::vector<uint16_t> key_offsets;
    PixelPredictor predictor;
    // Keys quantised like the entry pixels (pixel precision, coded against
    // the dequantised codeword re-quantised so), not like the codewords: a
    // temporal key must decode equal to its pixel when the example pixel did
    // not change (neighborhood3d.hpp, docs/FORMAT.md §D).
    bool keys_at_pixel_precision = false;
};
TreeLayout tree_layout_of(const NeighborhoodLayout& layout);

// One TSVQ tree from its TOPO, CODE and ENTR payloads (encode_tree of
// writer/model_writer.hpp writes them).
std::shared_ptr<const Codebook> decode_tree(const std::vector<uint8_t>& topology, const std::vector<uint8_t>& codewords,
                                            const std::vector<uint8_t>& entries, const TreeLayout& layout,
                                            int precision, int pixel_precision, const std::string& where,
                                            std::size_t& memory_budget);

// Section tags shared by still and animated files (docs/FORMAT.md).
inline constexpr char kTagLevel[4] = {'L', 'E', 'V', 'L'};
inline constexpr char kTagHistogram[4] = {'H', 'I', 'S', 'T'};
inline constexpr char kTagTopology[4] = {'T', 'O', 'P', 'O'};
inline constexpr char kTagCodewords[4] = {'C', 'O', 'D', 'E'};
inline constexpr char kTagEntries[4] = {'E', 'N', 'T', 'R'};

// The trees a level may have, as the `kind` byte of their sections
// (docs/FORMAT.md §C.1 and §D); a level's own sections (LEVL, HIST)
// have kind 0.
enum class TreeKind : uint8_t {
    Causal = 0,     // the scan's tree
    Closing = 1,    // seam closing (still) or loop closing (animated): symmetric shape
    FrameSeam = 2,  // animated textures only: frame-seam closing
};
// The kind as section references name it: "" (causal), "closing", "frame seam".
const char* section_kind_name(TreeKind kind);
// The tree as messages name it: "causal", "closing", "frame-seam".
const char* tree_name(TreeKind kind);

// The one section of `c` with this tag, level and kind; a missing or repeated
// one is CORRUPT.
const Section& require_section(const Container& c, const char tag[4], int level, TreeKind kind = TreeKind::Causal);

// A HIST payload: 256 counts per channel, as varints.
LevelHistogram decode_histogram(const std::vector<uint8_t>& bytes, int channels, const std::string& where);

// The level reader of the still and animated decoders: it hands out the
// sections a level needs, counts them (every section of the file must be
// used), and charges the decoded trees to what the memory limit leaves once
// the sections are counted in full (as read_container checked them).
class LevelReader {
public:
    LevelReader(const Container& c, const uint8_t* file, std::size_t memory_limit);

    // The payload of a level's own section (VOLU, LEVL, HIST: kind 0).
    std::vector<uint8_t> section(const char tag[4], int level);

    // The fields every LEVL has after its shape, read in order and checked
    // once the shape is: precision, pixel precision, closing flag (a closing
    // tree needs the header's seam-closing flag).
    struct Coding {
        int precision = 0, pixel_precision = 0, has_closing = 0;
    };
    static Coding read_coding(ByteReader& r);
    void check_coding(const Coding& coding, const std::string& where_level) const;

    // A level's LEVL section, read and checked: the causal window, the
    // coding, and the closing window when the level has a closing tree
    // (symmetric; else the causal window made symmetric). Animated levels
    // store each window's frames after its columns and hold windows up to
    // 31 on every axis (63 on a side for still ones), so both decoders read
    // their shapes here.
    struct LevelShapes {
        Shape shape;
        Shape closing_shape;
        Coding coding;
    };
    LevelShapes level_shapes(int level, bool animated, const std::string& where_level);

    // The level's HIST when the file has one (noise init, or the coarsest
    // level), else an empty histogram.
    LevelHistogram histogram(int level, LevelInit init, const std::string& where_level);

    // One tree: its TOPO, CODE and ENTR sections decoded.
    std::shared_ptr<const Codebook> tree(int level, TreeKind kind, const TreeLayout& layout, const Coding& coding,
                                         const std::string& where);

    // The last checks: the header's seam-closing flag agrees with the
    // closing trees found, and every section was used. Returns what the
    // trees took of the memory limit (an upper bound).
    std::size_t finish(bool any_closing) const;
    // The same, the flag read from the decoded levels (still or animated).
    template <typename Levels>
    std::size_t finish_levels(const Levels& levels) const {
        bool any_closing = false;
        for (const auto& lv : levels) any_closing = any_closing || lv.closing != nullptr;
        return finish(any_closing);
    }

    LevelInit init() const { return c_.header.init == 1 ? LevelInit::Noise : LevelInit::Parent; }

private:
    const Container& c_;
    const uint8_t* file_;
    std::size_t budget_start_, budget_;
    std::size_t used_ = 0;
};

struct DecodedFile {
    FileHeader header;
    std::vector<Section> sections;
    CodecModel model;
    int precision = 0, pixel_precision = 0;  // of level 0
    LevelInit init = LevelInit::Parent;
    // Of the memory limit, what the decoded trees may take (an upper bound):
    // the output must fit in the rest.
    std::size_t model_bytes = 0;
};

// Parses, verifies and rebuilds everything; throws a specific error for any
// damage. Nothing larger than `memory_limit` bytes is allocated.
DecodedFile decode_file(const uint8_t* data, std::size_t size, std::size_t memory_limit);

// The leaves of a tree given as each node's first child (-1 at a leaf), in
// depth-first order, first child first: the order both halves code the
// codewords and entries in.
std::vector<uint32_t> depth_first_leaves(const std::vector<int32_t>& first_child);

// Quantisation to `bits` and back, exactly invertible at 8 bits.
inline uint8_t quantise(uint8_t v, int bits) {
    const unsigned m = (1u << bits) - 1;
    return uint8_t((v * m + 127) / 255);
}
inline uint8_t dequantise(uint8_t q, int bits) {
    const unsigned m = (1u << bits) - 1;
    return uint8_t((q * 255u + m / 2) / m);
}

}  // namespace vqtex
