// model_writer.hpp - a trained texture model into the sections of a vqtex
// file (docs/FORMAT.md; paper section 6, "only the codebook would be
// transmitted"): per pyramid level the neighbourhood shape and the TSVQ
// codebooks (tree topology, leaf weights, quantised leaf codewords, leaf
// entries), plus the histograms that seed the noise. The writing
// half of format/model_codec.hpp, which reads them back.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/neighborhood.hpp"
#include "engine/noise.hpp"
#include "format/container.hpp"
#include "format/model_codec.hpp"
#include "format/tree_model.hpp"
#include "tsvq/tsvq_tree.hpp"
#include "writer/byte_writer.hpp"
#include "writer/container_writer.hpp"

namespace vqtex {

struct EncodeSettings {
    int precision = 5;        // bits per codeword and key sample, 1..8
    int pixel_precision = 8;  // bits per entry pixel, 1..8
    int smoothing = 1;        // codeword taps averaged in blocks of this size (encoder only)
    uint8_t backtrack = 1;
    LevelInit init = LevelInit::Parent;
    uint64_t seed = 1;
    int zstd_level = 19;
};

std::vector<uint8_t> encode_model(const CodecModel& model, const EncodeSettings& settings);

// One TSVQ tree as its TOPO, CODE and ENTR payloads (decode_tree reads them).
struct TreeSections {
    std::vector<uint8_t> topology, codewords, entries;
};
TreeSections encode_tree(const Codebook& book, const TreeLayout& layout, const EncodeSettings& settings);

// A tree of a level and kind as its three sections, encode_tree into the
// writer (LevelReader::tree reads it back).
void write_tree(ContainerWriter& writer, int level, TreeKind kind, const Codebook& book, const TreeLayout& layout,
                const EncodeSettings& settings);

// A HIST payload: 256 counts per channel, as varints (decode_histogram).
std::vector<uint8_t> encode_histogram(const LevelHistogram& h);

// The header both encoders start from: the model's sizes and the settings;
// the seam-closing flag when some level has a closing tree.
FileHeader model_header(int channels, uint32_t exemplar_width, uint32_t exemplar_height, int levels,
                        bool any_closing, const EncodeSettings& settings);

// The parts of a level both encoders write alike: the LEVL fields after the
// shape (LevelReader::read_coding reads them back) and the HIST section,
// which a file has at noise init and at its coarsest level.
void write_level_coding(ByteWriter& level, const EncodeSettings& settings, bool has_closing);
// A level's LEVL section: its window, its coding and, with a closing tree,
// the closing window; animated levels add the frames of each window (the
// writing side of LevelReader::level_shapes).
std::vector<uint8_t> level_section(const Shape& shape, const Shape* closing_shape, const EncodeSettings& settings,
                                   bool animated);
void write_histogram(ContainerWriter& writer, int level, int levels, const EncodeSettings& settings,
                     const LevelHistogram& histogram);

}  // namespace vqtex
