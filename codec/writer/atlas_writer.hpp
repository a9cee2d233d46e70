// atlas_writer.hpp - the atlas files the encoder writes, format version 8
// for one colour image and 9 for a set of maps (docs/FORMAT.md §2);
// format/atlas_file.hpp reads them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "format/atlas_file.hpp"
#include "format/container.hpp"

namespace vqtex {

// A version 8 file (what the encoder writes for one colour image): the exemplar size, channels,
// levels and seed of `header` (its other fields are not stored), the coded
// atlas and the parameters. The exemplar size is stored only when it is
// not the atlas's, the parameters only when they are not the defaults.
std::vector<uint8_t> encode_atlas_file(const FileHeader& header, int atlas_width, int atlas_height,
                                       const std::vector<uint8_t>& atlas_bitstream, const AtlasSynthesisParams& params);

// A coded map of a version 9 file.
struct CodedMap {
    std::string name;
    MapKind kind = MapKind::Colour;
    int channels = 0;
    int bits = 8;
    std::vector<uint8_t> bitstream;
};

// A version 9 file: the levels, exemplar size and seed of `header`, the
// maps and, for more than one, the guide's matrix (§4.15).
std::vector<uint8_t> encode_material_file(const FileHeader& header, int atlas_width, int atlas_height,
                                          const std::vector<CodedMap>& maps, const GuideMatrix& guide,
                                          const AtlasSynthesisParams& params);

}  // namespace vqtex
